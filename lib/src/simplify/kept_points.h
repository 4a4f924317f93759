// The collapse loop's measured error (collapse_loop.h): removed input vertices carried on the faces
// of the simplified surface, as RemovedPoints carried them for the former default loop (deleted in
// issue 25) (after Klein, Liebich and Straßer 1996, "Mesh reduction with error control", who keep
// the correspondence between the input and the reduced mesh to bound their distance), but a face
// keeps only its kKept farthest points. The Hausdorff distance of a level to the input is a
// maximum, made of the farthest points; the nearer ones seldom become the farthest, so dropping
// them costs the measure little, and bounds its cost: a collapse measures at most 1 + kKept points
// per face of v's fan against that fan, however many points its faces have absorbed (where
// RemovedPoints sampled up to 512 per collapse). And the other way round, for both metrics: the
// moved faces against the faces they replace (surface_distance()) and against the input around them
// (input_distance()), a bounded grid per face. Flat arrays; safe on several threads for collapses
// whose faces are apart (the collapse loop's regions): all scratch is on the stack. Internal to
// simplify/. Measurements: tests/bench/fast.md, fast_schroeder.md and tests/bench/README.md.
//
// What it measures is a lower bound of the distance of the removed input vertices to the
// surface (the dropped points are not counted): it orders the collapses. The record of a
// collapse is an upper bound: every removed point is tracked besides (tracked_points.h).
// Without the measure (EncodeOptions::fast) no point is kept.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "simplify/face_renumbering.h"
#include "simplify/geometry.h"

namespace pm::collapse_loop {

class KeptPoints {
 public:
  // Points kept per face: on the shared meshes 4 measure as well as 16 at 50% and 10% of the
  // faces, a little worse at 2% (tests/bench/fast.md).
  static constexpr int kKept = 4;

  // A face of the surface, before or after a collapse: its id and its corners then.
  struct FanFace {
    uint32_t face;
    Vec3 a, b, c;
    // A sphere around it (make() sets it): a point farther than the nearest face so far
    // plus the radius from the centre cannot be nearer, and is not measured.
    // The radius is kept with its square: nearest_from() adds it to a distance, and its root
    // there stood in the search's chain of dependent operations.
    Vec3 centre;
    double radius2, radius;
    static FanFace make(uint32_t face, const Vec3& a, const Vec3& b, const Vec3& c) {
      const Vec3 centre = (a + b + c) / 3.0;
      const double r2 =
          std::max({(a - centre).sqrnorm(), (b - centre).sqrnorm(), (c - centre).sqrnorm()});
      return {face, a, b, c, centre, r2, std::sqrt(r2)};
    }
  };

  // n_faces faces, none holding a point yet; xyz, the input's positions (three per vertex),
  // stays the caller's and must not change. n_faces 0: frees the memory.
  void reset(std::size_t n_faces, const float* xyz);
  // The faces renamed without the dead ones (face_renumbering.h), whose lists are empty.
  void compact(const FaceRenumbering& faces) {
    faces.compact(point_, kKept);
    faces.compact(distance_, kKept);
  }
  // Asks for face f's list ahead of collapse() or points_distance(). Inlined always
  // (CollapseLoop::fetch()).
  [[gnu::always_inline]] void prefetch(uint32_t f) const {
    __builtin_prefetch(&point_[kKept * std::size_t{f}]);
  }

  // The most moved faces a measure looks at (the loop's largest valence, collapse_loop.h's
  // kMaxValence, asserts it): the scratch of surface_distance() and input_distance() is
  // sized by it, on the stack.
  static constexpr int kMaxMoved = 64;

  // The measured distance of the collapse v -> u is the larger of points_distance() and
  // surface_distance() (collapse_measure.cpp asks for the second only when the first
  // leaves the collapse the cheapest); 0 when the fan is empty.
  //
  // The largest distance from `v`'s input position and the points kept on `old_faces`
  // (v's faces before the collapse) to the nearest face of `fan` (the faces around v and u
  // after it, the first `moved` of them those that replace v's).
  double points_distance(uint32_t v, const uint32_t* old_faces, int n_old, const FanFace* fan,
                         int n_fan) const;
  // The largest of `worst` and the distances from the centroids of the moved faces (the
  // first `moved` of `fan`) and the midpoints of their edges at u (at pu) to old_fan (v's
  // faces before the collapse, with their corners then).
  static double surface_distance(const FanFace* fan, int moved, const FanFace* old_fan, int n_old,
                                 const Vec3& pu, double worst);

