// See progressive_setups.h.
#include "progressive_setups.h"

#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModProgMeshT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#include <algorithm>
#include <chrono>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "bench_report.h"
#include "big_mesh.h"
#include "pm/encoder.h"
#include "pm/pm_codec.h"

namespace pm::bench {

namespace {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}
}  // namespace

void fail(const std::string& message) {
  std::fprintf(stderr, "%s: %s\n", program_invocation_short_name, message.c_str());
  std::exit(1);
}

std::string mesh_key(const pm::Mesh& mesh) {
  std::string bytes(reinterpret_cast<const char*>(mesh.positions.data()),
                    mesh.positions.size() * sizeof(float));
  bytes.append(reinterpret_cast<const char*>(mesh.triangles.data()),
               mesh.triangles.size() * sizeof(uint32_t));
  return std::to_string(mesh.face_count()) + "-" + pm::bench::hex64(pm::bench::fnv1a64(bytes));
}

std::string library_key() {
  const std::string repo = pm::bench::shell_quoted(PM_BENCH_SOURCE_DIR);
  std::string key =
      pm::bench::command_output("git -C " + repo + " rev-parse --short=12 HEAD:lib 2>/dev/null");
  if (key.empty()) return "nogit";
  const std::string diff =
      pm::bench::command_output("git -C " + repo + " diff HEAD -- lib 2>/dev/null");
  if (!diff.empty()) key += "-dirty" + pm::bench::hex64(pm::bench::fnv1a64(diff)).substr(0, 8);
  return key;
}

// --- Ours: the .pm, encoded once --------------------------------------------------------

pm::ProgressiveMesh our_progressive_mesh(const pm::Mesh& mesh, const std::string& name,
                                         const std::string& cache, OurSetup& setup) {
  pm::ProgressiveMesh pm;
  setup.path = cache + "/" + name + "-" + mesh_key(mesh) + "-lib" + library_key() + ".pm";
  std::string bytes;
  if (read_file(setup.path, bytes) && pm::read_pm(bytes, pm)) {
    std::fprintf(stderr, "ours: %s (cached)\n", setup.path.c_str());
    return pm;
  }
  // Default options, as pmenc encodes: the runtime object serves what pmenc writes.
  pm::EncodeOptions options;
  int shown = -1;
  const auto start = Clock::now();
  options.progress = [&](double done) {
    const int percent = static_cast<int>(done * 100);
    if (percent / 5 == shown) return;
    shown = percent / 5;
    std::fprintf(stderr, "ours: encoding %3d%% (%.0f s)\n", percent, seconds_since(start));
  };
  std::fprintf(stderr, "ours: pm::encode of %zu faces (a minute or two)\n", mesh.face_count());
  if (pm::Status s = pm::encode(mesh, options, pm); !s) fail("encode: " + s.message());
  setup.encode_seconds = seconds_since(start);
  std::fprintf(stderr, "ours: encoded in %.1f s\n", setup.encode_seconds);
  // A cache, not a deliverable: a fast zstd level.
  pm::WriteOptions write_options;
  write_options.zstd_level = 3;
  std::error_code error;
  fs::create_directories(cache, error);
  if (pm::Status s = pm::write_pm(pm, write_options, bytes);
      !s || !write_file_atomically(setup.path, bytes)) {
    std::fprintf(stderr, "warning: cannot cache %s\n", setup.path.c_str());
    return pm;
  }
  // The same input encoded by an earlier library: never read again, so removed.
  const std::string earlier = name + "-" + mesh_key(mesh) + "-lib";
  for (const auto& entry : fs::directory_iterator(cache, error)) {
    const std::string file = entry.path().filename().string();
    if (file.rfind(earlier, 0) == 0 && entry.path().extension() == ".pm" &&
        entry.path() != setup.path)
      fs::remove(entry.path(), error);
  }
  return pm;
}

// --- OpenMesh: its .pm (ModProgMeshT) and ProgViewer's replay --------------------------

