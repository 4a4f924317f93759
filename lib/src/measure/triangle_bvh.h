// The nearest-triangle search of the surface distance (surface_distance.cpp): a 4-wide
// bounding volume hierarchy (Wald, Benthin and Boulos 2008; Dammertz et al. 2008) built
// from Morton codes (Morton 1966; Lauterbach et al. 2009), float32 boxes and triangle
// slabs tested four at a time to prune, the exact distance in double (Ericson 2005,
// §5.1.5). surface_distance.cpp's top comment says what makes it fast and exact. Internal
// to measure/.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "pm/mesh.h"
#include "simplify/geometry.h"

namespace pm::measure {

inline Vec3 vertex_position(const Mesh& mesh, uint32_t v) {
  return Vec3(mesh.positions[3 * std::size_t(v)], mesh.positions[3 * std::size_t(v) + 1],
              mesh.positions[3 * std::size_t(v) + 2]);
}

inline int lowest_bit(unsigned bits) {
  return __builtin_ctz(bits);
}
inline int bit_count(unsigned bits) {  // no popcnt instruction in baseline x86-64
  int count = 0;
  for (; bits; bits &= bits - 1) ++count;
  return count;
}

// The 10 low bits of x, spread to every third bit of the result.
inline uint64_t spread_bits(uint32_t x) {
  uint64_t bits = 0;
  for (int i = 0; i < 10; ++i) bits |= uint64_t(x >> i & 1) << (3 * i);
  return bits;
}

// The faces in Morton order (Morton 1966) of their bounding boxes' centres on a 1024^3
// grid over the mesh: nearby faces come close together. Keys are code << 32 | face, sorted.
inline std::vector<uint64_t> morton_keys(const Mesh& mesh) {
  const std::size_t face_count = mesh.face_count();
  std::vector<float> centres(3 * face_count);
  double lo[3], hi[3];
  for (int axis = 0; axis < 3; ++axis) {
    lo[axis] = std::numeric_limits<double>::infinity();
    hi[axis] = -lo[axis];
  }
  for (std::size_t f = 0; f < face_count; ++f) {
    for (int axis = 0; axis < 3; ++axis) {
      float low = std::numeric_limits<float>::infinity(), high = -low;
      for (int c = 0; c < 3; ++c) {
        const float x = mesh.positions[3 * std::size_t(mesh.triangles[3 * f + c]) + axis];
        low = std::min(low, x);
        high = std::max(high, x);
      }
      const float centre = 0.5f * low + 0.5f * high;
      centres[3 * f + axis] = centre;
      lo[axis] = std::min(lo[axis], double(centre));
      hi[axis] = std::max(hi[axis], double(centre));
    }
  }
  std::vector<uint64_t> keys(face_count);
  for (std::size_t f = 0; f < face_count; ++f) {
    uint64_t code = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const double extent = hi[axis] - lo[axis];
      const double cell = extent > 0 ? (centres[3 * f + axis] - lo[axis]) / extent * 1024 : 0;
      code |= spread_bits(uint32_t(std::clamp(cell, 0.0, 1023.0))) << axis;
    }
    keys[f] = code << 32 | f;
  }
  // Least significant digit radix sort on the 30 code bits, 10 at a time: stable, so the
  // faces stay in index order within a code.
  std::vector<uint64_t> sorted(face_count);
  for (int shift = 32; shift < 62; shift += 10) {
    std::vector<std::size_t> start(1025, 0);
    for (uint64_t key : keys) ++start[(key >> shift & 1023) + 1];
    for (int digit = 0; digit < 1024; ++digit) start[digit + 1] += start[digit];
    for (uint64_t key : keys) sorted[start[key >> shift & 1023]++] = key;
    keys.swap(sorted);
  }
  return keys;
}

