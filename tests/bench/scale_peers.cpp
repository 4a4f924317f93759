// pm_bench_scale_peers: the peers of the memory and scale benchmark (issue 9's memory item,
// issue 10's whole-process tables; run_scale.sh, scale.md). One process per run, so that
// /usr/bin/time -v around it measures the peak memory of loading the OBJ and simplifying it
// to a fraction of its faces, and nothing else:
//
//   pm_bench_scale_peers meshopt  MESH.obj [--ratio 0.01]
//   pm_bench_scale_peers openmesh MESH.obj [--ratio 0.01]
//   pm_bench_scale_peers meshopt-seams MESH.obj [--ratio 0.01]
//
//   meshopt   a minimal OBJ reader (below) into one float and one uint32 array, then
//             meshopt_simplify (Garland and Heckbert 1997 quadrics, meshoptimizer's
//             simplifier) to ratio × faces, no error limit;
//   openmesh  OpenMesh::IO::read_mesh into a TriMesh_ArrayKernelT<>, then DecimaterT with
//             ModQuadricT (no error limit) and ModNormalFlippingT at 90 degrees (pmenc's own
//             rule), decimate_to_faces to ratio × faces, garbage_collection.
//   meshopt-seams  the textured peer (issue 25's whole-process benchmark): a minimal OBJ
//             reader of v, vt, vn and f a/t/n into the vertex buffer a renderer gets, one
//             vertex (position, uv, normal: 8 floats) per distinct a/t/n triple, so that UV
//             seams and creases are split as in meshopt_seams.h; meshopt_simplify on its
//             positions to ratio × faces, no error limit (meshoptimizer 0.18 holds the
//             split vertices' seams; its cost reads positions only).
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
#include <unordered_map>
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

