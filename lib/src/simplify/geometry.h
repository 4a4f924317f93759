// Small double-precision geometry used by the error and legality functions.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "simplify/half_edge_mesh.h"

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

// Squared distance from p to the segment [a, b]. Inline, like point_triangle_distance: the
// simplifier's innermost loops call them.
inline double point_segment_squared_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.sqrnorm();
  if (len2 == 0.0) return (p - a).sqrnorm();
  const double t = std::clamp(((p - a) | ab) / len2, 0.0, 1.0);
  return (p - (a + ab * t)).sqrnorm();
}
// Distance from p to the segment [a, b].
inline double point_segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  return std::sqrt(point_segment_squared_distance(p, a, b));
}

// Distance from p to the line through a and b (to a when a == b).
double point_line_distance(const Vec3& p, const Vec3& a, const Vec3& b);

// Squared distance from p to the closed triangle (a, b, c) (Ericson 2005, "Real-Time
// Collision Detection", §5.1.5: closest point by Voronoi regions of the triangle). Its square
// root is point_triangle_distance() bit for bit (norm() is the square root of sqrnorm(),
// and the square root keeps the order of the degenerate case's minimum): a search for the
// nearest of many triangles takes the root only of one nearer than the best so far.
inline double point_triangle_squared_distance(const Vec3& p, const Vec3& a, const Vec3& b,
                                              const Vec3& c) {
  // Ericson 2005, §5.1.5, ClosestPtPointTriangle.
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab | ap, d2 = ac | ap;
  if (d1 <= 0 && d2 <= 0) return (p - a).sqrnorm();
  const Vec3 bp = p - b;
  const double d3 = ab | bp, d4 = ac | bp;
  if (d3 >= 0 && d4 <= d3) return (p - b).sqrnorm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return point_segment_squared_distance(p, a, b);
  const Vec3 cp = p - c;
  const double d5 = ab | cp, d6 = ac | cp;
  if (d6 >= 0 && d5 <= d6) return (p - c).sqrnorm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return point_segment_squared_distance(p, a, c);
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return point_segment_squared_distance(p, b, c);
  const double denom = va + vb + vc;
  if (denom == 0.0) {  // degenerate triangle: nearest of its edges
    return std::min({point_segment_squared_distance(p, a, b),
                     point_segment_squared_distance(p, b, c),
                     point_segment_squared_distance(p, a, c)});
  }
  const double v = vb / denom, w = vc / denom;
  return (p - (a + ab * v + ac * w)).sqrnorm();
}
// A square below which a squared distance's root is surely at most `stop` (stop >= 0): the
// product's rounding (half a unit in the last place) and the root's cannot bring a square
// under it to a root above stop (2^-50 is eight such units). A search that only needs to
// know whether a distance is within `stop` compares squares, and takes no root. Where
// stop * stop is below the normal doubles its rounding has no such bound: -1, which no
// square is below. (KeptPoints::nearer_around()'s square_bound is the other side: a square
// above which the root is surely beyond a distance.)
inline double square_surely_within(double stop) {
  const double square = stop * stop;
  return square >= std::numeric_limits<double>::min() ? square * (1 - 0x1p-50) : -1.0;
}
// Distance from p to the closed triangle (a, b, c).
inline double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  return std::sqrt(point_triangle_squared_distance(p, a, b, c));
}

}  // namespace pm
