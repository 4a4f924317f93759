// Large meshes by Loop subdivision (Loop 1987, "Smooth subdivision surfaces based on
// triangles", M.S. thesis, University of Utah), through OpenMesh's
// Subdivider::Uniform::LoopT; see big_mesh.h.
#include "big_mesh.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <tuple>
#include <unordered_map>
#include <utility>
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


// The undirected pair a-b as one key.
uint64_t pair_key(uint32_t a, uint32_t b) {
  if (a > b) std::swap(a, b);
  return (uint64_t(a) << 32) | b;
}

// One step of loop_subdivide_keeping_attributes().
Mesh loop_step_keeping_attributes(const Mesh& mesh) {
  const std::size_t vertex_count = mesh.vertex_count(), face_count = mesh.face_count();
  // Edges, numbered in order of first use: their ends, their faces' opposite corners.
  struct Edge {
    uint32_t a, b;
    uint32_t faces = 0;
    double opposite[3] = {0, 0, 0};  // the sum of the opposite corners' positions
  };
  std::vector<Edge> edges;
  std::unordered_map<uint64_t, uint32_t> edge_of_pair;
  edge_of_pair.reserve(2 * face_count);
  std::vector<uint32_t> corner_edge(3 * face_count);  // the edge from corner i to corner i+1
  const auto& t = mesh.triangles;
  const auto& p = mesh.positions;
  for (std::size_t f = 0; f < face_count; ++f)
    for (int i = 0; i < 3; ++i) {
      const uint32_t a = t[3 * f + i], b = t[3 * f + (i + 1) % 3], c = t[3 * f + (i + 2) % 3];
      const auto [it, inserted] = edge_of_pair.emplace(pair_key(a, b), uint32_t(edges.size()));
      if (inserted) edges.push_back(Edge{a, b});
      Edge& edge = edges[it->second];
      ++edge.faces;
      for (int axis = 0; axis < 3; ++axis) edge.opposite[axis] += p[3 * std::size_t(c) + axis];
      corner_edge[3 * f + i] = it->second;
    }

  Mesh out;
  out.color_components = mesh.color_components;
  out.material_names = mesh.material_names;
  out.material_libraries = mesh.material_libraries;
  out.positions.resize(3 * (vertex_count + edges.size()));
  // Each old vertex: the sum and number of its neighbours, and of those across boundary
  // edges; whether an edge of three or more faces touches it.
  std::vector<double> ring(3 * vertex_count, 0.0), boundary_ring(3 * vertex_count, 0.0);
  std::vector<uint32_t> valence(vertex_count, 0), boundary_valence(vertex_count, 0);
  std::vector<char> on_complex_edge(vertex_count, 0);
  for (const Edge& edge : edges) {
    for (const auto& [from, to] : {std::pair{edge.a, edge.b}, std::pair{edge.b, edge.a}}) {
      ++valence[from];
      for (int axis = 0; axis < 3; ++axis) ring[3 * std::size_t(from) + axis] += p[3 * std::size_t(to) + axis];
      if (edge.faces == 1) {
        ++boundary_valence[from];
        for (int axis = 0; axis < 3; ++axis)
          boundary_ring[3 * std::size_t(from) + axis] += p[3 * std::size_t(to) + axis];
      }
      if (edge.faces > 2) on_complex_edge[from] = 1;
    }
  }
  const double pi = std::acos(-1.0);
  for (std::size_t v = 0; v < vertex_count; ++v)
    for (int axis = 0; axis < 3; ++axis) {
      const double x = p[3 * v + axis];
      double moved = x;  // no faces, a complex edge, or a boundary that is not one curve
      if (!on_complex_edge[v] && boundary_valence[v] == 0 && valence[v] >= 3) {
        const double n = valence[v], c = 3.0 / 8.0 + std::cos(2 * pi / n) / 4;
        const double beta = (5.0 / 8.0 - c * c) / n;
        moved = (1 - n * beta) * x + beta * ring[3 * v + axis];
      } else if (!on_complex_edge[v] && boundary_valence[v] == 2) {
        moved = 0.75 * x + 0.125 * boundary_ring[3 * v + axis];
      }
      out.positions[3 * v + axis] = float(moved);
    }
  for (std::size_t e = 0; e < edges.size(); ++e)
    for (int axis = 0; axis < 3; ++axis) {
      const Edge& edge = edges[e];
      const double ends = double(p[3 * std::size_t(edge.a) + axis]) + p[3 * std::size_t(edge.b) + axis];
      out.positions[3 * (vertex_count + e) + axis] =
          float(edge.faces == 2 ? 0.375 * ends + 0.125 * edge.opposite[axis] : 0.5 * ends);
    }
  if (mesh.has_colors()) {
    const uint32_t k = mesh.color_components;
    out.colors = mesh.colors;
    out.colors.resize(k * (vertex_count + edges.size()));
    for (std::size_t e = 0; e < edges.size(); ++e)
      for (uint32_t i = 0; i < k; ++i)
        out.colors[k * (vertex_count + e) + i] =
            0.5f * (mesh.colors[k * edges[e].a + i] + mesh.colors[k * edges[e].b + i]);
  }

  // A table of per-corner values (uv: 2 floats, normal: 3), extended by the midpoints of the
  // pairs of entries the faces' edges join, one entry per pair.
  struct Midpoints {
    std::vector<float>& values;
    int width;
    bool normalize;
    std::unordered_map<uint64_t, uint32_t> of_pair{};
    uint32_t at(uint32_t a, uint32_t b) {
      if (a == kNoAttribute || b == kNoAttribute) return kNoAttribute;
      if (a == b) return a;
      const auto [it, inserted] = of_pair.emplace(pair_key(a, b), uint32_t(values.size() / width));
      if (inserted) {
        float mid[3];
        double length = 0;
        for (int i = 0; i < width; ++i) {
          mid[i] = 0.5f * (values[std::size_t(a) * width + i] + values[std::size_t(b) * width + i]);
          length += double(mid[i]) * mid[i];
        }
        if (normalize && length > 0)
          for (int i = 0; i < width; ++i) mid[i] = float(mid[i] / std::sqrt(length));
        values.insert(values.end(), mid, mid + width);
      }
      return it->second;
    }
  };
  out.uvs = mesh.uvs;
  out.normals = mesh.normals;
  Midpoints uv_mid{out.uvs, 2, false};
  Midpoints normal_mid{out.normals, 3, true};

  out.triangles.reserve(12 * face_count);
  if (mesh.has_uvs()) out.uv_indices.reserve(12 * face_count);
  if (mesh.has_normals()) out.normal_indices.reserve(12 * face_count);
  if (mesh.has_materials()) out.face_materials.reserve(4 * face_count);
  // Corners 0, 1, 2 and the edge points 01, 12, 20 make four faces, counter-clockwise as
  // their parent: (0, 01, 20), (01, 1, 12), (20, 12, 2), (01, 12, 20).
  static constexpr int kChildren[4][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}, {3, 4, 5}};
  for (std::size_t f = 0; f < face_count; ++f) {
    uint32_t vertex[6], uv[6], normal[6];
    for (int i = 0; i < 3; ++i) {
      vertex[i] = t[3 * f + i];
      vertex[3 + i] = uint32_t(vertex_count + corner_edge[3 * f + i]);
    }
    for (auto [mid, source, ids] : {std::tuple{&uv_mid, &mesh.uv_indices, uv},
                                    std::tuple{&normal_mid, &mesh.normal_indices, normal}}) {
      if (source->empty()) continue;
      for (int i = 0; i < 3; ++i) ids[i] = (*source)[3 * f + i];
      for (int i = 0; i < 3; ++i) ids[3 + i] = mid->at(ids[i], ids[(i + 1) % 3]);
    }
    for (const auto& child : kChildren)
      for (int corner : child) {
        out.triangles.push_back(vertex[corner]);
        if (mesh.has_uvs()) out.uv_indices.push_back(uv[corner]);
        if (mesh.has_normals()) out.normal_indices.push_back(normal[corner]);
      }
    if (mesh.has_materials()) out.face_materials.insert(out.face_materials.end(), 4, mesh.face_materials[f]);
  }
  return out;
}

}  // namespace

Mesh loop_subdivide_keeping_attributes(const Mesh& mesh, int times) {
  Mesh result = mesh;
  for (int step = 0; step < times; ++step) result = loop_step_keeping_attributes(result);
  return result;
}

namespace {
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
