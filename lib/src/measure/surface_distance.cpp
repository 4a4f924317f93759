// Metro-style measured error (Cignoni, Rocchini and Scopigno 1998, "Metro: measuring error
// on simplified surfaces"): §3 defines the one-sided distance E(S1, S2) as the maximum over
// points of S1 of their distance to S2, and the mean distance, both computed by sampling
// S1; the Hausdorff distance is the larger of the two one-sided ones. We sample every
// vertex plus Metro's "similar triangles" sampling of each face (the face cut into m x m
// copies of itself, one random point in each), and measure each sample's exact distance to
// the nearest triangle of the other mesh (Ericson 2005, "Real-Time Collision Detection",
// §5.1.5, point_triangle_distance in geometry.h), found through a bounding volume hierarchy
// instead of Metro's uniform grid.
//
// What makes it fast, each step keeping the answer exact:
// - the hierarchy is 4-wide (Wald, Benthin and Boulos 2008, "Getting rid of packets";
//   Dammertz et al. 2008, "Shallow bounding volume hierarchies for fast SIMD ray tracing
//   of incoherent rays") with float32 boxes tested four at a time, built in linear time
//   from Morton codes (Lauterbach et al. 2009, "Fast BVH construction on GPUs");
// - leaves hold four triangles as float32 bounding planes, a lower bound on the distance
//   to each that is exact but at corners: the double-precision distance is computed only
//   for triangles that may beat the best so far;
// - faces are measured in Morton order, so that consecutive queries touch the same part of
//   the hierarchy, and per face: the triangles that can be nearest to any point of a small
//   face are found once (usually one to four), the samples test only those;
// - both hierarchies are built at once on two threads, overlapping the first measurement;
// - the sums of squares are exact (Neal 2015), so the order of the work does not matter.
#include "pm/surface_distance.h"
#include "core/no_throw.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <exception>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/in_turn.h"
#include "measure/triangle_bvh.h"
#include "simplify/geometry.h"

