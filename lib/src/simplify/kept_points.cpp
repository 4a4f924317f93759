// The fast loop's kept points: see kept_points.h (after Klein, Liebich and Straßer 1996).
#include "simplify/kept_points.h"

#include <cfloat>

#include "simplify/dropped_points_bound.h"

#include <algorithm>
#include <cmath>

namespace pm::fast_loop {

void KeptPoints::reset(std::size_t n_faces, const float* xyz) {
  if (n_faces == 0) {  // the loop is over: the memory goes back
    std::vector<uint32_t>().swap(point_);
    std::vector<float>().swap(distance_);
    xyz_ = nullptr;
    return;
  }
  xyz_ = xyz;
  point_.assign(kKept * n_faces, kNone);
  distance_.assign(kKept * n_faces, 0.0f);
}

double KeptPoints::nearest(const Vec3& x, const FanFace* fan, int n_fan, double stop, int first,
                           int* at) {
  double best = HUGE_VAL;
  int best_at = -1;
  if (first >= 0) {
    best = point_triangle_distance(x, fan[first].a, fan[first].b, fan[first].c);
    best_at = first;
    if (best <= stop) {
      *at = best_at;
      return best;
    }
  }
  for (int i = 0; i < n_fan; ++i) {
    if (i == first) continue;
    // |x - centre| >= best + radius: the whole face is at least `best` away.
    const double to_centre2 = (x - fan[i].centre).sqrnorm();
    if (best < HUGE_VAL && to_centre2 >= fan[i].radius2) {
      const double beyond = best + std::sqrt(fan[i].radius2);
      if (to_centre2 >= beyond * beyond) continue;
    }
    const double d = point_triangle_distance(x, fan[i].a, fan[i].b, fan[i].c);
    if (d < best) {
      best = d;
      best_at = i;
      if (best <= stop) break;
    }
  }
  *at = best_at;
  return best;
}

int KeptPoints::gather(uint32_t v, const uint32_t* old_faces, int n_old, const FanFace* fan,
                       int n_fan, bool take, Moving* moving) const {
  int n = 0;
  moving[n++] = {v, -1};
  for (int i = 0; i < n_old; ++i) {
    const uint32_t f = old_faces[i];
    int hint = -1;
    for (int j = 0; j < n_fan; ++j)
      if (fan[j].face == f) {
        hint = j;
        break;
      }
    uint32_t* kept = const_cast<uint32_t*>(&point_[kKept * std::size_t{f}]);
    for (int k = 0; k < kKept && kept[k] != kNone; ++k) {
      moving[n++] = {kept[k], hint};
      if (take) kept[k] = kNone;
    }
  }
  return n;
}

double KeptPoints::surface_distance(const FanFace* fan, int moved, const FanFace* old_fan,
                                    int n_old, const Vec3& pu, double worst) {
  if (moved == 0) return worst;
  // Each moved face's centroid and the midpoints of its edges at u. Its third edge, the
  // one away from u, is an edge of the face it replaces (same corners): on the old surface,
  // its midpoint is at distance 0 and cannot raise `worst`. Neighbouring faces share their
  // edge to u, so most midpoints come twice; a point measured again cannot raise `worst`
  // either, so it is measured once. Each point tries first the face its own face replaces
  // (the fan and old_fan list v's faces in the same order, old_fan with those at v-u too),
  // which holds most of them within `worst`.
  Vec3 points[3 * 64];
  int hint[3 * 64];
  int n_points = 0;
  for (int i = 0, j = 0; i < moved && i < 64; ++i) {
    while (j < n_old && old_fan[j].face != fan[i].face) ++j;
    const int same = j < n_old ? j : -1;
    const Vec3 &a = fan[i].a, &b = fan[i].b, &c = fan[i].c;
    hint[n_points] = same;
    points[n_points++] = (a + b + c) / 3.0;
    // The corner at u (by position: a corner elsewhere that coincides with u only adds
    // a point), and the edges at it.
    const Vec3* corners[3] = {&a, &b, &c};
    for (int k = 0; k < 3; ++k) {
      if (*corners[k] != pu) continue;
      for (const Vec3* other : {corners[(k + 1) % 3], corners[(k + 2) % 3]}) {
        const Vec3 x = (*corners[k] + *other) * 0.5;
        if (std::find(points, points + n_points, x) != points + n_points) continue;
        hint[n_points] = same;
        points[n_points++] = x;
      }
    }
  }
  for (int i = 0; i < n_points; ++i) {
    int at;
    const double d = nearest(points[i], old_fan, n_old, worst, hint[i], &at);
    if (d > worst && d != HUGE_VAL) worst = d;
  }
  return worst;
}

double KeptPoints::fans_apart(const FanFace* fan, int moved, int n_fan, const FanFace* old_fan,
                              int n_old, double worst, Grids steps) {
  worst = grid_distance(old_fan, n_old, fan, n_fan, steps.old_fan, worst);
  return grid_distance(fan, moved, old_fan, n_old, steps.moved_faces, worst);
}

double KeptPoints::grid_distance(const FanFace* from, int n_from, const FanFace* to, int n_to,
                                 int steps, double worst) {
  if (n_to == 0 || steps < 2) return worst;
  for (int g = 0; g < n_from; ++g) {
    // A moved face is on both fans: its points are nearest to itself, most within `worst`.
    int hint = -1;
    for (int j = 0; j < n_to; ++j)
      if (to[j].face == from[g].face) {
        hint = j;
        break;
      }
    const Vec3 &a = from[g].a, &b = from[g].b, &c = from[g].c;
    for (int i = 0; i <= steps; ++i)
      for (int j = 0; i + j <= steps; ++j) {
        const int k = steps - i - j;
        if (i == steps || j == steps || k == steps) continue;  // a corner
        const Vec3 x = (a * double(i) + b * double(j) + c * double(k)) / double(steps);
        int at;
        const double d = nearest(x, to, n_to, worst, hint, &at);
        if (d > worst && d != HUGE_VAL) worst = d;
      }
  }
  return worst;
}

double KeptPoints::points_distance(uint32_t v, const uint32_t* old_faces, int n_old,
                                   const FanFace* fan, int n_fan) const {
  if (n_fan == 0) return 0;
  Moving moving[kMaxMoving];
  const int n_moving = gather(v, old_faces, n_old, fan, n_fan, false, moving);
  // The largest over points of the distance to the nearest face: a point already within
  // the worst so far of some face cannot raise it, so its search stops there.
  double worst = 0;
  for (int i = 0; i < n_moving; ++i) {
    int at;
    const double d =
        nearest(position(moving[i].point), fan, n_fan, worst, moving[i].hint, &at);
    if (d > worst) worst = d;
  }
  return worst;
}

double KeptPoints::collapse(uint32_t v, const uint32_t* old_faces, int n_old, const FanFace* fan,
                            int n_fan, DroppedPointsBound& dropped) {
  if (n_fan == 0) return 0;
  Moving moving[kMaxMoving];
  const int n_moving = gather(v, old_faces, n_old, fan, n_fan, true, moving);
  double farthest = 0;
  for (int i = 0; i < n_moving; ++i) {
    int at;
    const double d = nearest(position(moving[i].point), fan, n_fan, 0.0, moving[i].hint, &at);
    if (at < 0) {  // no distance compares (not on finite input)
      dropped.lose();
      continue;
    }
    farthest = std::max(farthest, d);
    // Into the face's list, in place of its nearest point when the list is full.
    uint32_t* kept = &point_[kKept * std::size_t{fan[at].face}];
    float* kept_distance = &distance_[kKept * std::size_t{fan[at].face}];
    int slot = 0;
    for (int k = 0; k < kKept; ++k) {
      if (kept[k] == kNone) {
        slot = k;
        break;
      }
      if (kept_distance[k] < kept_distance[slot]) slot = k;
    }
    if (kept[slot] != kNone && !(float(d) > kept_distance[slot])) {
      dropped.drop(fan[at].face, d);
      continue;
    }
    // The point it pushes off: its distance, stored to the nearest float, rounded up.
    if (kept[slot] != kNone)
      dropped.drop(fan[at].face, std::nextafter(kept_distance[slot], FLT_MAX));
    kept[slot] = moving[i].point;
    kept_distance[slot] = float(d);
  }
  return farthest;
}

}  // namespace pm::fast_loop
