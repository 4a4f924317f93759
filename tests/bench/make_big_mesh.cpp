// pm_make_big_mesh: a large input for benchmark scripts (issue 10's whole-process run), a
// shared mesh after some steps of Loop subdivision (big_mesh.h).
//
//   pm_make_big_mesh MESH STEPS OUT [--no-cache] [--cache DIR] [--keep-attributes] [-q]
//
// MESH is a mesh file, or the name of one in ../shared/meshes (stanford-bunny.obj). Each
// step multiplies the faces by 4: `pm_make_big_mesh stanford-bunny.obj 2 bunny1m.obj` makes
// the ~1M-face mesh (1,111,216 faces). OUT's extension picks the format (.obj, .ply, .off,
// .stl), written by pm's own writers. The subdivided mesh is cached as in load_subdivided().
//
// --keep-attributes subdivides with texture coordinates, normals, colours and materials, their
// seams kept (loop_subdivide_keeping_attributes(), no cache: it takes under a second): issue
// 25's textured mesh, `pm_make_big_mesh samples/textured.obj 4 textured-loop4.obj
// --keep-attributes` (950,272 faces).
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "big_mesh.h"
#include "pm/mesh_io.h"

namespace {

// On stderr for a bad command line (exit code 2), on stdout for --help.
int usage(FILE* to = stderr) {
  std::fprintf(to,
               "usage: pm_make_big_mesh MESH STEPS OUT [--no-cache] [--cache DIR] "
               "[--keep-attributes] [-q]\n"
               "  MESH   a mesh file, or a name in %s\n"
               "  STEPS  Loop subdivision steps, 0 to 5 (each multiplies the faces by 4)\n"
               "  OUT    .obj, .ply, .off or .stl\n"
               "  --keep-attributes  texture coordinates, normals, colours and materials too\n",
               pm::bench::shared_meshes_dir().c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string positional[3];
  int count = 0;
  std::string cache = pm::bench::default_cache_dir();
  bool quiet = false, keep_attributes = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--no-cache")
      cache.clear();
    else if (arg == "--cache" && i + 1 < argc)
      cache = argv[++i];
    else if (arg == "--keep-attributes")
      keep_attributes = true;
    else if (arg == "-q")
      quiet = true;
    else if (arg == "-h" || arg == "--help")
      return usage(stdout), 0;
    else if (count < 3 && (arg.empty() || arg[0] != '-'))
      positional[count++] = arg;
    else
      return usage();
  }
  if (count != 3) return usage();
  std::string input = positional[0];
  if (!std::filesystem::exists(input) &&
      std::filesystem::exists(pm::bench::shared_meshes_dir() + "/" + input))
    input = pm::bench::shared_meshes_dir() + "/" + input;
  char* end = nullptr;
  const long steps = std::strtol(positional[1].c_str(), &end, 10);
  // 5 steps of a 100k-face mesh are 100M faces: beyond that no shared mesh fits in memory.
  if (*end != '\0' || steps < 0 || steps > 5) return usage();
  const std::string& output = positional[2];
  const pm::MeshFormat format = pm::mesh_format_from_path(output);
  if (format == pm::MeshFormat::kUnknown) {
    std::fprintf(stderr, "pm_make_big_mesh: %s: unknown format (.obj, .ply, .off, .stl)\n",
                 output.c_str());
    return 2;
  }

  pm::Mesh mesh;
  if (pm::Status s = keep_attributes ? pm::read_mesh(input, mesh)
                                     : pm::bench::load_subdivided(input, static_cast<int>(steps),
                                                                  cache, mesh, quiet);
      !s) {
    std::fprintf(stderr, "pm_make_big_mesh: %s: %s\n", input.c_str(), s.message().c_str());
    return 3;
  }
  if (keep_attributes) mesh = pm::bench::loop_subdivide_keeping_attributes(mesh, int(steps));
  std::string bytes;
  if (pm::Status s = pm::write_mesh_to_memory(mesh, format, bytes); !s) {
    std::fprintf(stderr, "pm_make_big_mesh: %s: %s\n", output.c_str(), s.message().c_str());
    return 5;
  }
  // A temporary beside OUT, renamed: a script never sees a partial mesh.
  const std::string temporary = output + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!out) {
      std::fprintf(stderr, "pm_make_big_mesh: cannot write %s\n", output.c_str());
      std::remove(temporary.c_str());
      return 5;
    }
  }
  std::error_code error;
  std::filesystem::rename(temporary, output, error);
  if (error) {
    std::fprintf(stderr, "pm_make_big_mesh: cannot write %s: %s\n", output.c_str(),
                 error.message().c_str());
    std::remove(temporary.c_str());
    return 5;
  }
  if (!quiet)
    std::fprintf(stderr, "%s: %zu faces, %zu vertices\n", output.c_str(), mesh.face_count(),
                 mesh.vertex_count());
  return 0;
}