// Four floats side by side: SSE where the compiler has it (every x86-64), else plain
// arrays. Only what the pruning tests need.
#if defined(__SSE2__)
struct Float4 {
  __m128 v;
  static Float4 load(const float* p) { return {_mm_load_ps(p)}; }  // 16-byte aligned
  static Float4 broadcast(float x) { return {_mm_set1_ps(x)}; }
  static Float4 zero() { return {_mm_setzero_ps()}; }
  void store(float* p) const { _mm_store_ps(p, v); }
  friend Float4 operator+(Float4 a, Float4 b) { return {_mm_add_ps(a.v, b.v)}; }
  friend Float4 operator-(Float4 a, Float4 b) { return {_mm_sub_ps(a.v, b.v)}; }
  friend Float4 operator*(Float4 a, Float4 b) { return {_mm_mul_ps(a.v, b.v)}; }
  friend Float4 max(Float4 a, Float4 b) { return {_mm_max_ps(a.v, b.v)}; }
  friend Float4 min(Float4 a, Float4 b) { return {_mm_min_ps(a.v, b.v)}; }
  // Bit i set where a's lane i <= b's.
  friend unsigned lanes_not_above(Float4 a, Float4 b) {
    return unsigned(_mm_movemask_ps(_mm_cmple_ps(a.v, b.v)));
  }
};
#else
struct Float4 {
  float v[4];
  static Float4 load(const float* p) { return {{p[0], p[1], p[2], p[3]}}; }
  static Float4 broadcast(float x) { return {{x, x, x, x}}; }
  static Float4 zero() { return broadcast(0); }
  void store(float* p) const { std::copy(v, v + 4, p); }
  template <typename Op>
  static Float4 apply(Float4 a, Float4 b, Op op) {
    return {{op(a.v[0], b.v[0]), op(a.v[1], b.v[1]), op(a.v[2], b.v[2]), op(a.v[3], b.v[3])}};
  }
  friend Float4 operator+(Float4 a, Float4 b) { return apply(a, b, std::plus<float>()); }
  friend Float4 operator-(Float4 a, Float4 b) { return apply(a, b, std::minus<float>()); }
  friend Float4 operator*(Float4 a, Float4 b) { return apply(a, b, std::multiplies<float>()); }
  friend Float4 max(Float4 a, Float4 b) {
    return apply(a, b, [](float x, float y) { return std::max(x, y); });
  }
  friend Float4 min(Float4 a, Float4 b) {
    return apply(a, b, [](float x, float y) { return std::min(x, y); });
  }
  friend unsigned lanes_not_above(Float4 a, Float4 b) {
    unsigned bits = 0;
    for (int i = 0; i < 4; ++i) bits |= unsigned(a.v[i] <= b.v[i]) << i;
    return bits;
  }
};
#endif

// A query point, four times over.
struct Point4 {
  Float4 x[3];
  explicit Point4(const Vec3& p)
      : x{Float4::broadcast(float(p[0])), Float4::broadcast(float(p[1])),
          Float4::broadcast(float(p[2]))} {}
};

constexpr uint32_t kNoChild = std::numeric_limits<uint32_t>::max();

// A node of the 4-wide hierarchy: its children's boxes, component by component, so that the
// four are tested side by side. 116 bytes: two cache lines.
struct alignas(64) BvhNode {
  float lo[3][4], hi[3][4];
  uint32_t child[4] = {kNoChild, kNoChild, kNoChild, kNoChild};  // node or block index
  uint32_t count[4] = {0, 0, 0, 0};  // triangles in the child block; 0 for a child node
  unsigned present = 0;              // bit i: child i exists (they fill from bit 0)

  BvhNode() {
    for (int axis = 0; axis < 3; ++axis) {
      for (int i = 0; i < 4; ++i) {
        lo[axis][i] = std::numeric_limits<float>::infinity();
        hi[axis][i] = -std::numeric_limits<float>::infinity();
      }
    }
  }

  // Bit i: child i's box overlaps the box [region_lo, region_hi].
  unsigned overlapping(const float region_lo[3], const float region_hi[3]) const {
    unsigned lanes = present;
    for (int axis = 0; axis < 3; ++axis) {
      lanes &= lanes_not_above(Float4::load(lo[axis]), Float4::broadcast(region_hi[axis])) &
               lanes_not_above(Float4::broadcast(region_lo[axis]), Float4::load(hi[axis]));
    }
    return lanes;
  }

