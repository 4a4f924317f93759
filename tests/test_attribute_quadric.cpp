// Hoppe 1999's attribute quadric (lib/src/simplify/attribute_quadric.h) about an origin of
// its own: moving the origin keeps the form, and float32 about the wedge's vertex measures
// what double measures, far from the coordinates' origin too.
#include <gtest/gtest.h>

#include <cmath>

#include "simplify/attribute_quadric.h"

namespace pm {
namespace {

// A triangle 10^4 units from the origin, with texture coordinates that are not linear in
// position over it (so errors away from a corner are not zero).
struct Face {
  Vec3 p[3] = {Vec3(10000.0, 20000.0, -5000.0), Vec3(10001.5, 20000.25, -5000.0),
               Vec3(10000.25, 20001.0, -4999.5)};
  float uv[3][2] = {{0.25f, 0.5f}, {0.75f, 0.5f}, {0.25f, 0.875f}};
  AttributeQuadric<2> quadric() const {
    const float* values[3] = {uv[0], uv[1], uv[2]};
    return AttributeQuadric<2>::from_face(p, values, 1.25);
  }
};

TEST(AttributeQuadric, MovingTheOriginKeepsTheForm) {
  const Face face;
  const AttributeQuadric<2> about_zero = face.quadric();
  const Vec3 delta = face.p[1];
  const AttributeQuadric<2> about_p1 = about_zero.moved_origin(delta);
  const Vec3 at = face.p[1] + Vec3(0.125, -0.25, 0.0625);
  const float s[2] = {0.5f, 0.625f};
  const double expected = about_zero.error(at, s);
  ASSERT_GT(expected, 0.0);
  // Within double's rounding of the form about zero, whose terms are 10^8 times larger than
  // the error they cancel to (why the loop keeps quadrics about their vertex).
  EXPECT_NEAR(about_p1.error(at - delta, s), expected, 1e-7 * expected);
  // And back: the same form about zero.
  EXPECT_NEAR(about_p1.moved_origin(-1.0 * delta).error(at, s), expected, 1e-7 * expected);
}

TEST(AttributeQuadric, FloatAboutTheVertexMeasuresWhatDoubleMeasures) {
  const Face face;
  const AttributeQuadric<2> exact = face.quadric();
  AttributeQuadric<2, float> about_p0;
  about_p0 += exact.moved_origin(face.p[0]);
  // A corner's own value at its own position: zero, exactly (no rounding residue).
  EXPECT_EQ(about_p0.error(Vec3(0, 0, 0), face.uv[0]), 0.0);
  // Elsewhere: the double's error within float's precision of the terms.
  const Vec3 at = face.p[0] + Vec3(0.5, 0.25, 0.0);
  const float s[2] = {0.375f, 0.5f};
  const double expected = exact.error(at, s);
  ASSERT_GT(expected, 0.0);
  EXPECT_NEAR(about_p0.error(at - face.p[0], s), expected, 1e-4 * expected);
}

TEST(AttributeQuadric, MergingAcrossOriginsAddsTheForms) {
  // Two wedges' quadrics, each about its own vertex, merged about the second's (as a
  // collapse merges v's wedge into u's): the sum of the two double forms.
  const Face face;
  const AttributeQuadric<2> exact = face.quadric();
  AttributeQuadric<2, float> v_wedge, u_wedge;
  v_wedge += exact.moved_origin(face.p[0]);
  u_wedge += exact.moved_origin(face.p[1]);
  u_wedge += v_wedge.moved_origin(face.p[1] - face.p[0]);
  const Vec3 at = face.p[1] + Vec3(-0.25, 0.5, 0.125);
  const float s[2] = {0.625f, 0.75f};
  const double expected = 2 * exact.error(at, s);
  EXPECT_NEAR(u_wedge.error(at - face.p[1], s), expected, 1e-4 * expected);
  EXPECT_DOUBLE_EQ(u_wedge.weight, 2 * 1.25);
}

}  // namespace
}  // namespace pm
