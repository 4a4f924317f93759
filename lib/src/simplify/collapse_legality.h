// May this half-edge collapse happen? Separate from its cost, and pure: nothing changes.
#pragma once

#include <cstdint>
#include <set>
#include <utility>
#include <vector>

#include "simplify/geometry.h"
#include "simplify/half_edge_mesh.h"
#include "simplify/manifold_repair.h"

namespace pm {

// Topology: the collapse h = (v -> u) keeps the mesh a manifold of the same genus and
// number of boundary loops. That is the link condition (Dey, Edelsbrunner, Guha and
// Nekhayev 1999, "Topology preserving edge contraction", §2: the common neighbours of v
// and u are exactly vl and vr) plus the boundary rules of Hoppe et al. 1993 ("Mesh
// optimization", §3.2: an interior edge between two boundary vertices may not collapse),
// as checked by OpenMesh's is_collapse_ok; and no closed tetrahedron is flattened.
bool collapse_keeps_topology(HalfEdgeMesh& mesh, HalfEdgeMesh::HalfedgeHandle h);

// Geometry: no face of v's fan that survives turns its normal by more than the angle
// whose cosine is cos_max_flip, and none becomes degenerate (its area vector shrinks to
// a negligible fraction of its squared longest edge).
bool collapse_keeps_geometry(const HalfEdgeMesh& mesh, HalfEdgeMesh::HalfedgeHandle h,
                             double cos_max_flip);

// The same test for one face, given its corners before and after the collapse.
bool face_keeps_geometry(const Vec3 before[3], const Vec3 after[3], double cos_max_flip);

// Welds: copies of one input vertex (see manifold_repair.h) are merged at output, so the
// output keeps the input's topology only while that merge stays one-to-one on edges. The
// collapse h = (v -> u) is refused if a new edge u-w would join two copies of one vertex,
// or would merge at output with an existing edge between copies of u's and w's vertices.
// weld_group[x] is the canonical vertex of x's group, or -1 when x is not welded;
// weld_members[c] lists the members of group c.
struct WeldGroups {
  std::vector<int> group;                      // per vertex
  std::vector<std::vector<uint32_t>> members;  // per canonical vertex
  bool empty() const { return members.empty(); }
};
bool collapse_keeps_welds(const HalfEdgeMesh& mesh, HalfEdgeMesh::HalfedgeHandle h,
                          const WeldGroups& welds);

// The weld groups of build_manifold_mesh's copies (empty when it made none).
WeldGroups weld_groups(const ManifoldMesh& repaired);

// The distinct vertex pairs of the carried faces, smaller id first: a collapse may not make
// one of them an edge of the surface (the two would merge at output and lose an edge).
std::set<std::pair<uint32_t, uint32_t>> carried_edges(const ManifoldMesh& repaired);

}  // namespace pm