  // Squared distances from q to the four children's boxes (Ericson 2005, §5.1.3.1).
  Float4 box_distances(const Point4& q) const {
    Float4 sum = Float4::zero();
    for (int axis = 0; axis < 3; ++axis) {
      const Float4 outside =
          max(max(Float4::load(lo[axis]) - q.x[axis], q.x[axis] - Float4::load(hi[axis])),
              Float4::zero());
      sum = sum + outside * outside;
    }
    return sum;
  }
};

// Up to four triangles, each as the slab between two planes parallel to it and the three
// half-spaces whose planes contain an edge and are perpendicular to it. The triangle lies in
// each, so its distance from a point is at least the distance to the intersection of the
// slab with any one half-space: sqrt(h^2 + s^2), h the distance to the slab and s to the
// half-space, their normals being orthogonal. That is exact where the nearest point is
// inside the triangle or on an edge, a lower bound near a corner, and costs four dot
// products. The planes' offsets come from the triangle's exact corners and the float32
// normals as stored, so that the triangle is in them whatever the rounding of the normals.
// A degenerate triangle, or a lane with none, has all zeros: a lower bound of 0.
struct alignas(16) TriangleBlock {
  float normal[3][4];              // unit normal, by component
  float plane_lo[4], plane_hi[4];  // range of normal . x over the triangle
  float edge[3][3][4];             // per edge, its outward unit normal in the plane
  float edge_offset[3][4];         // largest edge . x over the triangle

  // Squared lower bounds on the distances from q to the four triangles.
  Float4 lower_bounds(const Point4& q) const {
    const Float4 along = dot(normal, q);
    const Float4 h =
        max(max(Float4::load(plane_lo) - along, along - Float4::load(plane_hi)), Float4::zero());
    Float4 s = Float4::zero();
    for (int e = 0; e < 3; ++e) s = max(s, dot(edge[e], q) - Float4::load(edge_offset[e]));
    return h * h + s * s;
  }

  // Squared lower bounds on the distances from a triangle, corners c[0..2], to the four
  // triangles: the same planes, the distance to each being smallest at a corner.
  Float4 lower_bounds(const Point4 c[3]) const {
    Float4 low = dot(normal, c[0]), high = low;
    for (int k = 1; k < 3; ++k) {
      const Float4 along = dot(normal, c[k]);
      low = min(low, along);
      high = max(high, along);
    }
    const Float4 h =
        max(max(Float4::load(plane_lo) - high, low - Float4::load(plane_hi)), Float4::zero());
    Float4 s = Float4::zero();
    for (int e = 0; e < 3; ++e) {
      Float4 nearest = dot(edge[e], c[0]);
      for (int k = 1; k < 3; ++k) nearest = min(nearest, dot(edge[e], c[k]));
      s = max(s, nearest - Float4::load(edge_offset[e]));
    }
    return h * h + s * s;
  }

  // Lane `to` becomes lane `from` of `other`.
  void copy_lane(int to, const TriangleBlock& other, int from) {
    for (int axis = 0; axis < 3; ++axis) {
      normal[axis][to] = other.normal[axis][from];
      for (int e = 0; e < 3; ++e) edge[e][axis][to] = other.edge[e][axis][from];
    }
    plane_lo[to] = other.plane_lo[from];
    plane_hi[to] = other.plane_hi[from];
    for (int e = 0; e < 3; ++e) edge_offset[e][to] = other.edge_offset[e][from];
  }

  // Sets lane `lane` to the triangle with these corners.
  void set_lane(int lane, const Vec3 v[3]) {
    Vec3 n = area_vector(v[0], v[1], v[2]);
    const double length = n.norm();
    if (!(length > 0) || !std::isfinite(length)) return;  // degenerate
    n /= length;
    // The range of x . d over the triangle for the float32 direction d stored from `unit`.
    auto store = [&](const Vec3& unit, float(*direction)[4], double& lo, double& hi) {
      for (int axis = 0; axis < 3; ++axis) direction[axis][lane] = float(unit[axis]);
      const Vec3 stored(direction[0][lane], direction[1][lane], direction[2][lane]);
      lo = hi = stored | v[0];
      for (int c = 1; c < 3; ++c) {
        lo = std::min(lo, stored | v[c]);
        hi = std::max(hi, stored | v[c]);
      }
    };
    double lo, hi;
    store(n, normal, lo, hi);
    plane_lo[lane] = float(lo);
    plane_hi[lane] = float(hi);
    for (int e = 0; e < 3; ++e) {
      const Vec3 outward = (v[(e + 1) % 3] - v[e]) % n;  // in the plane, away from the triangle
      const double outward_length = outward.norm();
      if (!(outward_length > 0)) continue;  // leaves a bound of 0 from this edge
      store(outward / outward_length, edge[e], lo, hi);
      edge_offset[e][lane] = float(hi);
    }
  }