namespace pm {
namespace {

using measure::morton_keys;
using measure::TriangleBvh;
using measure::vertex_position;

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

// SplitMix64 (Steele, Lea and Flood 2014): tiny, seedable per chunk, and the same numbers
// on every platform, which std::uniform_real_distribution does not promise.
class Random {
 public:
  // The stream of `seed`, from its `position`-th number on (0 for the first): each number
  // depends only on the seed and its position, so a face's numbers can be drawn in any order.
  Random(uint64_t seed, uint64_t position) : state_(seed + position * kStep) {}
  double uniform() {  // in [0, 1)
    uint64_t z = (state_ += kStep);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return double((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  }

 private:
  static constexpr uint64_t kStep = 0x9e3779b97f4a7c15ULL;
  uint64_t state_;
};

// The exact sum of non-negative doubles, rounded once at the end, so that it does not depend
// on the order of the terms: a fixed-point accumulator over the whole double range (a
// "superaccumulator", Neal 2015, "Fast exact summation using small and large
// superaccumulators"). A double is m 2^(p - 1074) with a 53-bit integer m and 0 <= p <= 2045;
// m shifted by p goes into 32-bit digits, each held in 64 bits, which leaves room for 2^31
// additions between carries.
class ExactSum {
 public:
  void add(double x) {  // x >= 0 and finite
    uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    const auto exponent = int(bits >> 52 & 0x7ff);
    uint64_t mantissa = bits & ((uint64_t(1) << 52) - 1);
    int position = 0;    // of the mantissa's lowest bit, above 2^-1074
    if (exponent > 0) {  // normal: the leading 1 is implicit
      mantissa |= uint64_t(1) << 52;
      position = exponent - 1;
    }
    if (mantissa == 0) return;
    const int digit = position / 32, shift = position % 32;
    const uint64_t low = mantissa << shift, high = shift == 0 ? 0 : mantissa >> (64 - shift);
    digits_[digit] += low & 0xffffffff;
    digits_[digit + 1] += low >> 32;
    digits_[digit + 2] += high;
    if (++pending_ == kMaxPending) carry();
  }

  void add(const ExactSum& other) {
    ExactSum term = other;
    term.carry();
    carry();
    for (int i = 0; i < kDigits; ++i) digits_[i] += term.digits_[i];
    pending_ = 2;
  }

  // The sum rounded to the nearest double, ties to even.
  double value() const {
    ExactSum sum = *this;
    sum.carry();
    int top = kDigits - 1;
    while (top >= 0 && sum.digits_[top] == 0) --top;
    if (top < 0) return 0;
    if (top < 2 && (top == 0 || sum.digits_[1] < (uint64_t(1) << 21))) {
      // Below 2^53 units of 2^-1074: exact as a double (subnormal or not).
      return std::ldexp(double(sum.digits_[1] << 32 | sum.digits_[0]), -1074);
    }
    // The top 64 bits, the highest set bit first, and whether any bit below them is set.
    const uint64_t first = sum.digits_[top], second = sum.digits_[top - 1],
                   third = top >= 2 ? sum.digits_[top - 2] : 0;
    int leading = 0;  // zeros above `first`'s highest set bit, in its 32 bits
    while (!(first << leading & 0x80000000)) ++leading;
    uint64_t window = (first << 32 | second) << leading;
    bool sticky = false;
    if (leading > 0) {
      window |= third >> (32 - leading);
      sticky = (third & ((uint64_t(1) << (32 - leading)) - 1)) != 0;
    } else {
      sticky = third != 0;
    }
    for (int i = 0; i < top - 2; ++i) sticky = sticky || sum.digits_[i] != 0;
    int highest = 32 * top + 31 - leading;  // position of the leading bit
    uint64_t mantissa = window >> 11;
    const bool round = (window >> 10 & 1) != 0;
    sticky = sticky || (window & 0x3ff) != 0;
    if (round && (sticky || (mantissa & 1))) {
      if (++mantissa == uint64_t(1) << 53) {
        mantissa >>= 1;
        ++highest;
      }
    }
    return std::ldexp(double(mantissa), highest - 52 - 1074);
  }

 private:
  static constexpr int kDigits = 66;  // 2045 + 84 bits, 32 to a digit
  static constexpr uint32_t kMaxPending = uint32_t(1) << 31;

  // Leaves every digit but the last below 2^32.
  void carry() {
    for (int i = 0; i + 1 < kDigits; ++i) {
      digits_[i + 1] += digits_[i] >> 32;
      digits_[i] &= 0xffffffff;
    }
    pending_ = 0;
  }

  uint64_t digits_[kDigits] = {};
  uint32_t pending_ = 0;
};

// One direction's statistics, over some faces or a whole mesh.
struct OneWay {
  double max = 0;
  ExactSum sum_squared;
  std::size_t count = 0;

  void add(double distance) {
    max = std::max(max, distance);
    sum_squared.add(distance * distance);
    ++count;
  }
  void merge(const OneWay& other) {
    max = std::max(max, other.max);
    sum_squared.add(other.sum_squared);
    count += other.count;
  }
  double rms() const { return count == 0 ? 0 : std::sqrt(sum_squared.value() / double(count)); }
};

// Closed until opened, once; threads wait for it to open.
class Gate {
 public:
  void open() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      open_ = true;
    }
    opened_.notify_all();
  }
  void wait() {
    std::unique_lock<std::mutex> lock(mutex_);
    opened_.wait(lock, [this] { return open_; });
  }

 private:
  std::mutex mutex_;
  std::condition_variable opened_;
  bool open_ = false;
};

// Each face's random points come from a stream seeded by the face itself (canonical_face):
// the samples depend neither on the order in which faces are measured, nor on the thread
// count, nor on the order of the faces in the mesh.
// Faces are measured in units of this many, in Morton order, shared out to the threads.
constexpr std::size_t kFacesPerUnit = 1024;

class OneWayMeasurement {
 public:
  OneWayMeasurement(const Mesh& from, const TriangleBvh& to, const DistanceOptions& options,
                    uint64_t stream, double noise_floor)
      : from_(from),
        to_(to),
        samples_per_face_(options.samples_per_face),
        stream_(stream),
        noise_floor_(noise_floor) {
    const std::size_t face_count = from.face_count();
    // Each vertex is sampled once, with the first face that uses it.
    first_face_.assign(from.vertex_count(), std::numeric_limits<uint32_t>::max());
    for (std::size_t i = from.triangles.size(); i-- > 0;)
      first_face_[from.triangles[i]] = uint32_t(i / 3);
    ExactSum total_area;  // exact, so the mean is the same whatever the face order
    for (std::size_t f = 0; f < face_count; ++f) total_area.add(face_area(f));
    mean_area_ = total_area.value() / double(face_count);
    // Neighbouring faces one after the other: their queries visit the same part of the
    // other mesh's hierarchy, which stays in cache, and each face's hint is a good one.
    const std::vector<uint64_t> keys = morton_keys(from);
    order_.resize(face_count);
    for (std::size_t i = 0; i < face_count; ++i) order_[i] = uint32_t(keys[i]);
  }

