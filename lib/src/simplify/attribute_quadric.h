// Attribute error as a quadric (Hoppe 1999, "New quadric metric for simplifying meshes
// with appearance attributes", §4; the same space as Garland and Heckbert 1998,
// "Simplifying surfaces with color and texture using quadric error metrics", §3).
//
// Each face carries its K attribute components (texture u, v; or a normal's x, y, z) as
// a linear function of position over its plane: a_j(p) = g_j . p + d_j, with g_j in the
// plane (Hoppe 1999, §4: the gradient from the 4x4 system of the three corners and the
// normal). A vertex whose attribute is s but which sits at p is off by a_j(p) - s_j on
// that face; the quadric sums area * sum_j (g_j . p + d_j - s_j)^2 over the faces of a
// wedge, as a quadratic form in x = (p, s) of dimension 3 + K, so that merging two
// wedges is adding their quadrics, as for the geometric one.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

#include "simplify/geometry.h"

namespace pm {

// Stored compactly (Hoppe 1999, §4): a face's attribute block, the K x K lower right of
// its matrix, is area * I (each component's row (g_j, -e_j) contributes 1 on its own
// diagonal and 0 elsewhere), so a sum of faces has weight * I there, with weight the sum
// of their areas, added in the same order. Only the geometric 3x3 block, the 3 x K cross
// block (-area * g_j summed), b, c and the weight are kept: 19 numbers for K = 2 and 23 for
// K = 3 instead of 22 and 29, and error() does the arithmetic of the full form (the
// dropped entries are exactly weight on the diagonal and zero off it).
//
// A quadric is about an origin: its form is in x = (p - origin, s), as local_quadric.h's
// geometric quadric is. Real = float halves its memory (the collapse loop keeps one per
// wedge: 160 MB of doubles on a 950K-face textured mesh) but is exact enough only about a
// nearby origin: the errors it measures are squares of small distances, which about a far
// origin are the difference of terms the size of the squared coordinates, and float's
// rounding of those is larger than they are. So the loop keeps each wedge's quadric about
// its own vertex (which a half-edge collapse never moves) and moves it to u's origin, in
// double, when v's wedge merges into u's (moved_origin()).
template <int K, typename Real = double>
struct AttributeQuadric {
  static constexpr int kDim = 3 + K;
  static constexpr double kRoundingFloor =
      std::numeric_limits<Real>::epsilon() * 64;  // float: 7.6e-6; double: 1.4e-14
  std::array<Real, 6> geometric{};    // upper triangle of the 3x3 block: xx xy xz yy yz zz
  std::array<Real, 3 * K> cross{};    // row r < 3, column 3 + j at cross[K * r + j]
  std::array<Real, kDim> b{};
  Real c = 0;
  Real weight = 0;  // total area (the attribute block's diagonal); the error's mean

  static constexpr int geometric_index(int i, int j) {  // i <= j < 3
    return i * 3 - i * (i - 1) / 2 + (j - i);
  }

  // The face (p[0], p[1], p[2]) whose corners carry values[i][0..K), weighted by its area.
  // A degenerate face contributes nothing: it has no gradient.
  static AttributeQuadric from_face(const Vec3 (&p)[3], const float* const (&values)[3],
                                    double area) {
    AttributeQuadric q;
    const Vec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
    const double g11 = e1 | e1, g12 = e1 | e2, g22 = e2 | e2;
    const double det = g11 * g22 - g12 * g12;  // |e1 x e2|^2
    if (!(det > 0) || !(area > 0)) return q;
    for (int j = 0; j < K; ++j) {
      // g = alpha e1 + beta e2 with g.e1 = a1 - a0 and g.e2 = a2 - a0: g lies in the plane.
      const double d1 = double(values[1][j]) - values[0][j];
      const double d2 = double(values[2][j]) - values[0][j];
      const double alpha = (g22 * d1 - g12 * d2) / det;
      const double beta = (g11 * d2 - g12 * d1) / det;
      const Vec3 g = alpha * e1 + beta * e2;
      const double d = values[0][j] - (g | p[0]);
      // (c . x + d)^2 with c = (g, -e_j): A += c c^T, b += d c, const += d^2. The terms
      // are those of the full (3 + K)-square form, in its order (a zero product added to a
      // sum leaves it as it was).
      for (int r = 0; r < 3; ++r) {
        if (g[r] == 0) continue;
        for (int s = r; s < 3; ++s) q.geometric[geometric_index(r, s)] += area * g[r] * g[s];
        // Column 3 + j alone: the other columns' terms are zeros, which would leave their
        // sums as they are (never -0: a sum starts at +0, and +0 + -0 is +0), but for an
        // infinite gradient, whose zero terms were NaN.
        q.cross[K * r + j] += area * g[r] * -1.0;
        q.b[r] += area * d * g[r];
      }
      q.b[3 + j] += area * d * -1.0;
      q.c += area * d * d;
    }
    q.weight = area;  // area * (-1) * (-1) on each attribute diagonal, exactly
    return q;
  }

  // Real's nearest value to x: float saturates at its largest finite value instead of
  // overflowing (a mesh 10^20 units across has face areas beyond float's range; the
  // encoder takes meshes up to 10^38 across); NaN stays NaN.
  static Real saturated(double x) {
    constexpr double top = std::numeric_limits<Real>::max();
    return static_cast<Real>(x > top ? top : x < -top ? -top : x);
  }