 private:
  static Float4 dot(const float (*direction)[4], const Point4& x) {
    return Float4::load(direction[0]) * x.x[0] + Float4::load(direction[1]) * x.x[1] +
           Float4::load(direction[2]) * x.x[2];
  }
};

// A 4-wide bounding volume hierarchy over a mesh's triangles, for nearest-triangle queries.
//
// Built as a binary tree over the faces in Morton order, split where the highest bit of
// the code changes (a spatial midpoint split in linear time: Lauterbach et al. 2009, the
// LBVH), then collapsed to four children per node, the widest child opened first
// (Dammertz et al. 2008). Leaves are blocks of up to four triangles (TriangleBlock).
//
// Exactness. The float32 tests only prune: each is a lower bound on the distance to what
// it covers, and a box or triangle is skipped only when that bound exceeds the best
// distance so far plus a margin for rounding (pruning_bound). Every triangle that could be
// nearer is measured by point_triangle_distance in double, so a query returns the minimum
// of that function over all triangles, whatever the tree, the hint or the thread.
// The margin: a coordinate rounded to float32 moves by up to 2^-24 of the largest
// coordinate M; the few float32 operations of a bound add a few times as much, and the
// float32 unit normals are unit and orthogonal to about 2^-23. All told, a bound is within
// 2^-20 M plus 2^-20 of itself of the exact distance to its planes or box; the margin,
// 2^-18 M plus 2^-17 relative, covers that and the double rounding of
// point_triangle_distance (about 2^-50 M).
class TriangleBvh {
 public:
  // `largest_coordinate`: the largest absolute coordinate of this mesh and of every query
  // point. The mesh must outlive the hierarchy.
  TriangleBvh(const Mesh& mesh, double largest_coordinate)
      : slack_(0x1p-18 * largest_coordinate), mesh_(mesh) {
    const std::size_t face_count = mesh.face_count();
    const std::vector<uint64_t> keys = morton_keys(mesh);
    std::vector<BuildNode> binary;
    binary.reserve(face_count);
    binary.emplace_back();
    build_binary(0, 0, face_count, keys, mesh, binary);
    nodes_.reserve(face_count / 6 + 1);
    blocks_.reserve(face_count / 2 + 1);
    faces_.reserve(4 * (face_count / 2 + 1));
    nodes_.emplace_back();
    if (binary[0].count > 0) {  // a single leaf: the root's only child
      set_child(0, 0, binary[0], make_block(binary[0], keys, mesh));
    } else {
      collapse(0, 0, binary, keys, mesh);
    }
    const Node& root = nodes_[0];
    for (int i = 0; i < 4; ++i) {
      for (int axis = 0; axis < 3; ++axis) {
        root_start_.lo[axis][i] = root.lo[axis][i];
        root_start_.hi[axis][i] = root.hi[axis][i];
      }
      root_start_.index[i] = root.child[i];
      root_start_.count[i] = root.count[i];
      if (root.present >> i & 1) root_start_.size = i + 1;
    }
  }

  // The exact distance from p to triangle t (an index in this hierarchy's order).
  double triangle_distance(const Vec3& p, uint32_t t) const {
    const uint32_t* corner = &mesh_.triangles[3 * std::size_t(faces_[t])];
    return point_triangle_distance(p, vertex_position(mesh_, corner[0]),
                                   vertex_position(mesh_, corner[1]),
                                   vertex_position(mesh_, corner[2]));
  }

  // Where a query starts: a few subtrees and blocks that hold every triangle that may be
  // nearest to the query point.
  static constexpr int kStartSize = 8;
  struct Start {
    alignas(16) float lo[3][kStartSize];
    alignas(16) float hi[3][kStartSize];
    uint32_t index[kStartSize], count[kStartSize];  // as in BvhNode
    int size = 0;  // entries; the rest of the last group of four is infinitely far
  };

