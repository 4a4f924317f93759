// The runtime API in a render loop (README, "Levels of detail at run time"). A camera flies
// away from a mesh; each frame picks a face budget from the distance, and a change of level
// is blended over a few frames with a geomorph (Hoppe 1996, §4.2) instead of popping. The
// "GPU" here is two plain arrays; a real renderer uploads the same arrays.
//
// Usage: render_loop [FILE.pm]   (without a file: a sphere made here)
#include <pm/encoder.h>
#include <pm/lod_runtime.h>
#include <pm/pm_codec.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

pm::Mesh sphere(int rings) {  // a UV sphere, closed
  pm::Mesh m;
  const int segments = 2 * rings;
  m.positions.insert(m.positions.end(), {0, 0, 1});
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const float theta = float(M_PI) * r / rings, phi = 2 * float(M_PI) * s / segments;
      m.positions.insert(m.positions.end(), {std::sin(theta) * std::cos(phi),
                                             std::sin(theta) * std::sin(phi), std::cos(theta)});
    }
  m.positions.insert(m.positions.end(), {0, 0, -1});
  const uint32_t south = static_cast<uint32_t>(m.vertex_count() - 1);
  auto ring = [&](int r, int s) { return uint32_t(1 + (r - 1) * segments + (s % segments)); };
  for (int s = 0; s < segments; ++s) {
    m.triangles.insert(m.triangles.end(), {0, ring(1, s), ring(1, s + 1)});
    m.triangles.insert(m.triangles.end(), {south, ring(rings - 1, s + 1), ring(rings - 1, s)});
    for (int r = 1; r + 1 < rings; ++r) {
      m.triangles.insert(m.triangles.end(), {ring(r, s), ring(r + 1, s), ring(r + 1, s + 1)});
      m.triangles.insert(m.triangles.end(), {ring(r, s), ring(r + 1, s + 1), ring(r, s + 1)});
    }
  }
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  pm::ProgressiveMesh progressive;
  if (argc > 1) {
    std::ifstream in(argv[1], std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (pm::Status s = pm::read_pm(bytes, progressive); !s) {
      std::fprintf(stderr, "render_loop: %s: %s\n", argv[1], s.message().c_str());
      return 1;
    }
  } else if (!pm::encode(sphere(40), {}, progressive)) {
    return 1;
  }

  pm::RuntimeLod lod(progressive);  // starts at the base mesh
  lod.set_level(lod.max_level());
  const std::size_t full_faces = lod.face_count();

  std::vector<float> gpu_positions;  // what a renderer would upload, per wedge
  std::vector<uint32_t> gpu_indices;
  pm::RuntimeLod::Geomorph morph = lod.geomorph(lod.level(), lod.level());
  int morph_frame = 0;
  constexpr int kMorphFrames = 8;
  std::size_t changes = 0, drawn = 0;

  for (int frame = 0; frame < 240; ++frame) {
    // The budget falls with the square of the distance, as the projected area does.
    const double distance = 1.0 + frame / 24.0;
    const auto budget = static_cast<std::size_t>(full_faces / (distance * distance));
    const std::size_t from = lod.level();
    lod.set_face_count(budget);  // applies only the splits or collapses between the levels
    if (lod.level() != from) {
      ++changes;
      // Refining: morph the new vertices out of their ancestors. Coarsening: the collapses
      // are applied at once (a renderer could morph from the coarse level backwards).
      if (lod.level() > from) {
        morph = lod.geomorph(from, lod.level());
        morph_frame = 1;
      } else {
        morph = lod.geomorph(lod.level(), lod.level());
        morph_frame = kMorphFrames;
      }
    }
    // Draw: the active faces are a prefix of the index buffer; the wedges below
    // wedge_count() are all the vertices they use.
    gpu_positions.resize(3 * morph.wedge_count());
    const float alpha = std::min(1.0f, float(morph_frame) / kMorphFrames);
    morph.evaluate(alpha, gpu_positions.data(), nullptr, nullptr);
    if (morph_frame < kMorphFrames) ++morph_frame;
    gpu_indices.assign(morph.indices(), morph.indices() + 3 * morph.face_count());
    drawn += morph.face_count();
  }
  std::printf("%zu LOD changes over 240 frames, %zu faces drawn, %zu faces at the end of %zu\n",
              changes, drawn, lod.face_count(), full_faces);
  return changes > 0 && lod.face_count() < full_faces ? 0 : 1;
}