  // Schroeder's metric also measures the old fan (v's faces before the collapse, the two
  // at v-u with them) against the new one (`fan`), with grid_distance(): where the new fan
  // leaves part of the old surface (a boundary or a crease pulled in), the removed points
  // there were mostly dropped from the lists (near their face, so not among its farthest),
  // and only this grid sees them. Without it, 2 of 72 points above 1.05x the default loop's
  // Hausdorff distance (tests/bench/README.md); the quadric metric is better without it.
  static constexpr int kSchroederOldFanSteps = 3;
  // The largest of `worst` and the distances from the grid of `steps` per edge on each face
  // of `from` to the nearest face of `to` (a face of the same id tried first).
  static double grid_distance(const FanFace* from, int n_from, const FanFace* to, int n_to,
                              int steps, double worst);

  // The input surface as it was before the first collapse (the loop's faces change, the
  // positions never do: a half-edge collapse keeps u where it is): per face its three
  // vertices, per vertex its faces (compressed rows, faces[begin[x]] to
  // faces[begin[x + 1]]), in the loop's local ids. 4 bytes per corner twice, 4 per vertex.
  struct InputSurface {
    std::vector<uint32_t> corners, begin, faces;
    // corner_ids: 3 per face, taken over.
    void build(std::vector<uint32_t> corner_ids, std::size_t n_vertices);
    void clear() {
      std::vector<uint32_t>().swap(corners);
      std::vector<uint32_t>().swap(begin);
      std::vector<uint32_t>().swap(faces);
    }
  };

  // The measure of the new surface: the distance of the moved faces to the input itself
  // (the backward distance, level to input), where the grids of points on them used to be
  // measured against the surface they replace, which after many collapses has drifted off
  // the input: the levels farthest from the input (quadric metric: spot 10% 1.46x the
  // default loop's Hausdorff distance; Schroeder's: rocker-arm 2% 1.21x) were farthest
  // that way.
  // As the default loop's RemovedPoints (after Klein, Liebich and Straßer 1996), against
  // the input faces around the fan's corners, and for the points not settled there, the
  // input faces around the removed points too (here the points kept on v's faces); but
  // with a grid of kInputSteps per edge on each moved face instead of its centroid and
  // midpoints, and then, for a point still farther than `worst`, a walk on the input
  // (walk_input()): where a face has grown larger than the region (at 2% of the faces a
  // face stands for 50 input faces), the nearest region face is only the nearest edge of
  // it, and without the walk the levels at 2% were up to 5.8x the former default loop's.
  //
  // The largest of `worst` and the distances from the grid points of the first `moved`
  // faces of `fan` (u at pu) to the input: each face's points inside and on its two edges
  // at u (those shared with its neighbours measured once; its third edge is an edge of the
  // old surface, measured when it was made). `region`: v and its neighbours (n_region),
  // whose input faces are tried first (at most kMaxInputFaces); a point farther than
  // `worst` from all of them then tries the input faces around the point kept on old_faces
  // (v's faces) nearest to it, and walks from the nearest face found. What it measures
  // orders the collapses (it joins the key); the record stays the kept and tracked
  // points'.
  //
  // The faces around every kept point, gathered once for all such points and searched
  // whole by each, cost more: at the end of the textured 950K-face mesh's sequence nearly
  // every point was farther than `worst` from the region's faces, and searched 131 faces.
  // From the nearest kept point's: the levels as far from the input (the 8 shared meshes
  // at 50, 10 and 2%: Hausdorff 0.997 times, RMS 1.001 times, geometric means), nefertiti
  // 4% faster on one thread, and the textured mesh 8% on two.
  //
  // With 3 steps per edge (2 and 4 measured worse), the walk and the kept points' faces,
  // no point of 24 is above 1.05x the default loop's Hausdorff distance, for either metric
  // (tests/bench/README.md, "The collapse loop's measure").
  static constexpr int kInputSteps = 3;
  static constexpr int kMaxInputFaces = 256;
  static constexpr int kWalkSteps = 16;  // none took more on the shared meshes
  double input_distance(const FanFace* fan, int moved, const Vec3& pu, const uint32_t* region,
                        int n_region, const uint32_t* old_faces, int n_old,
                        const InputSurface& input, double worst) const;