  // The start for any point: the root's children.
  const Start& root_start() const { return root_start_; }

  // The start for points of the box [lo, hi] within `reach` of some triangle: the subtrees
  // that overlap the box grown by `reach`, as deep as kStartSize entries allow (the widest
  // replaced by its overlapping children first). The deeper, the fewer nodes a query visits.
  void start_near(const Vec3& lo, const Vec3& hi, double reach, Start& start) const {
    float region_lo[3], region_hi[3];
    grow(lo, hi, reach, region_lo, region_hi);
    struct Entry {
      uint32_t node;  // the entry is child `lane` of this node
      int lane;
      bool open;  // a node that may still be replaced by its children
    };
    Entry entries[kStartSize];
    int n = 0;
    for (unsigned lanes = nodes_[0].overlapping(region_lo, region_hi); lanes; lanes &= lanes - 1)
      entries[n++] = {0, lowest_bit(lanes), nodes_[0].count[lowest_bit(lanes)] == 0};
    for (;;) {
      int widest = -1;
      float widest_area = -1;
      for (int i = 0; i < n; ++i) {
        if (!entries[i].open) continue;
        const Node& parent = nodes_[entries[i].node];
        const int lane = entries[i].lane;
        const float box_lo[3] = {parent.lo[0][lane], parent.lo[1][lane], parent.lo[2][lane]};
        const float box_hi[3] = {parent.hi[0][lane], parent.hi[1][lane], parent.hi[2][lane]};
        const float area = half_area(box_lo, box_hi);
        if (area > widest_area) {
          widest = i;
          widest_area = area;
        }
      }
      if (widest < 0) break;
      const uint32_t node = nodes_[entries[widest].node].child[entries[widest].lane];
      const unsigned children = nodes_[node].overlapping(region_lo, region_hi);
      if (n - 1 + bit_count(children) > kStartSize) {
        entries[widest].open = false;
        continue;
      }
      entries[widest] = entries[--n];
      for (unsigned lanes = children; lanes; lanes &= lanes - 1)
        entries[n++] = {node, lowest_bit(lanes), nodes_[node].count[lowest_bit(lanes)] == 0};
    }
    start.size = n;
    for (int i = 0; i < (n + 3) / 4 * 4; ++i) {
      const bool there = i < n;
      const Node& parent = nodes_[there ? entries[i].node : 0];
      const int lane = there ? entries[i].lane : 0;
      for (int axis = 0; axis < 3; ++axis) {
        start.lo[axis][i] = there ? parent.lo[axis][lane] : std::numeric_limits<float>::infinity();
        start.hi[axis][i] = there ? parent.hi[axis][lane] : -std::numeric_limits<float>::infinity();
      }
      start.index[i] = there ? parent.child[lane] : 0;
      start.count[i] = there ? parent.count[lane] : 0;
    }
  }

