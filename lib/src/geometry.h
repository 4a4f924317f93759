// Small double-precision geometry used by the error and legality functions.
#pragma once

#include <cmath>

#include "half_edge_mesh.h"

namespace pm {

using Vec3 = OpenMesh::Vec3d;

inline Vec3 to_vec3(const HalfEdgeMesh::Point& p) {
  return Vec3(p[0], p[1], p[2]);
}
inline Vec3 point_of(const HalfEdgeMesh& mesh, HalfEdgeMesh::VertexHandle v) {
  return to_vec3(mesh.point(v));
}

// Twice the area vector of triangle (a, b, c): its direction is the normal.
inline Vec3 area_vector(const Vec3& a, const Vec3& b, const Vec3& c) {
  return (b - a) % (c - a);
}

// Distance from p to the segment [a, b].
double point_segment_distance(const Vec3& p, const Vec3& a, const Vec3& b);

// Distance from p to the line through a and b (to a when a == b).
double point_line_distance(const Vec3& p, const Vec3& a, const Vec3& b);

// Distance from p to the closed triangle (a, b, c) (Ericson 2005, "Real-Time Collision
// Detection", §5.1.5: closest point by Voronoi regions of the triangle).
double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace pm
