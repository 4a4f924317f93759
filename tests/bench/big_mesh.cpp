// Large meshes by Loop subdivision (Loop 1987, "Smooth subdivision surfaces based on
// triangles", M.S. thesis, University of Utah), through OpenMesh's
// Subdivider::Uniform::LoopT; see big_mesh.h.
#include "big_mesh.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

#include "pm/mesh_io.h"

namespace pm::bench {
namespace {

namespace fs = std::filesystem;
using OpenMeshTriMesh = OpenMesh::TriMesh_ArrayKernelT<>;

// Referenced vertices only (LoopT leaves a vertex without faces at an undefined position),
// and faces the half-edge mesh refuses on their own copies of their vertices, counted.
OpenMeshTriMesh to_openmesh(const Mesh& mesh, std::size_t& refused) {
  OpenMeshTriMesh result;
  result.reserve(mesh.vertex_count(), mesh.triangles.size(), mesh.face_count());
  const OpenMeshTriMesh::VertexHandle none;
  std::vector<OpenMeshTriMesh::VertexHandle> handles(mesh.vertex_count(), none);
  auto point = [&](uint32_t v) {
    return OpenMeshTriMesh::Point(mesh.positions[3 * v], mesh.positions[3 * v + 1],
                                  mesh.positions[3 * v + 2]);
  };
  for (uint32_t v : mesh.triangles)
    if (!handles[v].is_valid()) handles[v] = result.add_vertex(point(v));
  // OpenMesh prints a line per refused face on its error stream; they are handled here.
  const bool errors_shown = omerr().is_enabled();
  omerr().disable();
  refused = 0;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const uint32_t* corners = &mesh.triangles[3 * f];
    if (result.add_face(handles[corners[0]], handles[corners[1]], handles[corners[2]]).is_valid())
      continue;
    ++refused;
    result.add_face(result.add_vertex(point(corners[0])), result.add_vertex(point(corners[1])),
                    result.add_vertex(point(corners[2])));
  }
  if (errors_shown) omerr().enable();
  return result;
}

Mesh from_openmesh(const OpenMeshTriMesh& mesh) {
  Mesh result;
  result.positions.reserve(3 * mesh.n_vertices());
  for (const auto vertex : mesh.vertices()) {
    const auto& p = mesh.point(vertex);
    result.positions.insert(result.positions.end(), {p[0], p[1], p[2]});
  }
  result.triangles.reserve(3 * mesh.n_faces());
  for (const auto face : mesh.faces())
    for (const auto vertex : face.vertices())
      result.triangles.push_back(static_cast<uint32_t>(vertex.idx()));
  return result;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

bool read_file(const std::string& path, std::string& bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return !in.bad();
}

// Written beside the final name and renamed, so that a killed run leaves no partial cache.
bool write_file_atomically(const std::string& path, const std::string& bytes) {
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!out) return false;
  }
  std::error_code error;
  fs::rename(temporary, path, error);
  return !error;
}

Mesh loop_subdivide(const Mesh& mesh, int times, std::size_t* refused_faces) {
  std::size_t refused = 0;
  OpenMeshTriMesh om = to_openmesh(mesh, refused);
  if (refused_faces) *refused_faces = refused;
  if (times > 0) {
    OpenMesh::Subdivider::Uniform::LoopT<OpenMeshTriMesh> loop;
    // LoopT's weight table covers valences below 50 by default and indexes past it for a
    // vertex of higher valence (a fan in a scan): size it for this mesh. Subdivision adds
    // vertices of valence 6 (4 on a boundary) and keeps the old valences.
    std::size_t max_valence = 0;
    for (const auto vertex : om.vertices())
      max_valence = std::max<std::size_t>(max_valence, om.valence(vertex));
    loop.init_weights(max_valence + 1);
    loop.attach(om);
    loop(static_cast<std::size_t>(times));
    loop.detach();
  }
  return from_openmesh(om);
}

std::string shared_meshes_dir() {
  return std::string(PM_BENCH_SOURCE_DIR) + "/../shared/meshes";
}

std::string default_cache_dir() {
  return PM_BENCH_CACHE_DIR;
}

uint64_t fnv1a64(const std::string& bytes) {
  uint64_t hash = 0xcbf29ce484222325ull;
  for (unsigned char c : bytes) hash = (hash ^ c) * 0x100000001b3ull;
  return hash;
}

std::string hex64(uint64_t value) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
  return text;
}

Status load_subdivided(const std::string& path, int times, const std::string& cache_dir, Mesh& out,
                       bool quiet) {
  std::string source;
  if (!read_file(path, source)) return Status(ErrorCode::kIoError, "cannot read " + path);
  const std::string stem = fs::path(path).stem().string();
  std::string cached;
  if (!cache_dir.empty()) {
    cached = cache_dir + "/" + stem + "-loop" + std::to_string(times) + "-" +
             std::to_string(source.size()) + "-" + hex64(fnv1a64(source)) + ".ply";
    // A cache that does not read back (cut short, an older writer) is simply remade.
    std::string bytes;
    if (read_file(cached, bytes) && read_mesh_from_memory(bytes, MeshFormat::kPly, out)) {
      if (!quiet)
        std::fprintf(stderr, "%s x%d: %zu faces, from %s\n", stem.c_str(), 1 << (2 * times),
                     out.face_count(), cached.c_str());
      return Status::ok();
    }
  }
  Mesh input;
  if (Status s = read_mesh_from_memory(source, mesh_format_from_path(path), input); !s) return s;
  const auto start = std::chrono::steady_clock::now();
  if (!quiet)
    std::fprintf(stderr, "%s: %zu faces, Loop subdivision x%d ...\n", stem.c_str(),
                 input.face_count(), 1 << (2 * times));
  std::size_t refused = 0;
  out = loop_subdivide(input, times, &refused);
  if (!quiet && refused)
    std::fprintf(stderr, "%s: %zu faces at complex edges or vertices subdivided on their own\n",
                 stem.c_str(), refused);
  if (!quiet)
    std::fprintf(stderr, "%s x%d: %zu faces in %.1f s\n", stem.c_str(), 1 << (2 * times),
                 out.face_count(), seconds_since(start));
  if (!cached.empty()) {
    std::string bytes;
    std::error_code error;
    fs::create_directories(cache_dir, error);
    if (Status s = write_mesh_to_memory(out, MeshFormat::kPly, bytes);
        !s || !write_file_atomically(cached, bytes))
      std::fprintf(stderr, "warning: cannot cache %s (subdivided again next time)\n",
                   cached.c_str());
  }
  return Status::ok();
}

}  // namespace pm::bench
