// Quadric error metric (Garland and Heckbert 1997, "Surface simplification using quadric
// error metrics", §5): the sum of squared distances to a set of planes, as a symmetric
// 4x4 matrix, so that merging two vertices' plane sets is adding their matrices.
#pragma once

#include "simplify/geometry.h"

namespace pm {

struct Quadric {
  // Upper triangle of [A b; b^T c] for planes n.x + d = 0: A = sum w n n^T, b = sum w d n,
  // c = sum w d^2. weight = sum w, to turn the error into a mean squared distance.
  double a00 = 0, a01 = 0, a02 = 0, a11 = 0, a12 = 0, a22 = 0;
  double b0 = 0, b1 = 0, b2 = 0, c = 0;
  double weight = 0;

  // The plane through `point` with unit normal n, weighted by w (Garland and Heckbert
  // 1997, §5: "fundamental error quadric" K_p, here area-weighted as in §6.1).
  static Quadric from_plane(const Vec3& n, const Vec3& point, double w) {
    const double d = -(n | point);
    Quadric q;
    q.a00 = w * n[0] * n[0], q.a01 = w * n[0] * n[1], q.a02 = w * n[0] * n[2];
    q.a11 = w * n[1] * n[1], q.a12 = w * n[1] * n[2], q.a22 = w * n[2] * n[2];
    q.b0 = w * d * n[0], q.b1 = w * d * n[1], q.b2 = w * d * n[2];
    q.c = w * d * d;
    q.weight = w;
    return q;
  }

  Quadric& operator+=(const Quadric& o) {
    a00 += o.a00, a01 += o.a01, a02 += o.a02, a11 += o.a11, a12 += o.a12, a22 += o.a22;
    b0 += o.b0, b1 += o.b1, b2 += o.b2, c += o.c, weight += o.weight;
    return *this;
  }
  friend Quadric operator+(Quadric a, const Quadric& b) { return a += b; }

  // Weighted sum of squared distances from p to the planes: p^T A p + 2 b.p + c.
  double error(const Vec3& p) const {
    const double x = p[0], y = p[1], z = p[2];
    const double e = x * (a00 * x + 2 * (a01 * y + a02 * z + b0)) +
                     y * (a11 * y + 2 * (a12 * z + b1)) + z * (a22 * z + 2 * b2) + c;
    return e > 0 ? e : 0;  // rounding can make a zero error slightly negative
  }
};

}  // namespace pm
