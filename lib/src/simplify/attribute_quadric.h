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
#include <cstddef>

#include "simplify/geometry.h"

namespace pm {

// Stored compactly (Hoppe 1999, §4): a face's attribute block, the K x K lower right of
// its matrix, is area * I (each component's row (g_j, -e_j) contributes 1 on its own
// diagonal and 0 elsewhere), so a sum of faces has weight * I there, with weight the sum
// of their areas, added in the same order. Only the geometric 3x3 block, the 3 x K cross
// block (-area * g_j summed), b, c and the weight are kept: 19 doubles for K = 2 and 23 for
// K = 3 instead of 22 and 29, and error() does the arithmetic of the full form (the
// dropped entries are exactly weight on the diagonal and zero off it).
template <int K>
struct AttributeQuadric {
  static constexpr int kDim = 3 + K;
  std::array<double, 6> geometric{};    // upper triangle of the 3x3 block: xx xy xz yy yz zz
  std::array<double, 3 * K> cross{};    // row r < 3, column 3 + j at cross[K * r + j]
  std::array<double, kDim> b{};
  double c = 0;
  double weight = 0;  // total area (the attribute block's diagonal); the error's mean

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
        for (int k = 0; k < K; ++k) q.cross[K * r + k] += area * g[r] * (k == j ? -1.0 : 0.0);
        q.b[r] += area * d * g[r];
      }
      q.b[3 + j] += area * d * -1.0;
      q.c += area * d * d;
    }
    q.weight = area;  // area * (-1) * (-1) on each attribute diagonal, exactly
    return q;
  }

  AttributeQuadric& operator+=(const AttributeQuadric& o) {
    for (int i = 0; i < 6; ++i) geometric[i] += o.geometric[i];
    for (int i = 0; i < 3 * K; ++i) cross[i] += o.cross[i];
    for (int i = 0; i < kDim; ++i) b[i] += o.b[i];
    c += o.c;
    weight += o.weight;
    return *this;
  }

  // Area-weighted sum of squared attribute deviations of the point p carrying values s.
  double error(const Vec3& p, const float* s) const {
    double x[kDim] = {p[0], p[1], p[2]};
    for (int k = 0; k < K; ++k) x[3 + k] = s[k];
    double e = c;
    for (int r = 0; r < 3; ++r) {
      double row = geometric[geometric_index(r, r)] * x[r];
      for (int t = r + 1; t < 3; ++t) row += 2 * geometric[geometric_index(r, t)] * x[t];
      for (int k = 0; k < K; ++k) row += 2 * cross[K * r + k] * x[3 + k];
      e += x[r] * row + 2 * b[r] * x[r];
    }
    for (int k = 0; k < K; ++k) {
      const double row = weight * x[3 + k];  // the attribute block's row: weight on its diagonal
      e += x[3 + k] * row + 2 * b[3 + k] * x[3 + k];
    }
    return e > 0 ? e : 0;  // rounding can make a zero error slightly negative
  }
};

}  // namespace pm
