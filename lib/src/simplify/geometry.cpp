#include "simplify/geometry.h"

#include <algorithm>

namespace pm {

double point_line_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.sqrnorm();
  if (len2 == 0.0) return (p - a).norm();
  const double t = ((p - a) | ab) / len2;
  return (p - (a + ab * t)).norm();
}

}  // namespace pm
