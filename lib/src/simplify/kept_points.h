// The fast loop's measured error (fast_loop.h): removed input vertices carried on the faces
// of the simplified surface, as RemovedPoints carries them for the default loop (after Klein,
// Liebich and Straßer 1996, "Mesh reduction with error control", who keep the
// correspondence between the input and the reduced mesh to bound their distance), but a
// face keeps only its kKept farthest points. The Hausdorff distance of a level to the input
// is a maximum, made of the farthest points; the nearer ones seldom become the farthest, so
// dropping them costs the measure little, and bounds its cost: a collapse measures at most
// 1 + kKept points per face of v's fan against that fan, however many points its faces have
// absorbed (where RemovedPoints samples up to 512 per collapse). And the other way round:
// the centroids of the faces that change and the midpoints of their new edges, to the faces
// they replace (where RemovedPoints measures them against the input faces around, which
// costs as much as the whole default loop: measured in tests/bench/fast.md's notes). Flat arrays; safe on
// several threads for collapses whose faces are apart (the fast loop's regions): all
// scratch is on the stack. Internal to simplify/.
//
// What it measures is a lower bound of the distance of the removed input vertices to the
// surface (the dropped points are not counted): it orders the collapses. The record of a
// collapse is an upper bound: the points left off a list hand their distance to a slack
// per face, dropped_points_bound.h, which bounds them from then on without measuring them.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "simplify/geometry.h"

namespace pm::fast_loop {

class DroppedPointsBound;

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
    Vec3 centre;
    double radius2;  // squared
    static FanFace make(uint32_t face, const Vec3& a, const Vec3& b, const Vec3& c) {
      const Vec3 centre = (a + b + c) / 3.0;
      const double r2 =
          std::max({(a - centre).sqrnorm(), (b - centre).sqrnorm(), (c - centre).sqrnorm()});
      return {face, a, b, c, centre, r2};
    }
  };

  // n_faces faces, none holding a point yet; xyz, the input's positions (three per vertex),
  // stays the caller's and must not change. n_faces 0: frees the memory.
  void reset(std::size_t n_faces, const float* xyz);

  // The measured distance of the collapse v -> u is the larger of points_distance() and
  // surface_distance() (fast_loop.h's apply() asks for the second only when the first
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

  // Schroeder's metric measures more (fast_schroeder.cpp): the largest of `worst` and of the
  // distances from a grid of points on each fan to the other fan, that is from the old fan
  // (v's faces before the collapse, the two at v-u with them) to the new one (`fan`), and
  // from the moved faces (its first `moved`) to the old one. Where the new fan leaves part of
  // the old surface (a boundary or a crease pulled in), the removed points there were mostly
  // dropped from the lists (near their face, so not among its farthest), and only the first
  // sees them; the finer grid on the moved faces finds where they bulge away from the old
  // surface better than surface_distance()'s centroids and midpoints.
  //
  // Steps per edge of the grids (a corner of a face is no point of its grid), on the old
  // fan and on the moved faces. Schroeder's metric: fast_schroeder.cpp. The quadric metric
  // (fast_loop.h, apply(); with no guess of the measure in the queued key, queued_key()),
  // on the 8 shared meshes at 50/10/2% of the faces (24 points, fast/default Hausdorff H
  // and RMS, tests/bench/fast.md), before -> after: points above 1.05x in H 8 -> 3 (largest
  // 1.19 -> 1.46, spot at 10%; armadillo 10% 1.19 -> 0.98, nefertiti 2% 1.18 -> 1.12,
  // rocker-arm 10% and 2% 1.12 -> 0.96, 0.99), H geometric mean 0.98 -> 0.91; RMS 0 -> 0
  // above (largest 1.03 -> 1.05). At 9 targets (45/50/55, 9/10/11, 1.8/2/2.2%: 72 points)
  // 25 -> 8 above in H, RMS 1 -> 1. Where the fast loop's levels were farthest (armadillo
  // 10%, nefertiti 2%, spot 10%), the level lay away from the input (the backward
  // distance, level to input), not an input point away from the level: the centroids and
  // midpoints of surface_distance() see too little of the new surface's bulge. Variants,
  // 24 and 72 points above 1.05x in H, RMS above at 72: these steps with the guess 0.85
  // (the earlier kGuess) 3, 10, 6; 3 and 5 as Schroeder's 4, 10, 3 (with the guess 5, 11,
  // 8); 2 and 4: 2, 12, 2; the moved faces' grid alone (5 steps) 4, 10, 1; the old fan's
  // alone 9 at 24; 2 and 2 or 3 and 2: 27 at 72. Only for boundary or crease collapses:
  // no change (the cause is not there, unlike Schroeder's metric). A bound accumulated
  // per face (each step's distance plus the old face's, Guéziec 1996's tolerance volumes
  // in spirit) overestimates: 14 above at 24 points, RMS 14. The fast encode: 0.23-0.85x
  // the default loop's in tests/bench/fast.md at load 6 (0.15-0.34x before, load 5-7).
  struct Grids {
    int old_fan, moved_faces;
  };
  static constexpr Grids kSchroederGrids{3, 5}, kQuadricGrids{2, 3};
  static double fans_apart(const FanFace* fan, int moved, int n_fan, const FanFace* old_fan,
                           int n_old, double worst, Grids steps);
  // The largest of `worst` and the distances from the grid of `steps` per edge on each face
  // of `from` to the nearest face of `to` (a face of the same id tried first).
  static double grid_distance(const FanFace* from, int n_from, const FanFace* to, int n_to,
                              int steps, double worst);

  // Hands v and the points of old_faces to their nearest fan face, each keeping its kKept
  // farthest, and returns the largest distance of a point to its new face. The points
  // left off a face's list go to `dropped` with their distance (dropped_points_bound.h).
  // Call before the collapse changes the faces (old_faces lose their points first: some
  // are in the fan).
  double collapse(uint32_t v, const uint32_t* old_faces, int n_old, const FanFace* fan,
                  int n_fan, DroppedPointsBound& dropped);

 private:
  static constexpr uint32_t kNone = 0xffffffffu;
  struct Moving {
    uint32_t point;
    int hint;  // the fan index of the face it was on, or -1
  };
  static constexpr int kMaxMoving = 1 + 64 * kKept;  // v and the points of 64 faces
  // The nearest fan face to x and its distance; stops at the first face within `stop`
  // (then the distance is at most stop). `first`: a face to try first, or -1.
  static double nearest(const Vec3& x, const FanFace* fan, int n_fan, double stop, int first,
                        int* at);
  // Gathers v and the points of old_faces into `moving` (room for kMaxMoving), emptying
  // those faces when `take`. Returns their count.
  int gather(uint32_t v, const uint32_t* old_faces, int n_old, const FanFace* fan, int n_fan,
             bool take, Moving* moving) const;
  Vec3 position(uint32_t v) const {
    const float* p = xyz_ + 3 * std::size_t{v};
    return Vec3(p[0], p[1], p[2]);
  }

  std::vector<uint32_t> point_;  // kKept per face: vertex ids, kNone where empty
  std::vector<float> distance_;  // their distance to that face
  const float* xyz_ = nullptr;
};

}  // namespace pm::fast_loop
