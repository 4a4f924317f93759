// Schroeder's vertex classification (Schroeder, Zarge and Lorensen 1992, "Decimation of
// triangle meshes", §3.1; Schroeder 1997, "A topology modifying progressive decimation
// algorithm", §3): what kind of vertex this is decides how it may be removed and how its
// error is measured.
#pragma once

#include <cstdint>
#include <vector>

#include "simplify/geometry.h"

namespace pm {

enum class VertexKind : uint8_t {
  kSimple,        // interior, no feature edge: error = distance to the average plane
  kBoundary,      // on a boundary, no feature edge: error = distance to the boundary line
  kInteriorEdge,  // interior, exactly two feature edges: error = distance to the feature line
  kCorner,        // one or three or more special edges, or boundary and feature: removed last
  kComplex,       // non-manifold or pinned by the repair: never removed
};
inline constexpr int kVertexKindCount = 5;

// Along which edges a vertex of each kind may be collapsed (v -> u along edge v-u):
// only along its special (boundary or feature) edges, so that the boundary or the
// feature line keeps its shape; simple vertices along any edge. Corners prefer their
// special edges and fall back to any edge.
enum class CollapseEdges : uint8_t { kNone, kAny, kSpecialOnly, kSpecialFirst };
inline constexpr CollapseEdges kCollapseEdges[kVertexKindCount] = {
    CollapseEdges::kAny,           // simple
    CollapseEdges::kSpecialOnly,   // boundary
    CollapseEdges::kSpecialOnly,   // interior edge
    CollapseEdges::kSpecialFirst,  // corner
    CollapseEdges::kNone,          // complex
};

// Schroeder, Zarge and Lorensen 1992, §3.1, with Schroeder 1997's corner rule: the kind of
// a manifold vertex with faces, from how many of its edges are boundary and feature edges.
inline VertexKind kind_from_edges(int boundary_edges, int feature_edges) {
  if (boundary_edges == 0 && feature_edges == 0) return VertexKind::kSimple;
  if (boundary_edges == 2 && feature_edges == 0) return VertexKind::kBoundary;
  if (boundary_edges == 0 && feature_edges == 2) return VertexKind::kInteriorEdge;
  return VertexKind::kCorner;
}

}  // namespace pm