  // Measures units of faces until none is left; any number of threads may call it at once.
  void work() {
    Worker worker;
    for (std::size_t unit; (unit = next_unit_.fetch_add(1)) * kFacesPerUnit < order_.size();) {
      const std::size_t end = std::min(order_.size(), (unit + 1) * kFacesPerUnit);
      for (std::size_t i = unit * kFacesPerUnit; i < end; ++i) measure_face(order_[i], worker);
    }
    const std::lock_guard<std::mutex> lock(mutex_);
    total_.merge(worker.sum);
  }

  // Every sample's, once every work() has returned. The same whatever the order, since the
  // sum is exact.
  const OneWay& total() const { return total_; }

 private:
  // A face's corners from the rotation that makes their coordinates' bits the smallest
  // sequence, and a hash of those bits: what a face's samples are made from depends only on
  // the face's three positions and orientation, not on its index, its vertices' indices or
  // which corner is written first. So a mesh measures the same with its faces in another
  // order (as the full detail of a .pm has them, against the input file).
  struct CanonicalFace {
    Vec3 corner[3];
    uint64_t hash;
  };
  CanonicalFace canonical_face(std::size_t f) const {
    uint32_t bits[3][3];
    for (int c = 0; c < 3; ++c)
      std::memcpy(bits[c], &from_.positions[3 * std::size_t(from_.triangles[3 * f + c])],
                  sizeof bits[c]);
    auto key = [&](int rotation, int k) { return bits[(rotation + k / 3) % 3][k % 3]; };
    int first = 0;
    for (int rotation = 1; rotation < 3; ++rotation) {
      for (int k = 0; k < 9; ++k) {
        if (key(rotation, k) == key(first, k)) continue;
        if (key(rotation, k) < key(first, k)) first = rotation;
        break;
      }
    }
    CanonicalFace face;
    face.hash = 0x9e3779b97f4a7c15ULL;
    for (int c = 0; c < 3; ++c) {
      const uint32_t v = from_.triangles[3 * f + (first + c) % 3];
      face.corner[c] = vertex_position(from_, v);
      for (int k = 0; k < 3; ++k) {  // SplitMix64's finalizer as the mixing step
        uint64_t z = (face.hash ^ key(first, 3 * c + k)) + 0x9e3779b97f4a7c15ULL;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        face.hash = z ^ (z >> 31);
      }
    }
    return face;
  }

  double face_area(std::size_t f) const {
    const CanonicalFace face = canonical_face(f);
    return 0.5 * area_vector(face.corner[0], face.corner[1], face.corner[2]).norm();
  }

  // The face is cut into m x m cells, m = side(f): at least samples_per_face points, more
  // on faces larger than the mean, so that the sampling density never falls below the
  // mean's.
  std::size_t side(std::size_t f) const {
    double wanted = samples_per_face_;
    if (mean_area_ > 0) wanted = std::max(wanted, wanted * face_area(f) / mean_area_);
    return std::size_t(std::ceil(std::sqrt(wanted)));
  }

  // What a thread carries from one face to the next.
  struct Worker {
    uint32_t hint = 0;          // the last nearest triangle
    int skip = 0, penalty = 1;  // faces not to try candidates for, and after the next miss
    TriangleBvh::Candidates candidates;
    TriangleBvh::Start start;
    OneWay sum;
  };

