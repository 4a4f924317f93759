// Schroeder, Zarge and Lorensen 1992, "Decimation of triangle meshes", §3.2;
// Schroeder 1997, "A topology modifying progressive decimation algorithm", §3.3.
#include "simplify/schroeder_error.h"

namespace pm {

double distance_to_average_plane(const HalfEdgeMesh& mesh, const FaceGeometry& faces,
                                 HalfEdgeMesh::VertexHandle v) {
  return average_plane_distance(point_of(mesh, v), [&](auto&& visit) {
    for (auto f : mesh.vf_range(v)) {
      auto fv = mesh.cfv_iter(f);
      const Vec3 a = point_of(mesh, *fv), b = point_of(mesh, *++fv), c = point_of(mesh, *++fv);
      visit(a, b, c, faces.normal[f.idx()], faces.area[f.idx()]);
    }
  });
}

double distance_to_feature_line(const HalfEdgeMesh& mesh, HalfEdgeMesh::VertexHandle v,
                                const VertexClass& vertex_class) {
  return point_line_distance(point_of(mesh, v), point_of(mesh, vertex_class.line_ends[0]),
                             point_of(mesh, vertex_class.line_ends[1]));
}

double collapse_distance(const HalfEdgeMesh& mesh, HalfEdgeMesh::HalfedgeHandle h) {
  const auto v = mesh.from_vertex_handle(h), u = mesh.to_vertex_handle(h);
  const HalfEdgeMesh::FaceHandle fl = mesh.face_handle(h), fr = mesh.opposite_face_handle(h);
  const Vec3 pu = point_of(mesh, u);
  return collapse_distance_over(
      point_of(mesh, v), pu,
      [&](auto&& visit) {
        for (auto f : mesh.vf_range(v)) {
          if (f == fl || f == fr) continue;
          Vec3 corner[3];
          int k = 0;
          for (auto w : mesh.fv_range(f)) corner[k++] = (w == v) ? pu : point_of(mesh, w);
          visit(corner[0], corner[1], corner[2]);
        }
      },
      [&](auto&& visit) {
        for (auto w : mesh.vv_range(v))
          if (w != u) visit(point_of(mesh, w));
      });
}

double vertex_removal_error(const HalfEdgeMesh& mesh, const FaceGeometry& faces,
                            const VertexClass& vertex_class, HalfEdgeMesh::HalfedgeHandle h) {
  switch (vertex_class.kind) {
    case VertexKind::kSimple:
      return distance_to_average_plane(mesh, faces, mesh.from_vertex_handle(h));
    case VertexKind::kBoundary:
    case VertexKind::kInteriorEdge:
      return distance_to_feature_line(mesh, mesh.from_vertex_handle(h), vertex_class);
    case VertexKind::kCorner:
    case VertexKind::kComplex:
      return collapse_distance(mesh, h);
  }
  return collapse_distance(mesh, h);
}

}  // namespace pm
