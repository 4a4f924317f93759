#include "simplify/collapse_legality.h"

#include <algorithm>

#include "simplify/geometry.h"

namespace pm {

namespace {

// The link condition as OpenMesh's TriConnectivity::is_collapse_ok states it (the same
// answers), without its per-call allocations and tagged-bit writes: h (v0 -> v1) is not
// deleted, nor are its ends; neither of its triangles has both other edges on a boundary;
// vl != vr (so not both missing); v0 and v1 have no common neighbour but vl and vr; and
// an interior edge does not join two boundary vertices. When it holds, *valence0 and
// *valence1 are the valences of v0 and v1 (the walks count them).
bool link_condition(HalfEdgeMesh& mesh, HalfEdgeMesh::HalfedgeHandle v0v1, int* valence0,
                    int* valence1) {
  if (mesh.status(mesh.edge_handle(v0v1)).deleted()) return false;
  const auto v1v0 = mesh.opposite_halfedge_handle(v0v1);
  const auto v0 = mesh.to_vertex_handle(v1v0), v1 = mesh.to_vertex_handle(v0v1);
  if (mesh.status(v0).deleted() || mesh.status(v1).deleted()) return false;
  HalfEdgeMesh::VertexHandle vl, vr;
  auto apex = [&](HalfEdgeMesh::HalfedgeHandle h, HalfEdgeMesh::VertexHandle& apex) {
    if (mesh.is_boundary(h)) return true;
    const auto h1 = mesh.next_halfedge_handle(h), h2 = mesh.next_halfedge_handle(h1);
    apex = mesh.to_vertex_handle(h1);
    return !(mesh.is_boundary(mesh.opposite_halfedge_handle(h1)) &&
             mesh.is_boundary(mesh.opposite_halfedge_handle(h2)));
  };
  if (!apex(v0v1, vl) || !apex(v1v0, vr) || vl == vr) return false;
  // Neighbours of v1, then each neighbour of v0 looked up among them: valences are small.
  HalfEdgeMesh::VertexHandle ring[64];
  int n = 0;
  *valence1 = 0;
  for (auto w : mesh.vv_range(v1)) {
    ++*valence1;
    if (w == vl || w == vr) continue;
    if (n == 64) {  // a hub: OpenMesh's own test
      if (!mesh.is_collapse_ok(v0v1)) return false;
      *valence0 = static_cast<int>(mesh.valence(v0));
      *valence1 = static_cast<int>(mesh.valence(v1));
      return true;
    }
    ring[n++] = w;
  }
  *valence0 = 0;
  for (auto w : mesh.vv_range(v0)) {
    ++*valence0;
    for (int i = 0; i < n; ++i)
      if (ring[i] == w) return false;
  }
  return !(mesh.is_boundary(v0) && mesh.is_boundary(v1) && !mesh.is_boundary(v0v1) &&
           !mesh.is_boundary(v1v0));
}

}  // namespace

bool collapse_keeps_topology(HalfEdgeMesh& mesh, HalfEdgeMesh::HalfedgeHandle h) {
  int valence_v, valence_u;
  if (!link_condition(mesh, h, &valence_v, &valence_u)) return false;
  // A closed tetrahedron passes the link condition, but collapsing any of its edges leaves
  // two triangles on the same three vertices: not a simplicial surface any more.
  const auto v = mesh.from_vertex_handle(h), u = mesh.to_vertex_handle(h);
  return !(valence_v == 3 && valence_u == 3 && !mesh.is_boundary(v) && !mesh.is_boundary(u));
}

bool collapse_keeps_geometry(const HalfEdgeMesh& mesh, HalfEdgeMesh::HalfedgeHandle h,
                             double cos_max_flip) {
  const auto v = mesh.from_vertex_handle(h), u = mesh.to_vertex_handle(h);
  const HalfEdgeMesh::FaceHandle fl = mesh.face_handle(h), fr = mesh.opposite_face_handle(h);
  const Vec3 pu = point_of(mesh, u);
  for (auto f : mesh.vf_range(v)) {
    if (f == fl || f == fr) continue;
    Vec3 before[3], after[3];
    int k = 0;
    for (auto w : mesh.fv_range(f)) {
      before[k] = point_of(mesh, w);
      after[k] = (w == v) ? pu : before[k];
      ++k;
    }
    if (!face_keeps_geometry(before, after, cos_max_flip)) return false;
  }
  return true;
}

bool face_keeps_geometry(const Vec3 before[3], const Vec3 after[3], double cos_max_flip) {
  // Relative threshold for a degenerate face: |a x b| below this times the squared
  // longest edge means the triangle is thinner than float32 can represent faithfully.
  constexpr double kDegenerate = 1e-10;
  const Vec3 n0 = area_vector(before[0], before[1], before[2]);
  const Vec3 n1 = area_vector(after[0], after[1], after[2]);
  const double longest = std::max({(after[1] - after[0]).sqrnorm(), (after[2] - after[1]).sqrnorm(),
                                   (after[0] - after[2]).sqrnorm()});
  const double len1 = n1.norm();
  if (len1 <= kDegenerate * longest) return false;
  const double len0 = n0.norm();
  return !(len0 > 0 && (n0 | n1) < cos_max_flip * len0 * len1);
}

bool collapse_keeps_welds(const HalfEdgeMesh& mesh, HalfEdgeMesh::HalfedgeHandle h,
                          const WeldGroups& welds) {
  if (welds.empty()) return true;
  const auto v = mesh.from_vertex_handle(h), u = mesh.to_vertex_handle(h);
  auto members_of = [&](HalfEdgeMesh::VertexHandle x,
                        uint32_t& single) -> std::pair<const uint32_t*, std::size_t> {
    const int g = welds.group[x.idx()];
    if (g < 0) {
      single = static_cast<uint32_t>(x.idx());
      return {&single, 1};
    }
    return {welds.members[g].data(), welds.members[g].size()};
  };
  const int group_u = welds.group[u.idx()];
  for (auto w : mesh.vv_range(v)) {
    if (w == u) continue;
    const int group_w = welds.group[w.idx()];
    if (group_u < 0 && group_w < 0) continue;  // nothing is merged at output
    if (group_u >= 0 && group_u == group_w) return false;
    uint32_t single_u, single_w;
    const auto [us, nu] = members_of(u, single_u);
    const auto [ws, nw] = members_of(w, single_w);
    for (std::size_t i = 0; i < nu; ++i)
      for (std::size_t j = 0; j < nw; ++j) {
        const auto a = mesh.vertex_handle(us[i]), b = mesh.vertex_handle(ws[j]);
        if (a == u && b == w) continue;  // the edge itself: exists already only if u-w does
        if (mesh.find_halfedge(a, b).is_valid()) return false;
      }
  }
  return true;
}

std::set<std::pair<uint32_t, uint32_t>> carried_edges(const ManifoldMesh& repaired) {
  std::set<std::pair<uint32_t, uint32_t>> edges;
  const auto& f = repaired.carried_faces;
  for (std::size_t i = 0; i + 2 < f.size(); i += 3)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = f[i + k], b = f[i + (k + 1) % 3];
      if (a != b) edges.insert({std::min(a, b), std::max(a, b)});
    }
  return edges;
}

WeldGroups weld_groups(const ManifoldMesh& repaired) {
  WeldGroups welds;
  const std::size_t n = repaired.canonical.size();
  for (uint32_t x = 0; x < n; ++x) {
    const uint32_t c = repaired.canonical[x];
    if (c == x) continue;
    if (welds.group.empty()) {
      welds.group.assign(n, -1);
      welds.members.resize(n);
    }
    if (welds.group[c] < 0) {
      welds.group[c] = static_cast<int>(c);
      welds.members[c].push_back(c);
    }
    welds.group[x] = static_cast<int>(c);
    welds.members[c].push_back(x);
  }
  return welds;
}

}  // namespace pm