  // Distance from p to the nearest triangle, for p whose nearest triangle `start` holds.
  // `hint` is a triangle likely to be near p, typically the previous query's answer: its
  // distance prunes most of the tree at once. It is set to the nearest triangle found.
  double nearest(const Vec3& p, uint32_t& hint, const Start& start) const {
    const uint32_t first_hint = hint;
    double best = triangle_distance(p, hint);
    if (best == 0) return 0;
    float bound = pruning_bound(best);
    const Point4 q(p);
    struct Entry {
      uint32_t index;  // a node, or a block when count > 0
      uint32_t count;  // triangles in the block; 0 for a node
      float lower;     // squared lower bound on the distance to what it holds
    };
    Entry stack[kStackSize];
    int top = 0;
    // Pushes the entries in `lanes`, the nearest last, so that it is visited first.
    auto push = [&](unsigned lanes, const float* lower, const uint32_t* index,
                    const uint32_t* count) {
      const int first = top;
      for (; lanes; lanes &= lanes - 1) {
        const int i = lowest_bit(lanes);
        const Entry entry = {index[i], count[i], lower[i]};
        int j = top++;
        for (; j > first && stack[j - 1].lower < entry.lower; --j) stack[j] = stack[j - 1];
        stack[j] = entry;
      }
    };
    // Measures the triangles of a block that may be nearer; true when p is on one.
    auto visit_block = [&](uint32_t block, uint32_t count) {
      const Float4 lower = blocks_[block].lower_bounds(q);
      for (unsigned lanes = lanes_not_above(lower, Float4::broadcast(bound)) & ((1u << count) - 1);
           lanes; lanes &= lanes - 1) {
        const uint32_t t = 4 * block + uint32_t(lowest_bit(lanes));
        if (t == first_hint) continue;  // measured first
        const double d = triangle_distance(p, t);
        if (d < best) {
          best = d;
          hint = t;
          if (best == 0) return true;
          bound = pruning_bound(best);
        }
      }
      return false;
    };
    // The start's blocks are visited at once, its subtrees pushed.
    for (int group = 0; group < start.size; group += 4) {
      Float4 distances = Float4::zero();
      for (int axis = 0; axis < 3; ++axis) {
        const Float4 outside = max(max(Float4::load(start.lo[axis] + group) - q.x[axis],
                                       q.x[axis] - Float4::load(start.hi[axis] + group)),
                                   Float4::zero());
        distances = distances + outside * outside;
      }
      alignas(16) float lower[4];
      distances.store(lower);
      const unsigned there = start.size - group >= 4 ? 15u : (1u << (start.size - group)) - 1;
      unsigned subtrees = 0;
      for (unsigned lanes = lanes_not_above(distances, Float4::broadcast(bound)) & there; lanes;
           lanes &= lanes - 1) {
        const int i = lowest_bit(lanes);
        if (start.count[group + i] == 0) {
          subtrees |= 1u << i;
        } else if (lower[i] <= bound &&
                   visit_block(start.index[group + i], start.count[group + i])) {
          return 0;
        }
      }
      push(subtrees, lower, start.index + group, start.count + group);
    }
    while (top > 0) {
      const Entry entry = stack[--top];
      if (entry.lower > bound) continue;  // the best improved since it was pushed
      if (entry.count > 0) {
        if (visit_block(entry.index, entry.count)) return 0;
        continue;
      }
      const Node& node = nodes_[entry.index];
      const Float4 distances = node.box_distances(q);
      alignas(16) float lower[4];
      distances.store(lower);
      push(lanes_not_above(distances, Float4::broadcast(bound)) & node.present, lower, node.child,
           node.count);
    }
    return best;
  }

  // The few triangles that may be nearest to some point of one face, side by side.
  static constexpr int kMaxCandidates = 16;
  struct Candidates {
    TriangleBlock planes[kMaxCandidates / 4];
    uint32_t triangle[kMaxCandidates];
    int size = 0;
  };