  template <typename From>
  AttributeQuadric& operator+=(const AttributeQuadric<K, From>& o) {
    for (int i = 0; i < 6; ++i) geometric[i] = saturated(geometric[i] + saturated(o.geometric[i]));
    for (int i = 0; i < 3 * K; ++i) cross[i] = saturated(cross[i] + saturated(o.cross[i]));
    for (int i = 0; i < kDim; ++i) b[i] = saturated(b[i] + saturated(o.b[i]));
    c = saturated(c + saturated(o.c));
    weight = saturated(weight + saturated(o.weight));
    return *this;
  }

  // The same form about origin + delta, in double: x = x' + (delta, 0) gives
  // b' = b + A (delta, 0) and c' = c + 2 b . (delta, 0) + (delta, 0)^T A (delta, 0), the
  // matrix A unchanged (the attribute block does not see a move in space).
  AttributeQuadric<K, double> moved_origin(const Vec3& delta) const {
    AttributeQuadric<K, double> q;
    for (int i = 0; i < 6; ++i) q.geometric[i] = geometric[i];
    for (int i = 0; i < 3 * K; ++i) q.cross[i] = cross[i];
    for (int i = 0; i < kDim; ++i) q.b[i] = b[i];
    q.weight = weight;
    double a_delta[kDim];
    q.c = shifted(delta, a_delta);
    for (int i = 0; i < kDim; ++i) q.b[i] += a_delta[i];
    return q;
  }

  // The move to origin + delta of moved_origin() and add_moved(): a_delta = A (delta, 0),
  // which b gains; returns c there.
  double shifted(const Vec3& delta, double (&a_delta)[kDim]) const {
    for (int i = 0; i < kDim; ++i) a_delta[i] = 0;
    for (int r = 0; r < 3; ++r) {
      for (int t = 0; t < 3; ++t) {
        const int at = r <= t ? geometric_index(r, t) : geometric_index(t, r);
        a_delta[r] += double(geometric[at]) * delta[t];
      }
      for (int k = 0; k < K; ++k) a_delta[3 + k] += double(cross[K * r + k]) * delta[r];
    }
    double moved_c = c;
    for (int r = 0; r < 3; ++r) moved_c += (2 * double(b[r]) + a_delta[r]) * delta[r];
    return moved_c;
  }

  // The parts of a face's quadric that do not depend on its origin, rounded to Real once
  // for the three corners it is added to (add_moved()).
  struct OriginFree {
    std::array<Real, 6> geometric;
    std::array<Real, 3 * K> cross;
    Real weight;
  };
  static OriginFree origin_free(const AttributeQuadric<K, double>& o) {
    OriginFree f;
    for (int i = 0; i < 6; ++i) f.geometric[i] = saturated(o.geometric[i]);
    for (int i = 0; i < 3 * K; ++i) f.cross[i] = saturated(o.cross[i]);
    f.weight = saturated(o.weight);
    return f;
  }
  // *this += o.moved_origin(delta), the same sums without the moved copy (the face's
  // three corners each add it about their own vertex: CornerAttributes' construction).
  // `fixed` is origin_free(o).
  void add_moved(const AttributeQuadric<K, double>& o, const OriginFree& fixed, const Vec3& delta) {
    double a_delta[kDim];
    const double moved_c = o.shifted(delta, a_delta);
    for (int i = 0; i < 6; ++i) geometric[i] = saturated(geometric[i] + fixed.geometric[i]);
    for (int i = 0; i < 3 * K; ++i) cross[i] = saturated(cross[i] + fixed.cross[i]);
    for (int i = 0; i < kDim; ++i) b[i] = saturated(b[i] + saturated(o.b[i] + a_delta[i]));
    c = saturated(c + saturated(moved_c));
    weight = saturated(weight + fixed.weight);
  }

  // Area-weighted sum of squared attribute deviations of the point p (about the origin)
  // carrying values s.
  double error(const Vec3& p, const float* s) const {
    double x[kDim] = {p[0], p[1], p[2]};
    for (int k = 0; k < K; ++k) x[3 + k] = s[k];
    double e = c, size = std::abs(e);  // size: the terms' magnitudes, for the floor below
    for (int r = 0; r < 3; ++r) {
      double row = double(geometric[geometric_index(r, r)]) * x[r];
      for (int t = r + 1; t < 3; ++t) row += 2 * double(geometric[geometric_index(r, t)]) * x[t];
      for (int k = 0; k < K; ++k) row += 2 * double(cross[K * r + k]) * x[3 + k];
      e += x[r] * row + 2 * double(b[r]) * x[r];
      size += std::abs(x[r] * row) + std::abs(2 * double(b[r]) * x[r]);
    }
    for (int k = 0; k < K; ++k) {
      const double row = double(weight) * x[3 + k];  // the attribute block's row: weight on its diagonal
      e += x[3 + k] * row + 2 * double(b[3 + k]) * x[3 + k];
      size += std::abs(x[3 + k] * row) + std::abs(2 * double(b[3 + k]) * x[3 + k]);
    }
    // Below the stored numbers' resolution an error is their rounding, not the surface's:
    // zero, as a double quadric would find it (an attribute linear over the faces).
    if (e <= kRoundingFloor * size) return 0;
    return e > 0 ? e : 0;  // rounding can make a zero error slightly negative
  }
};

}  // namespace pm
