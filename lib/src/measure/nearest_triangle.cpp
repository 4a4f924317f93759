// Pruned nearest-triangle distances: see nearest_triangle.h (Ericson 2005, §5.1.3, §5.1.5).
#include "measure/nearest_triangle.h"

#include <algorithm>
#include <limits>

namespace pm {

void BoxedTriangles::clear(std::size_t capacity) {
  size_ = 0;
  chunks_ready_ = false;
  if (triangles_.size() >= capacity) return;
  triangles_.resize(capacity);
  for (auto& bound : box_) bound.resize(capacity);
  bound2_.resize(capacity);
}

bool BoxedTriangles::is_thin(const Vec3& a, const Vec3& b, const Vec3& c) {
  // The sine of the smallest angle is twice the area over the product of the two longest
  // edges (the longest edge squared stands in for that product, which only makes more
  // triangles thin).
  const double longest2 = std::max({(b - a).sqrnorm(), (c - b).sqrnorm(), (a - c).sqrnorm()});
  return area_vector(a, b, c).sqrnorm() < 1e-6 * longest2 * longest2;
}

void BoxedTriangles::add(const Vec3& a, const Vec3& b, const Vec3& c, bool thin) {
  const std::size_t i = size_++;
  chunks_ready_ = false;
  triangles_[i] = {{a, b, c}};
  constexpr float kInfinity = std::numeric_limits<float>::infinity();
  for (int k = 0; k < 3; ++k) {
    box_[k][i] = thin ? -kInfinity : float(std::min({a[k], b[k], c[k]}));
    box_[3 + k][i] = thin ? kInfinity : float(std::max({a[k], b[k], c[k]}));
  }
}

namespace {

// Squared distances from x to boxes [begin, end) (arrays per bound: x, y, z low then high)
// into b2[begin, end); returns the index of the least.
std::size_t bound_range(const std::vector<float> (&box)[6], const Vec3& x, std::size_t begin,
                        std::size_t end, float* b2) {
  const float *lx = box[0].data(), *ly = box[1].data(), *lz = box[2].data();
  const float *hx = box[3].data(), *hy = box[4].data(), *hz = box[5].data();
  const float x0 = float(x[0]), x1 = float(x[1]), x2 = float(x[2]);
  for (std::size_t i = begin; i < end; ++i) {
    // At most one of the two terms per axis is positive.
    const float dx = std::max(lx[i] - x0, 0.0f) + std::max(x0 - hx[i], 0.0f);
    const float dy = std::max(ly[i] - x1, 0.0f) + std::max(x1 - hy[i], 0.0f);
    const float dz = std::max(lz[i] - x2, 0.0f) + std::max(x2 - hz[i], 0.0f);
    b2[i] = dx * dx + dy * dy + dz * dz;
  }
  std::size_t least = begin;
  for (std::size_t i = begin + 1; i < end; ++i)
    if (b2[i] < b2[least]) least = i;
  return least;
}

}  // namespace

int BoxedTriangles::bound_all(const Vec3& x) {
  return static_cast<int>(bound_range(box_, x, 0, size_, bound2_.data()));
}

void BoxedTriangles::make_chunks() {
  const std::size_t chunks = (size_ + kChunk - 1) / kChunk;
  for (int k = 0; k < 6; ++k) chunk_box_[k].resize(chunks);
  chunk_bound2_.resize(chunks);
  for (std::size_t j = 0; j < chunks; ++j) {
    const std::size_t begin = j * kChunk, end = std::min(size_, begin + kChunk);
    for (int k = 0; k < 3; ++k) {
      chunk_box_[k][j] = *std::min_element(&box_[k][begin], &box_[k][0] + end);
      chunk_box_[3 + k][j] = *std::max_element(&box_[3 + k][begin], &box_[3 + k][0] + end);
    }
  }
  chunks_ready_ = true;
}

void BoxedTriangles::search(const Vec3& x, std::size_t begin, std::size_t end, double stop,
                            int tried, double& nearest, int& nearest_at) {
  // The triangle of nearest box first: most often the nearest triangle, so that the
  // others' boxes are mostly beyond it.
  const int least = static_cast<int>(bound_range(box_, x, begin, end, bound2_.data()));
  if (least != tried && !beyond(bound2_[least], nearest)) {
    const double d = exact(least, x);
    if (d < nearest) nearest = d, nearest_at = least;
  }
  for (int i = int(begin); i < int(end) && nearest > stop; ++i) {
    if (i == least || i == tried || beyond(bound2_[i], nearest)) continue;
    const double d = exact(i, x);
    if (d < nearest) nearest = d, nearest_at = i;
  }
}

double BoxedTriangles::nearest_distance(const Vec3& x, double stop, int* hint) {
  if (size_ == 0) return std::numeric_limits<double>::infinity();
  // The hint first: when it settles the question, the boxes need not be looked at.
  const int tried = hint && *hint >= 0 && *hint < size() ? *hint : -1;
  int nearest_at = tried;
  double nearest = tried >= 0 ? exact(tried, x) : std::numeric_limits<double>::infinity();
  if (nearest <= stop) return nearest;
  if (size_ <= 2 * kChunk) {
    search(x, 0, size_, stop, tried, nearest, nearest_at);
  } else {
    // Many triangles (late in the simplification a region holds thousands): the chunks'
    // boxes first, the nearest chunk searched first, then any other chunk not beyond.
    if (!chunks_ready_) make_chunks();
    const std::size_t chunks = chunk_bound2_.size();
    const std::size_t first = bound_range(chunk_box_, x, 0, chunks, chunk_bound2_.data());
    search(x, first * kChunk, std::min(size_, (first + 1) * kChunk), stop, tried, nearest,
           nearest_at);
    for (std::size_t j = 0; j < chunks && nearest > stop; ++j)
      if (j != first && !beyond(chunk_bound2_[j], nearest))
        search(x, j * kChunk, std::min(size_, (j + 1) * kChunk), stop, tried, nearest,
               nearest_at);
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