  void measure_face(uint32_t f, Worker& worker) {
    uint32_t& hint = worker.hint;
    auto add = [&](double d) {
      // Below this the distance is the rounding of the sample's own construction (a point
      // on a face shared by both meshes comes out ~1e-17 away), not a geometric error.
      worker.sum.add(d <= noise_floor_ ? 0.0 : d);
    };
    const uint32_t* corner = &from_.triangles[3 * std::size_t(f)];
    const Vec3 corners[3] = {vertex_position(from_, corner[0]), vertex_position(from_, corner[1]),
                             vertex_position(from_, corner[2])};
    // The nearest triangle to the face's centroid, from the root, makes a good hint. Every
    // point of the face is then at most `reach` from the hint's triangle (the distance to a
    // triangle is convex, so largest at a corner): the face's queries need only consider
    // what comes that close to it.
    to_.nearest((corners[0] + corners[1] + corners[2]) / 3.0, hint, to_.root_start());
    double reach = 0;
    for (int c = 0; c < 3; ++c) reach = std::max(reach, to_.triangle_distance(corners[c], hint));
    // Few candidate triangles for a face small next to the other mesh's triangles; else the
    // subtrees near the face. After a face with too many candidates, skip the next faces,
    // more after each further one, since neighbours look alike.
    bool few = false;
    if (worker.skip > 0) {
      --worker.skip;
    } else {
      few = to_.candidates_near(corners, hint, reach, worker.candidates);
      worker.skip = few ? 0 : worker.penalty;
      worker.penalty = few ? 1 : std::min(2 * worker.penalty, 64);
    }
    if (!few) {
      Vec3 lo = corners[0], hi = corners[0];
      for (int c = 1; c < 3; ++c) {
        lo.minimize(corners[c]);
        hi.maximize(corners[c]);
      }
      to_.start_near(lo, hi, reach, worker.start);
    }
    auto measure = [&](const Vec3& p) {
      add(few ? to_.nearest(p, hint, worker.candidates) : to_.nearest(p, hint, worker.start));
    };
    for (int c = 0; c < 3; ++c) {
      const bool repeated = (c > 0 && corner[c] == corner[0]) || (c == 2 && corner[2] == corner[1]);
      if (first_face_[corner[c]] != f || repeated) continue;
      measure(corners[c]);
    }
    const CanonicalFace face = canonical_face(f);
    Random random(stream_ ^ face.hash, 0);
    const std::size_t m = side(f);
    const Vec3& a = face.corner[0];
    const Vec3 ab = (face.corner[1] - a) / double(m);
    const Vec3 ac = (face.corner[2] - a) / double(m);
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

  const Mesh& from_;
  const TriangleBvh& to_;
  const double samples_per_face_;
  const uint64_t stream_;
  const double noise_floor_;
  double mean_area_ = 0;
  std::vector<uint32_t> first_face_;
  std::vector<uint32_t> order_;            // faces in the order they are measured
  std::atomic<std::size_t> next_unit_{0};
  std::mutex mutex_;
  OneWay total_;
};

}  // namespace

Status measure_surface_distance(const Mesh& reference, const Mesh& other,
                                const DistanceOptions& options, SurfaceDistance& out) {
  return detail::no_throw([&]() -> Status {
    if (!(options.samples_per_face >= 1) || !std::isfinite(options.samples_per_face))
      return Status(ErrorCode::kInvalidArgument, "samples per face must be a number of at least 1");
    if (Status s = check_mesh(reference, "reference"); !s) return s;
    if (Status s = check_mesh(other, "other"); !s) return s;

    unsigned threads = options.threads;
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    // Double-precision rounding in building a sample and its closest point is a few units
    // in the last place of the coordinates; 1e-12 of the largest one is far above that and
    // far below float32 input resolution (6e-8).
    const double largest = std::max(largest_coordinate(reference), largest_coordinate(other));
    const double noise_floor = 1e-12 * largest;

    // Forward: samples of `reference` against a hierarchy over `other`; backward: the
    // reverse. With one thread, one after the other. With more, this thread builds the
    // forward hierarchy while another builds the backward one, then joins the forward
    // measurement; each thread moves on to the backward measurement when the forward one has
    // no faces left for it. The results are the same either way.
    std::optional<TriangleBvh> other_bvh, reference_bvh;
    std::optional<OneWayMeasurement> forward_pass, backward_pass;
    Gate forward_ready, backward_ready;
    std::mutex error_mutex;
    std::exception_ptr error;
    auto guarded = [&](auto&& body) {
      try {
        body();
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
      }
    };
    auto prepare_forward = [&] {
      guarded([&] {
        other_bvh.emplace(other, largest);
        forward_pass.emplace(reference, *other_bvh, options, options.seed * 2 + 0, noise_floor);
      });
      forward_ready.open();
    };
    auto prepare_backward = [&] {
      guarded([&] {
        reference_bvh.emplace(reference, largest);
        backward_pass.emplace(other, *reference_bvh, options, options.seed * 2 + 1, noise_floor);
      });
      backward_ready.open();
    };
    auto measure = [&] {
      forward_ready.wait();
      if (forward_pass) guarded([&] { forward_pass->work(); });
      backward_ready.wait();
      if (backward_pass) guarded([&] { backward_pass->work(); });
    };
    OneWay forward, backward;
    if (threads == 1) {
      // One hierarchy at a time, to halve the memory.
      prepare_forward();
      if (forward_pass) guarded([&] { forward_pass->work(); });
      if (forward_pass) forward = forward_pass->total();
      forward_pass.reset();
      other_bvh.reset();
      prepare_backward();
      if (backward_pass) guarded([&] { backward_pass->work(); });
    } else {
      // The first worker prepares the backward pass; no more threads to be had: the ones
      // running and this one share the work.
      std::vector<std::thread> workers;
      if (start_threads(workers, 1, [&] {
            prepare_backward();
            measure();
          }) == 1)
        start_threads(workers, threads - 2, measure);
      prepare_forward();
      if (workers.empty()) prepare_backward();
      measure();
      for (std::thread& worker : workers) worker.join();
      if (forward_pass) forward = forward_pass->total();
    }
    if (error) std::rethrow_exception(error);
    backward = backward_pass->total();
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
  });
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
