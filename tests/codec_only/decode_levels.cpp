// Decodes a .pm file with pm::codec alone: full detail through the runtime and
// through extract_level, and checks that their faces agree. Prints "FACES VERTICES SPLITS".
#include <pm/lod.h>
#include <pm/lod_runtime.h>
#include <pm/pm_codec.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: decode_levels FILE.pm\n");
    return 2;
  }
  std::ifstream in(argv[1], std::ios::binary);
  const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  pm::ProgressiveMesh progressive;
  if (pm::Status status = pm::read_pm(bytes, progressive); !status) {
    std::fprintf(stderr, "%s: %s\n", argv[1], status.message().c_str());
    return 1;
  }
  const pm::Mesh full = pm::extract_level(progressive, progressive.split_count());
  pm::RuntimeLod runtime(progressive);
  runtime.set_level(progressive.split_count());
  const pm::Mesh from_runtime = runtime.to_mesh();
  // The runtime's mesh has a vertex per wedge, extract_level's a vertex per vertex: their
  // faces agree corner by corner.
  bool same = from_runtime.triangles.size() == full.triangles.size();
  for (std::size_t corner = 0; same && corner < full.triangles.size(); ++corner)
    for (int axis = 0; axis < 3; ++axis)
      same = same && from_runtime.positions[3 * from_runtime.triangles[corner] + axis] ==
                         full.positions[3 * full.triangles[corner] + axis];
  if (!same) {
    std::fprintf(stderr, "%s: the runtime's full detail (%zu faces) differs from extract_level's (%zu)\n", argv[1], from_runtime.face_count(), full.face_count());
    return 1;
  }
  std::printf("%zu %zu %zu\n", full.face_count(), full.vertex_count(), progressive.split_count());
  return 0;
}
