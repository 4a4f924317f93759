// Metro-style measured error (Cignoni, Rocchini and Scopigno 1998, "Metro: measuring error
// on simplified surfaces"): §3 defines the one-sided distance E(S1, S2) as the maximum over
// points of S1 of their distance to S2, and the mean distance, both computed by sampling
// S1; the Hausdorff distance is the larger of the two one-sided ones. We sample every
// vertex plus Metro's "similar triangles" sampling of each face (the face cut into m x m
// copies of itself, one random point in each), and replace Metro's uniform grid by a
// bounding volume hierarchy with exact point-triangle distances (Ericson 2005, "Real-Time
// Collision Detection", §5.1.5, point_triangle_distance in geometry.h).
#include "pm/surface_distance.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include "geometry.h"

namespace pm {
namespace {

Vec3 vertex_position(const Mesh& mesh, uint32_t v) {
  return Vec3(mesh.positions[3 * std::size_t(v)], mesh.positions[3 * std::size_t(v) + 1],
              mesh.positions[3 * std::size_t(v) + 2]);
}

Status check_mesh(const Mesh& mesh, const char* role) {
  if (mesh.face_count() == 0)
    return Status(ErrorCode::kInvalidArgument, std::string(role) + " mesh has no faces");
  if (mesh.face_count() > std::numeric_limits<uint32_t>::max())
    return Status(ErrorCode::kResourceLimit, std::string(role) + " mesh has too many faces");
  const std::size_t vertex_count = mesh.vertex_count();
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    if (mesh.triangles[i] >= vertex_count) {
      return Status(ErrorCode::kInvalidArgument,
                    std::string(role) + " mesh: face " + std::to_string(i / 3) + " uses vertex " +
                        std::to_string(mesh.triangles[i]) + " of " + std::to_string(vertex_count));
    }
  }
  for (std::size_t i = 0; i < 3 * vertex_count; ++i) {
    if (!std::isfinite(mesh.positions[i])) {
      return Status(ErrorCode::kInvalidArgument, std::string(role) + " mesh: vertex " +
                                                     std::to_string(i / 3) +
                                                     " has a non-finite coordinate");
    }
  }
  return Status::ok();
}

double largest_coordinate(const Mesh& mesh) {
  double largest = 0;
  for (std::size_t i = 0; i < 3 * mesh.vertex_count(); ++i)
    largest = std::max(largest, std::abs(double(mesh.positions[i])));
  return largest;
}

// A bounding volume hierarchy over a mesh's triangles, for nearest-triangle queries.
// Built by median splits along the longest axis of the triangle centroids, so its depth is
// at most log2(faces) + 1 whatever the input.
class TriangleBvh {
 public:
  explicit TriangleBvh(const Mesh& mesh) {
    const std::size_t face_count = mesh.face_count();
    std::vector<uint32_t> order(face_count);
    std::vector<Vec3> centroids(face_count);
    for (std::size_t f = 0; f < face_count; ++f) {
      order[f] = uint32_t(f);
      centroids[f] = (vertex_position(mesh, mesh.triangles[3 * f]) +
                      vertex_position(mesh, mesh.triangles[3 * f + 1]) +
                      vertex_position(mesh, mesh.triangles[3 * f + 2])) /
                     3.0;
    }
    nodes_.reserve(face_count);  // leaves hold 2 to 4 triangles
    nodes_.emplace_back();
    split(0, 0, face_count, order, centroids, mesh);
    // The corners in leaf order, so that a leaf's triangles are contiguous in memory.
    corners_.reserve(3 * face_count);
    for (uint32_t f : order)
      for (int c = 0; c < 3; ++c)
        corners_.push_back(vertex_position(mesh, mesh.triangles[3 * f + c]));
  }

