// Schroeder, Zarge and Lorensen 1992, "Decimation of triangle meshes", §3.2;
// Schroeder 1997, "A topology modifying progressive decimation algorithm", §3.3.
#include "simplify/schroeder_error.h"

#include <limits>

namespace pm {

double distance_to_average_plane(const HalfEdgeMesh& mesh, const FaceGeometry& faces,
                                 HalfEdgeMesh::VertexHandle v) {
  Vec3 normal(0, 0, 0), centre(0, 0, 0);
  double total_area = 0;
  for (auto f : mesh.vf_range(v)) {
    const double area = faces.area[f.idx()];
    auto fv = mesh.cfv_iter(f);
    const Vec3 a = point_of(mesh, *fv), b = point_of(mesh, *++fv), c = point_of(mesh, *++fv);
    normal += faces.normal[f.idx()] * area;
    centre += (a + b + c) * (area / 3.0);
    total_area += area;
  }
  const double length = normal.norm();
  if (total_area == 0 || length == 0) return 0;  // all faces degenerate: nothing to lose
  centre /= total_area;
  return std::abs((point_of(mesh, v) - centre) | (normal / length));
}

double distance_to_feature_line(const HalfEdgeMesh& mesh, HalfEdgeMesh::VertexHandle v,
                                const VertexClass& vertex_class) {
  return point_line_distance(point_of(mesh, v), point_of(mesh, vertex_class.line_ends[0]),
                             point_of(mesh, vertex_class.line_ends[1]));
}

double collapse_distance(const HalfEdgeMesh& mesh, HalfEdgeMesh::HalfedgeHandle h) {
  const auto v = mesh.from_vertex_handle(h), u = mesh.to_vertex_handle(h);
  const HalfEdgeMesh::FaceHandle fl = mesh.face_handle(h), fr = mesh.opposite_face_handle(h);
  const Vec3 p = point_of(mesh, v), pu = point_of(mesh, u);
  double nearest = std::numeric_limits<double>::infinity();
  for (auto f : mesh.vf_range(v)) {
    if (f == fl || f == fr) continue;
    Vec3 corner[3];
    int k = 0;
    for (auto w : mesh.fv_range(f)) corner[k++] = (w == v) ? pu : point_of(mesh, w);
    nearest = std::min(nearest, point_triangle_distance(p, corner[0], corner[1], corner[2]));
  }
  if (nearest == std::numeric_limits<double>::infinity()) {
    // No face survives around v (an ear): v's edges fold onto u-vl or u-vr.
    for (auto w : mesh.vv_range(v))
      if (w != u) nearest = std::min(nearest, point_segment_distance(p, pu, point_of(mesh, w)));
  }
  return nearest == std::numeric_limits<double>::infinity() ? (p - pu).norm() : nearest;
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
