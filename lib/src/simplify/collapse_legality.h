// What the collapse loop's legality tests share: one face's geometry test, the repair's
// weld groups and carried edges (collapse_loop.h tests topology on its own connectivity).
#pragma once

#include <cstdint>
#include <set>
#include <utility>
#include <vector>

#include "simplify/geometry.h"
#include "simplify/manifold_repair.h"

namespace pm {

// Geometry: no face of v's fan that survives the collapse v -> u turns its normal by more
// than the angle whose cosine is cos_max_flip, and none becomes degenerate (its area vector
// shrinks to a negligible fraction of its squared longest edge). The test for one face,
// given its corners before and after the collapse (CollapseLoop::keeps_geometry).
bool face_keeps_geometry(const Vec3 before[3], const Vec3 after[3], double cos_max_flip);

// Welds: copies of one input vertex (see manifold_repair.h) are merged at output, so the
// output keeps the input's topology only while that merge stays one-to-one on edges
// (CollapseLoop::keeps_weld_groups refuses the collapses that would break it).
// group[x] is the canonical vertex of x's group, or -1 when x is not welded;
// members[c] lists the members of group c.
struct WeldGroups {
  std::vector<int> group;                      // per vertex
  std::vector<std::vector<uint32_t>> members;  // per canonical vertex
  bool empty() const { return members.empty(); }
};

// The weld groups of build_manifold_mesh's copies (empty when it made none).
WeldGroups weld_groups(const ManifoldMesh& repaired);

// The distinct vertex pairs of the carried faces, smaller id first: a collapse may not make
// one of them an edge of the surface (the two would merge at output and lose an edge).
std::set<std::pair<uint32_t, uint32_t>> carried_edges(const ManifoldMesh& repaired);

}  // namespace pm
