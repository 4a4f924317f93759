// Schroeder's vertex classification (Schroeder, Zarge and Lorensen 1992, "Decimation of
// triangle meshes", §3.1; Schroeder 1997, "A topology modifying progressive decimation
// algorithm", §3): what kind of vertex this is decides how it may be removed and how its
// error is measured.
#pragma once

#include <cstdint>
#include <vector>

#include "simplify/geometry.h"
#include "simplify/half_edge_mesh.h"

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

struct VertexClass {
  VertexKind kind = VertexKind::kComplex;
  // The two neighbours across the special edges, for boundary and interior-edge vertices.
  HalfEdgeMesh::VertexHandle line_ends[2];
};

class CornerAttributes;

// Per-face unit normals and areas of the current mesh, kept up to date by the simplifier.
struct FaceGeometry {
  std::vector<Vec3> normal;  // unit, or zero for a degenerate face
  std::vector<double> area;
  // Attribute seams and material borders count as feature edges (Garland and Heckbert
  // 1998, §4: discontinuities are kept like boundaries). Null when there are none.
  const CornerAttributes* attributes = nullptr;
  void update(const HalfEdgeMesh& mesh, HalfEdgeMesh::FaceHandle f);
};

// An edge is special if it is a boundary edge or a feature edge: the normals of its two
// faces differ by more than the feature angle (cos_feature_angle = its cosine), or it is
// an attribute seam or a material border.
bool is_boundary_edge(const HalfEdgeMesh& mesh, HalfEdgeMesh::EdgeHandle e);
bool is_feature_edge(const HalfEdgeMesh& mesh, const FaceGeometry& faces,
                     HalfEdgeMesh::EdgeHandle e, double cos_feature_angle);
inline bool is_special_edge(const HalfEdgeMesh& mesh, const FaceGeometry& faces,
                            HalfEdgeMesh::EdgeHandle e, double cos_feature_angle) {
  return is_boundary_edge(mesh, e) || is_feature_edge(mesh, faces, e, cos_feature_angle);
}

VertexClass classify_vertex(const HalfEdgeMesh& mesh, const FaceGeometry& faces,
                            HalfEdgeMesh::VertexHandle v, double cos_feature_angle, bool pinned);

}  // namespace pm
