// Garland and Heckbert 1997's quadric error (§5; quadric.h) in float32, relative to an origin
// of its own: the position of the vertex it belongs to. Q(o + d) = d^T A d + 2 b.d + c, so b
// and c describe the planes as seen from o (b = A o + b_global, c = Q(o)), and every term is
// of the size of the local error, not of the coordinates: float32 then keeps the order of
// small errors far from the origin, where a global float32 quadric would round them away
// (its terms grow with the squared distance to the origin and cancel). Half the memory of
// the double quadric, which is what the collapse loop's cache misses are made of.
#pragma once

#include "simplify/geometry.h"

namespace pm {

struct LocalQuadric {
  float a00 = 0, a01 = 0, a02 = 0, a11 = 0, a12 = 0, a22 = 0;
  float b0 = 0, b1 = 0, b2 = 0, c = 0;
  float weight = 0;

  // Adds the plane through `point` with unit normal n, weighted by w (§5, "fundamental error
  // quadric"), for the origin `origin`.
  void add_plane(const Vec3& n, const Vec3& point, double w, const Vec3& origin) {
    const double s = n | (origin - point);  // the origin's signed distance to the plane
    a00 = float(a00 + w * n[0] * n[0]), a01 = float(a01 + w * n[0] * n[1]);
    a02 = float(a02 + w * n[0] * n[2]), a11 = float(a11 + w * n[1] * n[1]);
    a12 = float(a12 + w * n[1] * n[2]), a22 = float(a22 + w * n[2] * n[2]);
    b0 = float(b0 + w * s * n[0]), b1 = float(b1 + w * s * n[1]), b2 = float(b2 + w * s * n[2]);
    c = float(c + w * s * s);
    weight = float(weight + w);
  }

  // The weighted sum of squared distances to the planes at origin + d.
  double error_at(const Vec3& d) const {
    const double x = d[0], y = d[1], z = d[2];
    const double e = x * (a00 * x + 2 * (a01 * y + a02 * z + double(b0))) +
                     y * (a11 * y + 2 * (a12 * z + double(b1))) + z * (a22 * z + 2 * double(b2)) +
                     c;
    return e > 0 ? e : 0;  // rounding can make a zero error slightly negative
  }

  // Q1 + Q2 (§4): adds q, moved first to this quadric's origin; delta = this origin minus
  // q's origin.
  void add(const LocalQuadric& q, const Vec3& delta) {
    const double dx = delta[0], dy = delta[1], dz = delta[2];
    // q's b at the new origin: b + A delta; its c: q's error there.
    const double qb0 = q.b0 + q.a00 * dx + q.a01 * dy + q.a02 * dz;
    const double qb1 = q.b1 + q.a01 * dx + q.a11 * dy + q.a12 * dz;
    const double qb2 = q.b2 + q.a02 * dx + q.a12 * dy + q.a22 * dz;
    const double qc = q.error_at(delta);
    a00 += q.a00, a01 += q.a01, a02 += q.a02, a11 += q.a11, a12 += q.a12, a22 += q.a22;
    b0 = float(b0 + qb0), b1 = float(b1 + qb1), b2 = float(b2 + qb2);
    c = float(c + qc);
    weight += q.weight;
  }
};

}  // namespace pm
