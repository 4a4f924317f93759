// pm_bench_scale_peers: the peers of the memory and scale benchmark (issue 9's memory item,
// issue 10's whole-process tables; run_scale.sh, scale.md). One process per run, so that
// /usr/bin/time -v around it measures the peak memory of loading the OBJ and simplifying it
// to a fraction of its faces, and nothing else:
//
//   pm_bench_scale_peers meshopt  MESH.obj [--ratio 0.01]
//   pm_bench_scale_peers openmesh MESH.obj [--ratio 0.01]
//
//   meshopt   a minimal OBJ reader (below) into one float and one uint32 array, then
//             meshopt_simplify (Garland and Heckbert 1997 quadrics, meshoptimizer's
//             simplifier) to ratio × faces, no error limit;
//   openmesh  OpenMesh::IO::read_mesh into a TriMesh_ArrayKernelT<>, then DecimaterT with
//             ModQuadricT (no error limit) and ModNormalFlippingT at 90 degrees (pmenc's own
//             rule), decimate_to_faces to ratio × faces, garbage_collection.
//
// Prints one line on stdout, `faces_in=N faces_out=M load_s=A simplify_s=B`; errors on
// stderr with exit code 1.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#include <cfloat>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "meshoptimizer.h"

namespace {

using Clock = std::chrono::steady_clock;
using OMesh = OpenMesh::TriMesh_ArrayKernelT<>;

[[noreturn]] void die(const std::string& message) {
  std::fprintf(stderr, "pm_bench_scale_peers: %s\n", message.c_str());
  std::exit(1);
}

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The minimal OBJ reader meshopt is given: `v x y z` and `f a b c ...` lines (a polygon as a
// fan; `a/t/n` reads a; negative indices count back), everything else skipped. Two passes
// over the file, the first counting, so that the arrays are allocated once at their size:
// the peak is then the data meshopt needs, not a growing vector's spare capacity. The
// meshes here are written by pm's OBJ writer, which this covers.
struct ObjMesh {
  std::vector<float> positions;    // x, y, z per vertex
  std::vector<uint32_t> indices;   // 3 per triangle
};

bool parse_index(const char*& p, std::size_t vertex_count, uint32_t& out) {
  while (*p == ' ' || *p == '\t') ++p;
  char* end = nullptr;
  const long value = std::strtol(p, &end, 10);
  if (end == p) return false;
  p = end;
  while (*p && *p != ' ' && *p != '\t' && *p != '\n' && *p != '\r') ++p;  // skip /t/n
  const long index = value < 0 ? static_cast<long>(vertex_count) + value : value - 1;
  if (index < 0 || static_cast<std::size_t>(index) >= vertex_count) die("face index out of range");
  out = static_cast<uint32_t>(index);
  return true;
}

ObjMesh read_obj_minimal(const std::string& path) {
  FILE* file = std::fopen(path.c_str(), "r");
  if (!file) die("cannot open " + path);
  char line[4096];
  std::size_t vertices = 0, triangles = 0;
  while (std::fgets(line, sizeof line, file)) {
    if (line[0] == 'v' && line[1] == ' ') ++vertices;
    if (line[0] == 'f' && line[1] == ' ') {
      int corners = 0;
      for (const char* p = line + 1; *p;) {
        while (*p == ' ' || *p == '\t') ++p;
        if (!*p || *p == '\n' || *p == '\r') break;
        ++corners;
        while (*p && *p != ' ' && *p != '\t') ++p;
      }
      if (corners >= 3) triangles += corners - 2;
    }
  }
  ObjMesh mesh;
  mesh.positions.reserve(3 * vertices);
  mesh.indices.reserve(3 * triangles);
  std::rewind(file);
  while (std::fgets(line, sizeof line, file)) {
    if (line[0] == 'v' && line[1] == ' ') {
      float x = 0, y = 0, z = 0;
      if (std::sscanf(line + 2, "%f %f %f", &x, &y, &z) != 3) die("bad vertex line");
      mesh.positions.insert(mesh.positions.end(), {x, y, z});
    } else if (line[0] == 'f' && line[1] == ' ') {
      const char* p = line + 2;
      const std::size_t count = mesh.positions.size() / 3;
      uint32_t first = 0, previous = 0, current = 0;
      if (!parse_index(p, count, first) || !parse_index(p, count, previous)) continue;
      while (parse_index(p, count, current)) {
        mesh.indices.insert(mesh.indices.end(), {first, previous, current});
        previous = current;
      }
    }
  }
  std::fclose(file);
  return mesh;
}

void run_meshopt(const std::string& path, double ratio) {
  auto start = Clock::now();
  const ObjMesh mesh = read_obj_minimal(path);
  const double load_s = seconds_since(start);
  const std::size_t faces = mesh.indices.size() / 3;
  const std::size_t target = static_cast<std::size_t>(ratio * static_cast<double>(faces) + 0.5);
  start = Clock::now();
  // The destination holds index_count entries, the worst case meshopt's header asks for.
  std::vector<unsigned int> destination(mesh.indices.size());
  const std::size_t kept = meshopt_simplify(destination.data(), mesh.indices.data(),
                                            mesh.indices.size(), mesh.positions.data(),
                                            mesh.positions.size() / 3, 3 * sizeof(float),
                                            3 * target, FLT_MAX, 0, nullptr);
  const double simplify_s = seconds_since(start);
  std::printf("faces_in=%zu faces_out=%zu load_s=%.3f simplify_s=%.3f\n", faces, kept / 3, load_s,
              simplify_s);
}

void run_openmesh(const std::string& path, double ratio) {
  auto start = Clock::now();
  OMesh mesh;
  if (!OpenMesh::IO::read_mesh(mesh, path)) die("OpenMesh cannot read " + path);
  const double load_s = seconds_since(start);
  const std::size_t faces = mesh.n_faces();
  const std::size_t target = static_cast<std::size_t>(ratio * static_cast<double>(faces) + 0.5);
  start = Clock::now();
  // ModNormalFlippingT compares face normals before and after each collapse.
  mesh.request_face_normals();
  mesh.update_face_normals();
  {
    OpenMesh::Decimater::DecimaterT<OMesh> decimater(mesh);
    OpenMesh::Decimater::ModQuadricT<OMesh>::Handle quadric;
    decimater.add(quadric);
    decimater.module(quadric).unset_max_err();  // the priority only, no error limit
    OpenMesh::Decimater::ModNormalFlippingT<OMesh>::Handle normal_flipping;
    decimater.add(normal_flipping);
    decimater.module(normal_flipping).set_max_normal_deviation(90.0);
    if (!decimater.initialize()) die("OpenMesh's decimater did not initialize");
    decimater.decimate_to_faces(0, target);
    // Before the decimater goes: it releases the status bits garbage_collection reads.
    mesh.garbage_collection();
  }
  const double simplify_s = seconds_since(start);
  std::printf("faces_in=%zu faces_out=%zu load_s=%.3f simplify_s=%.3f\n", faces, mesh.n_faces(),
              load_s, simplify_s);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: pm_bench_scale_peers meshopt|openmesh MESH.obj [--ratio R]\n");
    return 2;
  }
  const std::string peer = argv[1], path = argv[2];
  double ratio = 0.01;
  for (int i = 3; i < argc; ++i) {
    if (std::strcmp(argv[i], "--ratio") == 0 && i + 1 < argc) {
      ratio = std::atof(argv[++i]);
    } else {
      std::fprintf(stderr, "pm_bench_scale_peers: unknown argument %s\n", argv[i]);
      return 2;
    }
  }
  if (!(ratio > 0 && ratio <= 1)) die("--ratio must be in (0, 1]");
  if (peer == "meshopt") {
    run_meshopt(path, ratio);
  } else if (peer == "openmesh") {
    run_openmesh(path, ratio);
  } else {
    std::fprintf(stderr, "pm_bench_scale_peers: unknown peer %s\n", peer.c_str());
    return 2;
  }
  return 0;
}