  // Hands v and the points of old_faces to their nearest fan face, each keeping its kKept
  // farthest, and returns the largest distance of a point to its new face. The points left
  // off a face's list are forgotten (tracked_points.h has them all). Call before the collapse
  // changes the faces (old_faces lose their points first: some are in the fan).
  double collapse(uint32_t v, const uint32_t* old_faces, int n_old, const FanFace* fan, int n_fan);

  // The nearest fan face to x and its distance; stops at the first face within `stop`
  // (then the distance is at most stop). `first`: a face to try first, or -1. *at: the
  // face's index, -1 when no distance compares (non-finite input). Also tracked_points.h's.
  static double nearest(const Vec3& x, const FanFace* fan, int n_fan, double stop, int first,
                        int* at) {
    return first < 0 ? nearest_from(x, fan, n_fan, stop, -1, HUGE_VAL, at)
                     : nearest_from(x, fan, n_fan, stop, first,
                                    point_triangle_squared_distance(x, fan[first].a, fan[first].b,
                                                                    fan[first].c),
                                    at);
  }
  // nearest() when x's squared distance to face `first` (>= 0) is known already: first2.
  static double nearest_from(const Vec3& x, const FanFace* fan, int n_fan, double stop, int first,
                             double first2, int* at);

 private:
  static constexpr uint32_t kNone = 0xffffffffu;
  struct Moving {
    uint32_t point;
    int hint;  // the fan index of the face it was on, or -1
  };
  static constexpr int kMaxMoving = 1 + 64 * kKept;  // v and the points of 64 faces
  // Gathers v and the points of old_faces into `moving` (room for kMaxMoving), emptying
  // those faces when `take`. Returns their count.
  int gather(uint32_t v, const uint32_t* old_faces, int n_old, const FanFace* fan, int n_fan,
             bool take, Moving* moving) const;
  // The input faces around `vertex` but `skip`: where one is nearer to x than *d, the
  // nearest of them goes to *f and its distance to *d.
  void nearer_around(const Vec3& x, uint32_t vertex, uint32_t skip, const InputSurface& input,
                     uint32_t* f, double* d) const;
  // The input vertices all of whose faces one point's search has tried: none of those faces
  // is nearer than the distance it had then, which only decreases after, so a vertex here
  // needs no second look (the same faces found, fewer distances: the walks of the textured
  // 950K-face mesh's last collapses tried each corner's faces up to three times).
  struct Searched {
    static constexpr int kMost = kMaxMoved + 2 + 3 * kWalkSteps;  // region, kept point, walk
    uint32_t vertex[kMost];
    int n = 0;
    bool has(uint32_t w) const { return std::find(vertex, vertex + n, w) != vertex + n; }
    void add(uint32_t w) {
      if (n < kMost) vertex[n++] = w;  // when full, a vertex is searched again: the same faces
    }
  };
  // From input face *f at distance d of x, to the input face sharing a corner with it
  // nearest to x, while one is nearer (a descent on the input surface), until within
  // `stop` or after kWalkSteps steps; *f where it ends, and its distance. Corners in
  // `searched` are not searched again; those it searches join it.
  double walk_input(const Vec3& x, uint32_t* f, double d, double stop, const InputSurface& input,
                    Searched& searched) const;
  Vec3 position(uint32_t v) const {
    const float* p = xyz_ + 3 * std::size_t{v};
    return Vec3(p[0], p[1], p[2]);
  }

  std::vector<uint32_t> point_;  // kKept per face: vertex ids, kNone where empty
  std::vector<float> distance_;  // their distance to that face
  const float* xyz_ = nullptr;
};

}  // namespace pm::collapse_loop