  // The triangles that may be nearest to a point of the triangle `corners`, every point of
  // which is within `reach` of triangle `hint`: the hint and those whose planes come within
  // `reach` of the face. False when there are more than kMaxCandidates, as when the face is
  // large next to this mesh's triangles.
  bool candidates_near(const Vec3 corners[3], uint32_t hint, double reach, Candidates& out) const {
    Vec3 lo = corners[0], hi = corners[0];
    for (int c = 1; c < 3; ++c) {
      lo.minimize(corners[c]);
      hi.maximize(corners[c]);
    }
    float region_lo[3], region_hi[3];
    grow(lo, hi, reach, region_lo, region_hi);
    const Point4 c[3] = {Point4(corners[0]), Point4(corners[1]), Point4(corners[2])};
    const Float4 bound = Float4::broadcast(pruning_bound(reach));
    out.size = 0;
    auto add = [&](uint32_t t) {
      if (out.size == kMaxCandidates) return false;
      out.planes[out.size / 4].copy_lane(out.size % 4, blocks_[t / 4], int(t % 4));
      out.triangle[out.size++] = t;
      return true;
    };
    add(hint);
    uint32_t stack[kStackSize];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      for (unsigned lanes = node.overlapping(region_lo, region_hi); lanes; lanes &= lanes - 1) {
        const int i = lowest_bit(lanes);
        if (node.count[i] == 0) {
          stack[top++] = node.child[i];
          continue;
        }
        const uint32_t block = node.child[i];
        for (unsigned near = lanes_not_above(blocks_[block].lower_bounds(c), bound) &
                             ((1u << node.count[i]) - 1);
             near; near &= near - 1) {
          const uint32_t t = 4 * block + uint32_t(lowest_bit(near));
          if (t != hint && !add(t)) return false;
        }
      }
    }
    return true;
  }

  // nearest() for a point of a face whose candidates are `candidates`; `hint` is one of them.
  double nearest(const Vec3& p, uint32_t& hint, const Candidates& candidates) const {
    double best = triangle_distance(p, hint);
    if (best == 0 || candidates.size == 1) return best;
    float bound = pruning_bound(best);
    const uint32_t first_hint = hint;
    const Point4 q(p);
    for (int group = 0; group < candidates.size; group += 4) {
      alignas(16) float lower[4];
      candidates.planes[group / 4].lower_bounds(q).store(lower);
      for (int i = 0; i < std::min(4, candidates.size - group); ++i) {
        const uint32_t t = candidates.triangle[group + i];
        if (lower[i] > bound || t == first_hint) continue;
        const double d = triangle_distance(p, t);
        if (d < best) {
          best = d;
          hint = t;
          if (best == 0) return 0;
          bound = pruning_bound(best);
        }
      }
    }
    return best;
  }

 private:
  using Node = BvhNode;
  static constexpr std::size_t kLeafSize = 4;
  // The binary tree is at most 30 + 32 deep (build_binary), the 4-wide one no deeper. A
  // node pushes at most 4 entries for the 1 it pops: at most 3 per level, plus the start.
  static constexpr int kStackSize = 3 * (30 + 32) + kStartSize;

  struct BuildNode {
    float lo[3], hi[3];
    uint32_t first = 0;  // leaf: first of its faces in Morton order; else left child (right + 1)
    uint32_t count = 0;  // triangles in a leaf; 0 for an inner node
  };

  // The squared float32 distance beyond which a lower bound prunes, for a best distance
  // (see the class comment). Rounding it to float32 (2^-24) is within the relative margin.
  float pruning_bound(double best) const {
    const double reach = best + slack_;
    return float(reach * reach * (1 + 0x1p-16));
  }

  // The box [lo, hi] grown by `reach` and the margin, in float32 (rounding within it).
  void grow(const Vec3& lo, const Vec3& hi, double reach, float grown_lo[3],
            float grown_hi[3]) const {
    for (int axis = 0; axis < 3; ++axis) {
      grown_lo[axis] = float(lo[axis] - reach - 2 * slack_);
      grown_hi[axis] = float(hi[axis] + reach + 2 * slack_);
    }
  }

  static float half_area(const float lo[3], const float hi[3]) {
    const float x = hi[0] - lo[0], y = hi[1] - lo[1], z = hi[2] - lo[2];
    return x * y + y * z + z * x;
  }

  // Node `index` of the binary tree over the faces keys[begin, end): split where the
  // highest differing code bit changes, or (equal codes) at half the count. Either way the
  // depth is at most 30 + 32.
  static void build_binary(std::size_t index, std::size_t begin, std::size_t end,
                           const std::vector<uint64_t>& keys, const Mesh& mesh,
                           std::vector<BuildNode>& binary) {
    BuildNode node;
    if (end - begin <= kLeafSize) {
      for (int axis = 0; axis < 3; ++axis) {
        node.lo[axis] = std::numeric_limits<float>::infinity();
        node.hi[axis] = -std::numeric_limits<float>::infinity();
      }
      for (std::size_t i = begin; i < end; ++i) {
        for (int c = 0; c < 3; ++c) {
          const std::size_t vertex = mesh.triangles[3 * std::size_t(uint32_t(keys[i])) + c];
          for (int axis = 0; axis < 3; ++axis) {
            node.lo[axis] = std::min(node.lo[axis], mesh.positions[3 * vertex + axis]);
            node.hi[axis] = std::max(node.hi[axis], mesh.positions[3 * vertex + axis]);
          }
        }
      }
      node.first = uint32_t(begin);
      node.count = uint32_t(end - begin);
      binary[index] = node;
      return;
    }
    std::size_t middle = begin + (end - begin) / 2;
    const auto first_code = uint32_t(keys[begin] >> 32), last_code = uint32_t(keys[end - 1] >> 32);
    if (first_code != last_code) {
      // The codes agree above the highest bit where the first and last differ, so along
      // the range that bit is 0, then 1.
      const uint64_t bit = uint64_t(1) << (32 + 31 - __builtin_clz(first_code ^ last_code));
      middle = std::size_t(std::partition_point(keys.begin() + begin, keys.begin() + end,
                                                [&](uint64_t key) { return !(key & bit); }) -
                           keys.begin());
    }
    node.first = uint32_t(binary.size());
    binary.emplace_back();
    binary.emplace_back();
    build_binary(node.first, begin, middle, keys, mesh, binary);
    build_binary(node.first + 1, middle, end, keys, mesh, binary);
    for (int axis = 0; axis < 3; ++axis) {
      node.lo[axis] = std::min(binary[node.first].lo[axis], binary[node.first + 1].lo[axis]);
      node.hi[axis] = std::max(binary[node.first].hi[axis], binary[node.first + 1].hi[axis]);
    }
    binary[index] = node;
  }

  // Makes node `index` of the 4-wide tree from binary inner node `b`: its two children,
  // then the child of largest area replaced by its own two, up to four (Dammertz et al.).
  void collapse(uint32_t index, uint32_t b, const std::vector<BuildNode>& binary,
                const std::vector<uint64_t>& keys, const Mesh& mesh) {
    uint32_t children[4] = {binary[b].first, binary[b].first + 1, 0, 0};
    int n = 2;
    while (n < 4) {
      int widest = -1;
      float widest_area = -1;
      for (int i = 0; i < n; ++i) {
        const BuildNode& child = binary[children[i]];
        if (child.count > 0) continue;
        const float area = half_area(child.lo, child.hi);
        if (area > widest_area) {
          widest = i;
          widest_area = area;
        }
      }
      if (widest < 0) break;
      const uint32_t opened = children[widest];
      for (int i = n; i > widest + 1; --i) children[i] = children[i - 1];
      children[widest] = binary[opened].first;
      children[widest + 1] = binary[opened].first + 1;
      ++n;
    }
    for (int i = 0; i < n; ++i) {
      const BuildNode& child = binary[children[i]];
      if (child.count > 0) {
        set_child(index, i, child, make_block(child, keys, mesh));
      } else {
        const auto node = uint32_t(nodes_.size());
        nodes_.emplace_back();  // may move nodes_: set_child indexes afresh
        set_child(index, i, child, node);
        collapse(node, children[i], binary, keys, mesh);
      }
    }
  }

  void set_child(uint32_t index, int i, const BuildNode& child, uint32_t target) {
    Node& node = nodes_[index];
    for (int axis = 0; axis < 3; ++axis) {
      node.lo[axis][i] = child.lo[axis];
      node.hi[axis][i] = child.hi[axis];
    }
    node.child[i] = target;
    node.count[i] = child.count;
    node.present |= 1u << i;
  }

  // The block for a binary leaf, and its faces in the same order.
  uint32_t make_block(const BuildNode& leaf, const std::vector<uint64_t>& keys, const Mesh& mesh) {
    TriangleBlock block = {};
    for (uint32_t lane = 0; lane < 4; ++lane) {
      uint32_t face = 0;  // none: never measured
      if (lane < leaf.count) {
        face = uint32_t(keys[leaf.first + lane]);
        const uint32_t* corner = &mesh.triangles[3 * std::size_t(face)];
        const Vec3 v[3] = {vertex_position(mesh, corner[0]), vertex_position(mesh, corner[1]),
                           vertex_position(mesh, corner[2])};
        block.set_lane(int(lane), v);
      }
      faces_.push_back(face);
    }
    blocks_.push_back(block);
    return uint32_t(blocks_.size() - 1);
  }

  double slack_;
  Start root_start_;
  std::vector<Node> nodes_;
  std::vector<TriangleBlock> blocks_;
  std::vector<uint32_t> faces_;  // per block lane: the face of the mesh
  const Mesh& mesh_;
};

}  // namespace pm::measure
