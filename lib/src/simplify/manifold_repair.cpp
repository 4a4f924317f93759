// Manifold repair by cutting: an edge is kept only where it joins exactly two faces of
// opposite orientation; elsewhere it is cut, and every vertex gets one copy per fan of
// faces still connected around it (Guéziec, Taubin, Lazarus and Horn 2001, "Cutting and
// stitching: converting sets of polygons to manifold surfaces", §3: the cutting step).
// Unlike that paper we never stitch back: the copies are welded at output instead, and
// they are pinned (Schroeder 1992 keeps "complex" vertices) so the weld holds at every
// level of detail.
#include "simplify/manifold_repair.h"

#include "io/openmesh_logs.h"

#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>

namespace pm {
namespace {

// Union-find over face corners, with path halving.
class CornerSets {
 public:
  explicit CornerSets(std::size_t n) : parent_(n) {
    std::iota(parent_.begin(), parent_.end(), uint32_t{0});
  }
  uint32_t find(uint32_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void unite(uint32_t a, uint32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<uint32_t> parent_;
};

inline uint32_t next_corner(uint32_t c) {
  return c - c % 3 + (c + 1) % 3;
}

bool has_repeated_index(const uint32_t* t) {
  return t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
}

}  // namespace

Status check_encodable(const Mesh& input) {
  const std::size_t vertex_count = input.vertex_count();
  const std::size_t face_count = input.face_count();
  if (input.positions.size() % 3 != 0 || input.triangles.size() % 3 != 0)
    return Status(ErrorCode::kInvalidArgument, "positions or triangles not a multiple of 3");
  if (vertex_count == 0) return Status(ErrorCode::kEmptyMesh, "no vertices");
  // Corners are numbered in 32 bits, and copies can at most triple the vertices.
  if (face_count >= (1u << 30) || vertex_count >= (1u << 30))
    return Status(ErrorCode::kResourceLimit, "more than 2^30 vertices or faces");
  const uint32_t* tri = input.triangles.data();
  for (std::size_t i = 0; i < input.triangles.size(); ++i) {
    if (tri[i] >= vertex_count)
      return Status(ErrorCode::kInvalidArgument, "face " + std::to_string(i / 3 + 1) +
                                                     " uses vertex " + std::to_string(tri[i] + 1) +
                                                     " of " + std::to_string(vertex_count));
  }
  // Every distance the encoder records must fit a float32 (encoder.h, kMaxEncodeDiagonal).
  double low[3], high[3];
  for (int axis = 0; axis < 3; ++axis) low[axis] = high[axis] = input.positions[axis];
  for (std::size_t i = 0; i < input.positions.size(); ++i) {
    const double x = input.positions[i];
    if (!std::isfinite(x)) {
      return Status(ErrorCode::kInvalidArgument,
                    "vertex " + std::to_string(i / 3 + 1) + " has a non-finite coordinate");
    }
    low[i % 3] = std::min(low[i % 3], x);
    high[i % 3] = std::max(high[i % 3], x);
  }
  const double diagonal = std::hypot(high[0] - low[0], high[1] - low[1], high[2] - low[2]);
  if (diagonal > kMaxEncodeDiagonal) {
    char text[64];
    std::snprintf(text, sizeof text, "%.3g units across, more than %.3g", diagonal,
                  kMaxEncodeDiagonal);
    return Status(ErrorCode::kResourceLimit, std::string("the mesh is ") + text);
  }
  return Status::ok();
}

Status build_manifold_mesh(const Mesh& input, ManifoldMesh& out) {
  if (Status s = check_encodable(input); !s) return s;
  const std::size_t vertex_count = input.vertex_count();
  const std::size_t face_count = input.face_count();
  const uint32_t* tri = input.triangles.data();

  // OpenMesh reports rejected faces on its error stream; the library never prints.
  const QuietOpenMeshLogs quiet;

  // Faces with a repeated index have no place in a half-edge mesh: carry them aside.
  std::vector<uint8_t> carried(face_count, 0);
  std::vector<uint8_t> referenced(vertex_count, 0);
  for (std::size_t f = 0; f < face_count; ++f) {
    carried[f] = has_repeated_index(tri + 3 * f);
    for (int k = 0; k < 3; ++k) referenced[tri[3 * f + k]] = 1;
  }

  // Undirected edges, grouped by sorting their corners (the corner that starts the edge).
  std::vector<std::pair<uint64_t, uint32_t>> edges;
  edges.reserve(3 * face_count);
  for (uint32_t f = 0; f < face_count; ++f) {
    if (carried[f]) continue;
    for (uint32_t k = 0; k < 3; ++k) {
      const uint32_t c = 3 * f + k;
      const uint64_t a = tri[c], b = tri[next_corner(c)];
      edges.emplace_back(std::min(a, b) << 32 | std::max(a, b), c);
    }
  }
  std::sort(edges.begin(), edges.end());

  // Two faces stay joined across an edge only if it is a manifold edge; their corners at
  // each end of the edge then belong to the same fan.
  CornerSets fans(3 * face_count);
  std::size_t complex_edges = 0;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].first == edges[i].first) ++j;
    if (j - i == 2) {
      const uint32_t c1 = edges[i].second, c2 = edges[i + 1].second;
      if (tri[c1] == tri[next_corner(c2)]) {  // opposite orientations
        fans.unite(c1, next_corner(c2));
        fans.unite(next_corner(c1), c2);
      } else {
        ++complex_edges;
      }
    } else if (j - i > 2) {
      ++complex_edges;
    }
    i = j;
  }
  edges.clear();
  edges.shrink_to_fit();

