// The distance from a point to the nearest of a set of triangles, as the minimum of
// point_triangle_distance (Ericson 2005, §5.1.5) over the set, computed for fewer of them:
// a triangle's bounding box is a cheap lower bound of its distance (Ericson 2005, §5.1.3,
// closest point on an AABB), so a triangle whose box is farther than the nearest distance
// found so far need not be measured. The result is bit for bit the minimum over all
// triangles: a skipped triangle's computed distance would have been larger than the minimum
// anyway, by the margin `slack` that covers the rounding of both the bound and the exact
// distance (see BoxedTriangles::slack_for).
#pragma once

#include <limits>
#include <vector>

#include "simplify/geometry.h"

namespace pm {

class BoxedTriangles {
 public:
  // A margin far above the rounding error of point_triangle_distance on a well-shaped
  // triangle whose coordinates are at most `extent` in magnitude (some ulps of `extent`,
  // times the conditioning of the triangle, which `thin` bounds), and of the boxes'
  // distances, computed in single precision. Beyond 1e15, squares could overflow a float:
  // an infinite margin turns the pruning off.
  static double slack_for(double extent) {
    return extent < 1e15 ? 1e-5 * extent + 1e-30 : std::numeric_limits<double>::infinity();
  }

  explicit BoxedTriangles(double slack) : slack_(slack) {}

  // Empties the set and makes room for `capacity` triangles: at most that many may be
  // added (the arrays only grow, so a set reused query after query stops allocating).
  void clear(std::size_t capacity);
  void add(const Vec3& a, const Vec3& b, const Vec3& c) { add(a, b, c, is_thin(a, b, c)); }
  // The same, where the caller knows is_thin(a, b, c) already.
  void add(const Vec3& a, const Vec3& b, const Vec3& c, bool thin);
  // Nearly degenerate: the sine of the smallest angle below 1e-3. Rounding in such a
  // triangle's closest point may exceed the slack, so it is always measured.
  static bool is_thin(const Vec3& a, const Vec3& b, const Vec3& c);
  int size() const { return static_cast<int>(size_); }
  const Vec3& corner(int i, int c) const { return triangles_[i].corner[c]; }

  // The least point_triangle_distance from x to the triangles, or infinity when there are
  // none; or, once some triangle is at most `stop` away, any value at most `stop` (callers
  // taking the largest of such minima need no more). *hint, unless hint is null: a
  // triangle to try first (any value will do, -1 for none), and on return the one of the
  // answer: for a nearby point, the previous answer often settles the question.
  double nearest_distance(const Vec3& x, double stop, int* hint);

  // The first triangle (lowest index) at the least distance from x; *distance gets that
  // distance. Requires size() > 0.
  int nearest(const Vec3& x, double* distance);

 private:
  struct Triangle {
    Vec3 corner[3];
  };
  double exact(int i, const Vec3& x) const {
    const Triangle& t = triangles_[i];
    return point_triangle_distance(x, t.corner[0], t.corner[1], t.corner[2]);
  }
  // Fills bound2_ with the squared distances from x to the boxes and returns the triangle
  // of least bound.
  int bound_all(const Vec3& x);
  // Lowers nearest (at triangle nearest_at) to the least distance from x to triangles
  // [begin, end) other than `tried` (measured already), or stops once it is at most `stop`.
  void search(const Vec3& x, std::size_t begin, std::size_t end, double stop, int tried,
              double& nearest, int& nearest_at);
  // Consecutive triangles (neighbours, as the callers add them) in chunks of kChunk, each
  // with the box of their boxes: a chunk beyond the nearest distance is skipped whole.
  static constexpr std::size_t kChunk = 16;
  void make_chunks();
  // True when a triangle whose squared box distance is b2 cannot be nearer than `nearest`
  // (b2's own rounding, a few float ulps, is far below the 1e-6).
  bool beyond(float b2, double nearest) const {
    const double reach = nearest + slack_;
    return double(b2) * (1 - 1e-6) > reach * reach;
  }

  double slack_;
  std::size_t size_ = 0;
  std::vector<Triangle> triangles_;
  // The boxes, one array per bound (x, y, z low then high), in single precision (the
  // input's, so the corners' bounds are exact) so that bound_all vectorizes wide. A nearly
  // degenerate triangle gets an infinite box, so that it is always measured: rounding in
  // its closest point may exceed the slack.
  std::vector<float> box_[6];
  std::vector<float> bound2_;  // scratch: per triangle, for the current point
  bool chunks_ready_ = false;
  std::vector<float> chunk_box_[6];
  std::vector<float> chunk_bound2_;  // scratch: per chunk, for the current point
};

}  // namespace pm