  // Distance from p to the nearest triangle. `hint` is a triangle (in this hierarchy's
  // order) likely to be near p, typically the previous query's answer: starting from its
  // distance prunes most of the tree at once. It is set to the nearest triangle found.
  // The result is the minimum over all triangles whatever the hint, so it is deterministic.
  double nearest(const Vec3& p, uint32_t& hint) const {
    double best = triangle_distance(p, hint);
    double best_squared = best * best;
    uint32_t stack[2 * kMaxDepth];
    int top = 0;
    if (box_distance_squared(nodes_[0], p) < best_squared) stack[top++] = 0;
    while (top > 0 && best > 0) {
      const Node& node = nodes_[stack[--top]];
      if (box_distance_squared(node, p) >= best_squared) continue;  // best improved since
      if (node.count > 0) {
        for (uint32_t t = node.first; t < node.first + node.count; ++t) {
          const double d = triangle_distance(p, t);
          if (d < best) {
            best = d;
            best_squared = d * d;
            hint = t;
          }
        }
        continue;
      }
      // Visit the nearer child first (pushed last), so the bound tightens sooner.
      uint32_t near_child = node.first, far_child = node.first + 1;
      double near_squared = box_distance_squared(nodes_[near_child], p);
      double far_squared = box_distance_squared(nodes_[far_child], p);
      if (far_squared < near_squared) {
        std::swap(near_child, far_child);
        std::swap(near_squared, far_squared);
      }
      if (far_squared < best_squared) stack[top++] = far_child;
      if (near_squared < best_squared) stack[top++] = near_child;
    }
    return best;
  }

 private:
  static constexpr std::size_t kLeafSize = 4;
  // Median splits halve the triangle count per level; uint32_t face indices bound it.
  static constexpr int kMaxDepth = 34;

  struct Node {
    double lo[3], hi[3];
    uint32_t first = 0;  // leaf: first triangle; inner node: left child (right is first + 1)
    uint32_t count = 0;  // triangles in a leaf; 0 for an inner node
  };

  double triangle_distance(const Vec3& p, uint32_t t) const {
    return point_triangle_distance(p, corners_[3 * t], corners_[3 * t + 1], corners_[3 * t + 2]);
  }

  static double box_distance_squared(const Node& node, const Vec3& p) {
    double sum = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const double outside = std::max({node.lo[axis] - p[axis], 0.0, p[axis] - node.hi[axis]});
      sum += outside * outside;
    }
    return sum;
  }

  void split(std::size_t node_index, std::size_t begin, std::size_t end,
             std::vector<uint32_t>& order, const std::vector<Vec3>& centroids, const Mesh& mesh) {
    Node node;
    double centroid_lo[3], centroid_hi[3];
    for (int axis = 0; axis < 3; ++axis) {
      node.lo[axis] = centroid_lo[axis] = std::numeric_limits<double>::infinity();
      node.hi[axis] = centroid_hi[axis] = -std::numeric_limits<double>::infinity();
    }
    for (std::size_t i = begin; i < end; ++i) {
      for (int c = 0; c < 3; ++c) {
        const Vec3 corner = vertex_position(mesh, mesh.triangles[3 * std::size_t(order[i]) + c]);
        for (int axis = 0; axis < 3; ++axis) {
          node.lo[axis] = std::min(node.lo[axis], corner[axis]);
          node.hi[axis] = std::max(node.hi[axis], corner[axis]);
        }
      }
      for (int axis = 0; axis < 3; ++axis) {
        centroid_lo[axis] = std::min(centroid_lo[axis], centroids[order[i]][axis]);
        centroid_hi[axis] = std::max(centroid_hi[axis], centroids[order[i]][axis]);
      }
    }
    if (end - begin <= kLeafSize) {
      node.first = uint32_t(begin);
      node.count = uint32_t(end - begin);
      nodes_[node_index] = node;
      return;
    }
    int axis = 0;
    for (int a = 1; a < 3; ++a)
      if (centroid_hi[a] - centroid_lo[a] > centroid_hi[axis] - centroid_lo[axis]) axis = a;
    const std::size_t middle = begin + (end - begin) / 2;
    std::nth_element(
        order.begin() + begin, order.begin() + middle, order.begin() + end,
        [&](uint32_t x, uint32_t y) { return centroids[x][axis] < centroids[y][axis]; });
    node.first = uint32_t(nodes_.size());
    nodes_[node_index] = node;
    nodes_.emplace_back();
    nodes_.emplace_back();
    split(node.first, begin, middle, order, centroids, mesh);
    split(node.first + 1, middle, end, order, centroids, mesh);
  }

  std::vector<Node> nodes_;
  std::vector<Vec3> corners_;  // three per triangle, in leaf order
};

