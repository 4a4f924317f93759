// The collapse loop's float32 quadric relative to its vertex (lib/src/simplify/local_quadric.h)
// measures what the double quadric (quadric.h) measures, and keeps small errors far from the
// origin.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "simplify/local_quadric.h"
#include "simplify/quadric.h"

namespace pm {
namespace {

Vec3 unit(const Vec3& v) {
  return v / v.norm();
}

TEST(LocalQuadric, AgreesWithTheDoubleQuadricAndMergesAcrossOrigins) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
  auto point = [&] { return Vec3(coordinate(random), coordinate(random), coordinate(random)); };
  const Vec3 o1 = point(), o2 = point();
  Quadric global1, global2;
  LocalQuadric local1, local2;
  for (int i = 0; i < 6; ++i) {
    const Vec3 n = unit(point()), on_plane = point();
    const double w = 0.5 + i;
    global1 += Quadric::from_plane(n, on_plane, w);
    local1.add_plane(n, on_plane, w, o1);
    const Vec3 n2 = unit(point()), on_plane2 = point();
    global2 += Quadric::from_plane(n2, on_plane2, w);
    local2.add_plane(n2, on_plane2, w, o2);
  }
  for (int i = 0; i < 20; ++i) {
    const Vec3 p = point();
    EXPECT_NEAR(local1.error_at(p - o1), global1.error(p), 1e-5 * (1 + global1.error(p)));
  }
  // Q1 + Q2 at o1's origin: the sum of the two at every point.
  LocalQuadric merged = local1;
  merged.add(local2, o1 - o2);
  EXPECT_FLOAT_EQ(merged.weight, float(global1.weight + global2.weight));
  for (int i = 0; i < 20; ++i) {
    const Vec3 p = point();
    const double want = global1.error(p) + global2.error(p);
    EXPECT_NEAR(merged.error_at(p - o1), want, 1e-5 * (1 + want));
  }
}

// A vertex 10^4 units from the origin, on a plane, its neighbour 10^-3 off it: the error
// 10^-6 (squared distance) is kept to a few percent, where float32 terms of the global
// quadric (10^8 in size) could not hold it at all.
TEST(LocalQuadric, KeepsSmallErrorsFarFromTheOrigin) {
  const Vec3 vertex(1e4, 2e4, -1e4);
  const Vec3 n = unit(Vec3(1, 2, 3));
  LocalQuadric q;
  q.add_plane(n, vertex, 1.0, vertex);
  const Vec3 off = Vec3(0.3, -0.2, 0.1) * 1e-2;
  const Vec3 along = off - n * (n | off);  // in the plane: no error
  EXPECT_NEAR(q.error_at(along), 0.0, 1e-12);
  const Vec3 away = along + n * 1e-3;
  EXPECT_NEAR(q.error_at(away), 1e-6, 0.03e-6);
}

}  // namespace
}  // namespace pm
