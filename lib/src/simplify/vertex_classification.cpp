// Schroeder, Zarge and Lorensen 1992, §3.1 (vertex classification), with the corner
// rule of Schroeder 1997, §3 (a vertex with one or more than two feature edges, or on a
// boundary with a feature edge, is a corner).
#include "simplify/vertex_classification.h"

#include "simplify/corner_attributes.h"

namespace pm {

void FaceGeometry::update(const HalfEdgeMesh& mesh, HalfEdgeMesh::FaceHandle f) {
  auto fv = mesh.cfv_iter(f);
  const Vec3 a = point_of(mesh, *fv);
  const Vec3 b = point_of(mesh, *++fv);
  const Vec3 c = point_of(mesh, *++fv);
  const Vec3 n = area_vector(a, b, c);
  const double twice_area = n.norm();
  area[f.idx()] = 0.5 * twice_area;
  normal[f.idx()] = twice_area > 0 ? n / twice_area : Vec3(0, 0, 0);
}

bool is_boundary_edge(const HalfEdgeMesh& mesh, HalfEdgeMesh::EdgeHandle e) {
  return mesh.is_boundary(e);
}

bool is_feature_edge(const HalfEdgeMesh& mesh, const FaceGeometry& faces,
                     HalfEdgeMesh::EdgeHandle e, double cos_feature_angle) {
  if (mesh.is_boundary(e)) return false;
  const auto f0 = mesh.face_handle(mesh.halfedge_handle(e, 0));
  const auto f1 = mesh.face_handle(mesh.halfedge_handle(e, 1));
  // A degenerate face has no normal; its edges count as features so that nothing
  // is collapsed across it on a guess.
  return (faces.normal[f0.idx()] | faces.normal[f1.idx()]) < cos_feature_angle ||
         (faces.attributes &&
          faces.attributes->is_seam(static_cast<uint32_t>(f0.idx()), static_cast<uint32_t>(f1.idx()),
                                    static_cast<uint32_t>(mesh.from_vertex_handle(mesh.halfedge_handle(e, 0)).idx()),
                                    static_cast<uint32_t>(mesh.to_vertex_handle(mesh.halfedge_handle(e, 0)).idx())));
}

VertexClass classify_vertex(const HalfEdgeMesh& mesh, const FaceGeometry& faces,
                            HalfEdgeMesh::VertexHandle v, double cos_feature_angle, bool pinned) {
  VertexClass result;
  if (pinned || mesh.is_isolated(v) || !mesh.is_manifold(v)) return result;  // complex
  int boundary_edges = 0, feature_edges = 0;
  for (auto h : mesh.voh_range(v)) {
    const auto e = mesh.edge_handle(h);
    const bool boundary = mesh.is_boundary(e);
    const bool feature = !boundary && is_feature_edge(mesh, faces, e, cos_feature_angle);
    if (!boundary && !feature) continue;
    const int special = boundary_edges + feature_edges;
    if (special < 2) result.line_ends[special] = mesh.to_vertex_handle(h);
    boundary_edges += boundary;
    feature_edges += feature;
  }
  result.kind = kind_from_edges(boundary_edges, feature_edges);
  return result;
}

}  // namespace pm
