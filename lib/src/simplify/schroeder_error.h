// The error of removing a vertex, by Schroeder's decimation criteria (Schroeder, Zarge
// and Lorensen 1992, §3.2 "Evaluating the decimation criteria"; Schroeder 1997, §3.3).
#pragma once

#include <cmath>
#include <limits>

#include "simplify/geometry.h"
#include "simplify/vertex_classification.h"

namespace pm {

// A corner with an edge sharper than this is a corner of the shape (a fandisk's, a
// machined part's), not of tessellation noise (on organic meshes the 30 degree feature
// angle finds many mild "corners"). Its error counts kSharpCornerWeight times: such
// corners go last in practice, mild ones compete on their error. Both loops.
inline constexpr double kSharpCornerDeg = 60.0;
inline constexpr double kSharpCornerWeight = 10.0;

// The formulas, over a description of v's fan that either loop gives (the former default loop's
// half-edge mesh, the collapse loop's flat arrays: schroeder_costs.cpp).
//
// Schroeder 1992, §3.2: the distance from p to the average plane of its triangles.
// for_each_face(visit) calls visit(a, b, c, unit normal, area) for each face of the fan
// (a zero normal for a degenerate face).
template <typename ForEachFace>
double average_plane_distance(const Vec3& p, ForEachFace&& for_each_face) {
  Vec3 normal(0, 0, 0), centre(0, 0, 0);
  double total_area = 0;
  for_each_face([&](const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& n, double area) {
    normal += n * area;
    centre += (a + b + c) * (area / 3.0);
    total_area += area;
  });
  const double length = normal.norm();
  if (total_area == 0 || length == 0) return 0;  // all faces degenerate: nothing to lose
  centre /= total_area;
  return std::abs((p - centre) | (normal / length));
}

// The distance from p (v) to the triangles that replace v's fan when v moves onto pu:
// for_each_face(visit) calls visit(a, b, c) for each face of v's but the two on v-u, with
// pu in place of p; when there is none (an ear), to the edges u-w, for_each_neighbour(visit)
// calling visit(w) for each neighbour w of v but u.
template <typename ForEachFace, typename ForEachNeighbour>
double collapse_distance_over(const Vec3& p, const Vec3& pu, ForEachFace&& for_each_face,
                              ForEachNeighbour&& for_each_neighbour) {
  double nearest = std::numeric_limits<double>::infinity();
  for_each_face([&](const Vec3& a, const Vec3& b, const Vec3& c) {
    nearest = std::min(nearest, point_triangle_distance(p, a, b, c));
  });
  if (nearest == std::numeric_limits<double>::infinity()) {
    // No face survives around v (an ear): v's edges fold onto u-vl or u-vr.
    for_each_neighbour(
        [&](const Vec3& w) { nearest = std::min(nearest, point_segment_distance(p, pu, w)); });
  }
  return nearest == std::numeric_limits<double>::infinity() ? (p - pu).norm() : nearest;
}

}  // namespace pm