// The first pass of both readers: opens path, counts its `v`, `vt` and `vn` lines into
// counts[0..2] and the triangles its `f` lines make (a polygon of n corners: n - 2), and
// returns the file back at its start.
FILE* open_counted_obj(const std::string& path, std::size_t counts[3], std::size_t& triangles) {
  FILE* file = std::fopen(path.c_str(), "r");
  if (!file) die("cannot open " + path);
  counts[0] = counts[1] = counts[2] = triangles = 0;
  char line[4096];
  while (std::fgets(line, sizeof line, file)) {
    if (line[0] == 'v' && line[1] == ' ') ++counts[0];
    if (line[0] == 'v' && line[1] == 't' && line[2] == ' ') ++counts[1];
    if (line[0] == 'v' && line[1] == 'n' && line[2] == ' ') ++counts[2];
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
  std::rewind(file);
  return file;
}

ObjMesh read_obj_minimal(const std::string& path) {
  std::size_t counts[3], triangles;
  FILE* file = open_counted_obj(path, counts, triangles);
  char line[4096];
  const std::size_t vertices = counts[0];
  ObjMesh mesh;
  mesh.positions.reserve(3 * vertices);
  mesh.indices.reserve(3 * triangles);
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

// The seam-split reader of meshopt-seams: a buffer of (x, y, z, u, v, nx, ny, nz) vertices,
// one per distinct v/vt/vn triple of the faces (missing parts 0), as a glTF exporter writes
// it. Two passes as above: counts first, then arrays at their size; the triples' map is the
// one structure that grows.
struct SplitMesh {
  std::vector<float> vertices;    // 8 floats per split vertex
  std::vector<uint32_t> indices;  // 3 per triangle
};

struct Corner {
  long v = 0, t = 0, n = 0;  // 1-based as in the file (0: absent), negatives resolved
};

bool parse_corner(const char*& p, const std::size_t counts[3], Corner& out) {
  while (*p == ' ' || *p == '\t') ++p;
  long* parts[3] = {&out.v, &out.t, &out.n};
  out = Corner{};
  for (int part = 0; part < 3; ++part) {
    char* end = nullptr;
    const long value = std::strtol(p, &end, 10);
    if (end != p) {
      const long index = value < 0 ? static_cast<long>(counts[part]) + value + 1 : value;
      if (index < 1 || static_cast<std::size_t>(index) > counts[part]) die("face index out of range");
      *parts[part] = index;
      p = end;
    } else if (part == 0) {
      return false;
    }
    if (*p != '/') break;
    ++p;
  }
  while (*p && *p != ' ' && *p != '\t' && *p != '\n' && *p != '\r') ++p;
  return true;
}

SplitMesh read_obj_split(const std::string& path) {
  std::size_t counts[3], triangles;
  FILE* file = open_counted_obj(path, counts, triangles);
  char line[4096];
  // The triple's key holds 21 bits of each index.
  for (std::size_t count : counts)
    if (count >= (std::size_t(1) << 21)) die("more than 2^21 - 1 v, vt or vn lines");
  std::vector<float> positions, uvs, normals;
  positions.reserve(3 * counts[0]);
  uvs.reserve(2 * counts[1]);
  normals.reserve(3 * counts[2]);
  SplitMesh mesh;
  mesh.indices.reserve(3 * triangles);
  std::unordered_map<uint64_t, uint32_t> split;  // (v, vt, vn) -> split vertex
  split.reserve(counts[0] + counts[1]);
  const std::size_t sizes[3] = {counts[0], counts[1], counts[2]};
  auto vertex_of = [&](const Corner& c) {
    const uint64_t key = (uint64_t(c.v) << 42) | (uint64_t(c.t) << 21) | uint64_t(c.n);
    const auto [it, inserted] = split.emplace(key, uint32_t(mesh.vertices.size() / 8));
    if (inserted) {
      float vertex[8] = {};
      for (int i = 0; i < 3; ++i) vertex[i] = positions[3 * (c.v - 1) + i];
      if (c.t)
        for (int i = 0; i < 2; ++i) vertex[3 + i] = uvs[2 * (c.t - 1) + i];
      if (c.n)
        for (int i = 0; i < 3; ++i) vertex[5 + i] = normals[3 * (c.n - 1) + i];
      mesh.vertices.insert(mesh.vertices.end(), vertex, vertex + 8);
    }
    return it->second;
  };
  while (std::fgets(line, sizeof line, file)) {
    float x = 0, y = 0, z = 0;
    if (line[0] == 'v' && line[1] == ' ') {
      if (std::sscanf(line + 2, "%f %f %f", &x, &y, &z) != 3) die("bad vertex line");
      positions.insert(positions.end(), {x, y, z});
    } else if (line[0] == 'v' && line[1] == 't' && line[2] == ' ') {
      if (std::sscanf(line + 3, "%f %f", &x, &y) != 2) die("bad vt line");
      uvs.insert(uvs.end(), {x, y});
    } else if (line[0] == 'v' && line[1] == 'n' && line[2] == ' ') {
      if (std::sscanf(line + 3, "%f %f %f", &x, &y, &z) != 3) die("bad vn line");
      normals.insert(normals.end(), {x, y, z});
    } else if (line[0] == 'f' && line[1] == ' ') {
      const char* p = line + 2;
      Corner first, previous, current;
      if (!parse_corner(p, sizes, first) || !parse_corner(p, sizes, previous)) continue;
      const uint32_t a = vertex_of(first);
      uint32_t b = vertex_of(previous);
      while (parse_corner(p, sizes, current)) {
        const uint32_t c = vertex_of(current);
        mesh.indices.insert(mesh.indices.end(), {a, b, c});
        b = c;
      }
    }
  }
  std::fclose(file);
  return mesh;
}

// meshopt_simplify of a read mesh to ratio × faces, timed, and the output line; `extra` goes
// after faces_out (" split_vertices=N").
void simplify_and_report(const std::vector<uint32_t>& indices, const float* vertices,
                         std::size_t vertex_count, std::size_t floats_per_vertex, double ratio,
                         double load_s, const std::string& extra) {
  const std::size_t faces = indices.size() / 3;
  const std::size_t target = static_cast<std::size_t>(ratio * static_cast<double>(faces) + 0.5);
  const auto start = Clock::now();
  // The destination holds index_count entries, the worst case meshopt's header asks for.
  std::vector<unsigned int> destination(indices.size());
  const std::size_t kept =
      meshopt_simplify(destination.data(), indices.data(), indices.size(), vertices, vertex_count,
                       floats_per_vertex * sizeof(float), 3 * target, FLT_MAX, 0, nullptr);
  const double simplify_s = seconds_since(start);
  std::printf("faces_in=%zu faces_out=%zu%s load_s=%.3f simplify_s=%.3f\n", faces, kept / 3,
              extra.c_str(), load_s, simplify_s);
}

void run_meshopt_seams(const std::string& path, double ratio) {
  const auto start = Clock::now();
  const SplitMesh mesh = read_obj_split(path);
  const double load_s = seconds_since(start);
  const std::size_t count = mesh.vertices.size() / 8;
  simplify_and_report(mesh.indices, mesh.vertices.data(), count, 8, ratio, load_s,
                      " split_vertices=" + std::to_string(count));
}

void run_meshopt(const std::string& path, double ratio) {
  const auto start = Clock::now();
  const ObjMesh mesh = read_obj_minimal(path);
  const double load_s = seconds_since(start);
  simplify_and_report(mesh.indices, mesh.positions.data(), mesh.positions.size() / 3, 3, ratio,
                      load_s, "");
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
    std::fprintf(stderr, "usage: pm_bench_scale_peers meshopt|meshopt-seams|openmesh MESH.obj [--ratio R]\n");
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
  } else if (peer == "meshopt-seams") {
    run_meshopt_seams(path, ratio);
  } else if (peer == "openmesh") {
    run_openmesh(path, ratio);
  } else {
    std::fprintf(stderr, "pm_bench_scale_peers: unknown peer %s\n", peer.c_str());
    return 2;
  }
  return 0;
}