bool parse_openmesh_pm(const std::string& bytes, OpenMeshPm& pm, std::string& problem) {
  std::size_t at = 0;
  auto take = [&](void* to, std::size_t n) {
    if (bytes.size() - at < n) return false;
    std::memcpy(to, bytes.data() + at, n);
    at += n;
    return true;
  };
  char magic[8];
  uint32_t counts[3];
  if (!take(magic, 8) || std::memcmp(magic, "ProgMesh", 8) != 0 || !take(counts, sizeof counts)) {
    problem = "not a ProgMesh file";
    return false;
  }
  const std::size_t needed = 12ull * counts[0] + 12ull * counts[1] + 24ull * counts[2];
  if (bytes.size() - at != needed) {
    problem = "size does not match the counts";
    return false;
  }
  pm.base_points.resize(counts[0]);
  for (auto& p : pm.base_points) {
    float xyz[3];
    take(xyz, sizeof xyz);
    p = OMesh::Point(xyz[0], xyz[1], xyz[2]);
  }
  pm.base_faces.resize(3ull * counts[1]);
  take(pm.base_faces.data(), 4 * pm.base_faces.size());
  for (uint32_t v : pm.base_faces)
    if (v >= counts[0]) {
      problem = "base face index out of range";
      return false;
    }
  pm.records.resize(counts[2]);
  pm.faces_at.assign(1, counts[1]);
  // Checked here so that the timed replay cannot be handed an index OpenMesh would trip on.
  for (std::size_t i = 0; i < pm.records.size(); ++i) {
    float xyz[3];
    uint32_t v[3];
    take(xyz, sizeof xyz);
    take(v, sizeof v);
    const uint32_t existing = counts[0] + static_cast<uint32_t>(i);
    if (v[0] >= existing || (v[1] != ~0u && v[1] >= existing) ||
        (v[2] != ~0u && v[2] >= existing)) {
      problem = "record " + std::to_string(i) + " refers to a vertex not yet made";
      return false;
    }
    pm.records[i] = {OMesh::Point(xyz[0], xyz[1], xyz[2]), static_cast<int>(v[0]),
                     v[1] == ~0u ? -1 : static_cast<int>(v[1]),
                     v[2] == ~0u ? -1 : static_cast<int>(v[2])};
    pm.faces_at.push_back(pm.faces_at.back() + (v[1] != ~0u) + (v[2] != ~0u));
  }
  return true;
}

OMesh to_openmesh(const pm::Mesh& mesh) {
  OMesh result;
  std::vector<OMesh::VertexHandle> handles(mesh.vertex_count());
  auto point = [&](uint32_t v) {
    return OMesh::Point(mesh.positions[3 * v], mesh.positions[3 * v + 1],
                        mesh.positions[3 * v + 2]);
  };
  for (uint32_t v = 0; v < mesh.vertex_count(); ++v) handles[v] = result.add_vertex(point(v));
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const uint32_t* c = &mesh.triangles[3 * f];
    if (!result.add_face(handles[c[0]], handles[c[1]], handles[c[2]]).is_valid())
      result.add_face(result.add_vertex(point(c[0])), result.add_vertex(point(c[1])),
                      result.add_vertex(point(c[2])));
  }
  return result;
}

OpenMeshPm openmesh_progressive_mesh(const pm::Mesh& mesh, const std::string& name,
                                     const std::string& cache, OpenMeshSetup& setup) {
  setup.path = cache + "/" + name + "-" + mesh_key(mesh) + ".openmesh.pm";
  OpenMeshPm pm;
  std::string bytes, problem;
  if (read_file(setup.path, bytes) && parse_openmesh_pm(bytes, pm, problem)) {
    std::fprintf(stderr, "OpenMesh: %s (cached)\n", setup.path.c_str());
    return pm;
  }
  std::fprintf(stderr, "OpenMesh: decimating %zu faces with ModProgMeshT (a minute or two)\n",
               mesh.face_count());
  OMesh om = to_openmesh(mesh);
  om.request_face_normals();
  om.update_face_normals();
  const auto start = Clock::now();
  std::error_code error;
  fs::create_directories(cache, error);
  const std::string temporary = setup.path + ".tmp";
  {
    OpenMesh::Decimater::DecimaterT<OMesh> decimater(om);
    OpenMesh::Decimater::ModQuadricT<OMesh>::Handle quadric;
    OpenMesh::Decimater::ModNormalFlippingT<OMesh>::Handle normal_flipping;
    OpenMesh::Decimater::ModProgMeshT<OMesh>::Handle progressive;
    decimater.add(quadric);
    decimater.module(quadric).unset_max_err();  // the priority, no error limit
    decimater.add(normal_flipping);
    decimater.module(normal_flipping).set_max_normal_deviation(90.0);
    decimater.add(progressive);
    if (!decimater.initialize()) fail("OpenMesh's decimater did not initialize");
    decimater.decimate(0);
    setup.decimate_seconds = seconds_since(start);
    // Before the garbage collection (there is none here), as ModProgMeshT asks.
    if (!decimater.module(progressive).write(temporary)) fail("cannot write " + temporary);
  }
  fs::rename(temporary, setup.path, error);
  std::fprintf(stderr, "OpenMesh: decimated in %.1f s\n", setup.decimate_seconds);
  if (error || !read_file(setup.path, bytes) || !parse_openmesh_pm(bytes, pm, problem))
    fail("cannot read back OpenMesh's .pm " + setup.path + ": " + problem);
  return pm;
}

void load_base(const OpenMeshPm& pm, OMesh& mesh) {
  const std::size_t v = pm.full_vertices(), f = pm.full_faces();
  mesh.reserve(v, v + f + 16, f);  // Euler: E = V + F - 2 + 2g, and boundaries
  for (const auto& p : pm.base_points) mesh.add_vertex(p);
  for (std::size_t i = 0; i < pm.base_faces.size(); i += 3)
    if (!mesh.add_face(OMesh::VertexHandle(int(pm.base_faces[i])),
                       OMesh::VertexHandle(int(pm.base_faces[i + 1])),
                       OMesh::VertexHandle(int(pm.base_faces[i + 2])))
             .is_valid())
      fail("OpenMesh refuses a face of its own base mesh");
}

}  // namespace pm::bench