  HalfEdgeMesh& mesh = out.mesh;
  mesh.clear();
  mesh.reserve(vertex_count, 3 * face_count / 2, face_count);
  out.input_vertex.clear();
  out.pinned.clear();
  out.canonical.clear();
  out.carried_faces.clear();
  out.carried_input_faces.clear();
  out.input_face.clear();
  out.loose_vertices.clear();
  out.report = RepairReport{};

  auto add_vertex = [&](uint32_t input_id, uint32_t canonical_vertex) {
    const uint32_t id = static_cast<uint32_t>(mesh.n_vertices());
    const float* p = &input.positions[3 * input_id];
    mesh.add_vertex(HalfEdgeMesh::Point(p[0], p[1], p[2]));
    out.input_vertex.push_back(input_id);
    out.pinned.push_back(0);
    out.canonical.push_back(canonical_vertex == kNoVertex ? id : canonical_vertex);
    return id;
  };

  // One primary vertex per referenced input vertex, in input order.
  std::vector<uint32_t> primary(vertex_count, kNoVertex);
  for (uint32_t v = 0; v < vertex_count; ++v) {
    if (referenced[v])
      primary[v] = add_vertex(v, kNoVertex);
    else
      out.loose_vertices.push_back(v);
  }

  // The first fan of a vertex keeps the primary vertex; each further fan gets a copy.
  std::vector<uint32_t> fan_vertex(3 * face_count, kNoVertex);
  std::vector<uint8_t> primary_taken(vertex_count, 0);
  auto pin_copy = [&](uint32_t copy) {
    out.pinned[copy] = 1;
    out.pinned[out.canonical[copy]] = 1;
    ++out.report.vertices_duplicated;
  };
  for (uint32_t c = 0; c < 3 * face_count; ++c) {
    if (carried[c / 3]) continue;
    const uint32_t root = fans.find(c);
    if (fan_vertex[root] != kNoVertex) continue;
    const uint32_t v = tri[c];
    if (!primary_taken[v]) {
      primary_taken[v] = 1;
      fan_vertex[root] = primary[v];
    } else {
      fan_vertex[root] = add_vertex(v, primary[v]);
      pin_copy(fan_vertex[root]);
    }
  }

  for (uint32_t f = 0; f < face_count; ++f) {
    if (carried[f]) {
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = primary[tri[3 * f + k]];
        out.carried_faces.push_back(v);
        out.pinned[v] = 1;
      }
      out.carried_input_faces.push_back(f);
      continue;
    }
    out.input_face.push_back(f);  // add_face below adds exactly one face, or fails
    HalfEdgeMesh::VertexHandle corners[3];
    for (int k = 0; k < 3; ++k) corners[k] = mesh.vertex_handle(fan_vertex[fans.find(3 * f + k)]);
    if (mesh.add_face(corners[0], corners[1], corners[2]).is_valid()) continue;
    // The fans could not be stitched (e.g. a locally non-orientable strip): the face
    // becomes an island of three fresh copies.
    for (int k = 0; k < 3; ++k) {
      const uint32_t copy = add_vertex(tri[3 * f + k], out.canonical[corners[k].idx()]);
      pin_copy(copy);
      corners[k] = mesh.vertex_handle(copy);
    }
    if (!mesh.add_face(corners[0], corners[1], corners[2]).is_valid())
      return Status(ErrorCode::kInternal, "face " + std::to_string(f + 1) + " cannot be inserted");
  }

  out.report.complex_edges = complex_edges;
  out.report.carried_faces = out.carried_faces.size() / 3;
  out.report.loose_vertices = out.loose_vertices.size();
  return Status::ok();
}

}  // namespace pm