// SplitMix64 (Steele, Lea and Flood 2014): tiny, seedable per chunk, and the same numbers
// on every platform, which std::uniform_real_distribution does not promise.
class Random {
 public:
  explicit Random(uint64_t seed) : state_(seed) {}
  double uniform() {  // in [0, 1)
    uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return double((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  }

 private:
  uint64_t state_;
};

// One direction's statistics, over a chunk of faces or a whole mesh.
struct OneWay {
  double max = 0, sum_squared = 0;
  std::size_t count = 0;

  void add(double distance) {
    max = std::max(max, distance);
    sum_squared += distance * distance;
    ++count;
  }
  void merge(const OneWay& other) {
    max = std::max(max, other.max);
    sum_squared += other.sum_squared;
    count += other.count;
  }
  double rms() const { return count == 0 ? 0 : std::sqrt(sum_squared / double(count)); }
};

// Faces are measured in fixed chunks, each with its own random stream, and the chunks'
// sums added in chunk order: the result does not depend on how threads share the chunks.
constexpr std::size_t kFacesPerChunk = 1024;

class OneWayMeasurement {
 public:
  OneWayMeasurement(const Mesh& from, const TriangleBvh& to, const DistanceOptions& options,
                    uint64_t stream, double noise_floor)
      : from_(from), to_(to), options_(options), stream_(stream), noise_floor_(noise_floor) {
    // Each vertex is sampled once, with the first face that uses it.
    first_face_.assign(from.vertex_count(), std::numeric_limits<uint32_t>::max());
    for (std::size_t i = from.triangles.size(); i-- > 0;)
      first_face_[from.triangles[i]] = uint32_t(i / 3);
    double total_area = 0;
    for (std::size_t f = 0; f < from.face_count(); ++f) total_area += face_area(f);
    mean_area_ = total_area / double(from.face_count());
  }

  OneWay run(unsigned threads) {
    const std::size_t chunk_count = (from_.face_count() + kFacesPerChunk - 1) / kFacesPerChunk;
    chunks_.assign(chunk_count, OneWay());
    next_chunk_ = 0;
    std::vector<std::thread> workers;
    try {
      for (unsigned i = 1; i < std::min<std::size_t>(threads, chunk_count); ++i)
        workers.emplace_back([this] { work(); });
    } catch (const std::system_error&) {
      // No more threads to be had: the ones running and this one share the work.
    }
    work();
    for (std::thread& worker : workers) worker.join();
    OneWay total;
    for (const OneWay& chunk : chunks_) total.merge(chunk);
    return total;
  }

 private:
  double face_area(std::size_t f) const {
    const Vec3 a = vertex_position(from_, from_.triangles[3 * f]);
    return 0.5 * area_vector(a, vertex_position(from_, from_.triangles[3 * f + 1]),
                             vertex_position(from_, from_.triangles[3 * f + 2]))
                     .norm();
  }

  void work() {
    uint32_t hint = 0;
    for (std::size_t chunk; (chunk = next_chunk_.fetch_add(1)) < chunks_.size();)
      chunks_[chunk] = measure_chunk(chunk, hint);
  }

  OneWay measure_chunk(std::size_t chunk, uint32_t& hint) const {
    Random random(stream_ ^ (uint64_t(chunk) * 0xd1342543de82ef95ULL));
    OneWay result;
    auto measure = [&](const Vec3& p) {
      const double d = to_.nearest(p, hint);
      // Below this the distance is the rounding of the sample's own construction (a point
      // on a face shared by both meshes comes out ~1e-17 away), not a geometric error.
      result.add(d <= noise_floor_ ? 0.0 : d);
    };
    const std::size_t end = std::min(from_.face_count(), (chunk + 1) * kFacesPerChunk);
    for (std::size_t f = chunk * kFacesPerChunk; f < end; ++f) {
      const uint32_t* corner = &from_.triangles[3 * f];
      for (int c = 0; c < 3; ++c) {
        const bool repeated =
            (c > 0 && corner[c] == corner[0]) || (c == 2 && corner[2] == corner[1]);
        if (first_face_[corner[c]] == f && !repeated) measure(vertex_position(from_, corner[c]));
      }
      // At least samples_per_face points, more on faces larger than the mean, so that the
      // sampling density never falls below the mean's.
      double wanted = options_.samples_per_face;
      if (mean_area_ > 0) wanted = std::max(wanted, wanted * face_area(f) / mean_area_);
      const auto m = std::size_t(std::ceil(std::sqrt(wanted)));
      const Vec3 a = vertex_position(from_, corner[0]);
      const Vec3 ab = (vertex_position(from_, corner[1]) - a) / double(m);
      const Vec3 ac = (vertex_position(from_, corner[2]) - a) / double(m);
      // The face is cut into m x m similar triangles, in (u, v) steps of ab and ac: for each
      // grid point (i, j) an upward cell (i, j), (i+1, j), (i, j+1), and, except along the
      // far edge, a downward one (i+1, j), (i, j+1), (i+1, j+1). One random point in each.
      auto sample_cell = [&](std::size_t i, std::size_t j, bool downward) {
        double r1 = random.uniform(), r2 = random.uniform();
        if (r1 + r2 > 1) {  // fold the unit square onto the unit triangle, uniformly
          r1 = 1 - r1;
          r2 = 1 - r2;
        }
        const double u = downward ? double(i + 1) - r1 : double(i) + r1;
        const double v = downward ? double(j) + r1 + r2 : double(j) + r2;
        measure(a + ab * u + ac * v);
      };
      for (std::size_t i = 0; i < m; ++i) {
        for (std::size_t j = 0; i + j < m; ++j) {
          sample_cell(i, j, false);
          if (i + j + 2 <= m) sample_cell(i, j, true);
        }
      }
    }
    return result;
  }

  const Mesh& from_;
  const TriangleBvh& to_;
  const DistanceOptions& options_;
  const uint64_t stream_;
  const double noise_floor_;
  std::vector<uint32_t> first_face_;
  double mean_area_ = 0;
  std::vector<OneWay> chunks_;
  std::atomic<std::size_t> next_chunk_{0};
};

}  // namespace

Status measure_surface_distance(const Mesh& reference, const Mesh& other,
                                const DistanceOptions& options, SurfaceDistance& out) {
  if (!(options.samples_per_face >= 1) || !std::isfinite(options.samples_per_face))
    return Status(ErrorCode::kInvalidArgument, "samples per face must be a number of at least 1");
  if (Status s = check_mesh(reference, "reference"); !s) return s;
  if (Status s = check_mesh(other, "other"); !s) return s;

  unsigned threads = options.threads;
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  // Double-precision rounding in building a sample and its closest point is a few units
  // in the last place of the coordinates; 1e-12 of the largest one is far above that and
  // far below float32 input resolution (6e-8).
  const double noise_floor =
      1e-12 * std::max(largest_coordinate(reference), largest_coordinate(other));

  OneWay forward, backward;
  {
    const TriangleBvh other_bvh(other);
    forward = OneWayMeasurement(reference, other_bvh, options, options.seed * 2 + 0, noise_floor)
                  .run(threads);
  }
  {
    const TriangleBvh reference_bvh(reference);
    backward = OneWayMeasurement(other, reference_bvh, options, options.seed * 2 + 1, noise_floor)
                   .run(threads);
  }
  SurfaceDistance result;
  result.forward_max = forward.max;
  result.forward_rms = forward.rms();
  result.backward_max = backward.max;
  result.backward_rms = backward.rms();
  result.hausdorff = std::max(forward.max, backward.max);
  OneWay both = forward;
  both.merge(backward);
  result.rms = both.rms();
  result.samples = both.count;
  result.diagonal = bounding_box_diagonal(reference.positions);
  out = result;
  return Status::ok();
}

double bounding_box_diagonal(const std::vector<float>& positions) {
  if (positions.size() < 3) return 0;
  double lo[3], hi[3];
  for (int axis = 0; axis < 3; ++axis) lo[axis] = hi[axis] = positions[axis];
  for (std::size_t i = 0; i < positions.size() / 3 * 3; ++i) {
    lo[i % 3] = std::min(lo[i % 3], double(positions[i]));
    hi[i % 3] = std::max(hi[i % 3], double(positions[i]));
  }
  return std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                   (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

}  // namespace pm
