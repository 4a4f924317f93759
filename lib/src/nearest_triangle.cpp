// Pruned nearest-triangle distances: see nearest_triangle.h (Ericson 2005, §5.1.3, §5.1.5).
#include "nearest_triangle.h"

#include <algorithm>
#include <limits>

namespace pm {

void BoxedTriangles::clear(std::size_t capacity) {
  size_ = 0;
  if (triangles_.size() >= capacity) return;
  triangles_.resize(capacity);
  for (auto& bound : box_) bound.resize(capacity);
  bound2_.resize(capacity);
}

void BoxedTriangles::add(const Vec3& a, const Vec3& b, const Vec3& c) {
  const std::size_t i = size_++;
  triangles_[i] = {{a, b, c}};
  // The sine of the smallest angle is twice the area over the product of the two longest
  // edges; below 1e-3 the triangle counts as thin (the longest edge squared stands in for
  // that product, which only makes more triangles thin).
  const double longest2 = std::max({(b - a).sqrnorm(), (c - b).sqrnorm(), (a - c).sqrnorm()});
  const bool thin = area_vector(a, b, c).sqrnorm() < 1e-6 * longest2 * longest2;
  constexpr float kInfinity = std::numeric_limits<float>::infinity();
  for (int k = 0; k < 3; ++k) {
    box_[k][i] = thin ? -kInfinity : float(std::min({a[k], b[k], c[k]}));
    box_[3 + k][i] = thin ? kInfinity : float(std::max({a[k], b[k], c[k]}));
  }
}

int BoxedTriangles::bound_all(const Vec3& x) {
  const std::size_t n = size_;
  const float *lx = box_[0].data(), *ly = box_[1].data(), *lz = box_[2].data();
  const float *hx = box_[3].data(), *hy = box_[4].data(), *hz = box_[5].data();
  const float x0 = float(x[0]), x1 = float(x[1]), x2 = float(x[2]);
  float* b2 = bound2_.data();
  for (std::size_t i = 0; i < n; ++i) {
    // At most one of the two terms per axis is positive.
    const float dx = std::max(lx[i] - x0, 0.0f) + std::max(x0 - hx[i], 0.0f);
    const float dy = std::max(ly[i] - x1, 0.0f) + std::max(x1 - hy[i], 0.0f);
    const float dz = std::max(lz[i] - x2, 0.0f) + std::max(x2 - hz[i], 0.0f);
    b2[i] = dx * dx + dy * dy + dz * dz;
  }
  std::size_t least = 0;
  for (std::size_t i = 1; i < n; ++i)
    if (b2[i] < b2[least]) least = i;
  return static_cast<int>(least);
}

double BoxedTriangles::nearest_distance(const Vec3& x, double stop, int* hint) {
  if (size_ == 0) return std::numeric_limits<double>::infinity();
  // The hint first: when it settles the question, the boxes need not be looked at.
  const int tried = hint && *hint >= 0 && *hint < size() ? *hint : -1;
  int nearest_at = tried;
  double nearest = tried >= 0 ? exact(tried, x) : std::numeric_limits<double>::infinity();
  if (nearest <= stop) return nearest;
  // Then the triangle of nearest box: most often the nearest triangle, so that the others'
  // boxes are mostly beyond it.
  const int least = bound_all(x);
  if (least != tried) {
    const double d = exact(least, x);
    if (d < nearest) nearest = d, nearest_at = least;
  }
  for (int i = 0; i < size() && nearest > stop; ++i) {
    if (i == least || i == tried || beyond(bound2_[i], nearest)) continue;
    const double d = exact(i, x);
    if (d < nearest) nearest = d, nearest_at = i;
  }
  if (hint) *hint = nearest_at;
  return nearest;
}

int BoxedTriangles::nearest(const Vec3& x, double* distance) {
  int best = bound_all(x);
  double nearest = exact(best, x);
  for (int i = 0; i < size(); ++i) {
    if (i == best || beyond(bound2_[i], nearest)) continue;
    const double d = exact(i, x);
    if (d < nearest || (d == nearest && i < best)) nearest = d, best = i;
  }
  *distance = nearest;
  return best;
}

}  // namespace pm
