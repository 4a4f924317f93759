// The collapse loop's kept points: see kept_points.h (after Klein, Liebich and Straßer 1996).
#include "simplify/kept_points.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <utility>

#include "core/memory_pages.h"

namespace pm::collapse_loop {

void KeptPoints::reset(std::size_t n_faces, const float* xyz) {
  if (n_faces == 0) {  // the loop is over: the memory goes back
    std::vector<uint32_t>().swap(point_);
    std::vector<float>().swap(distance_);
    xyz_ = nullptr;
    return;
  }
  xyz_ = xyz;
  detail::assign_preferring_huge_pages(point_, kKept * n_faces, kNone);
  detail::assign_preferring_huge_pages(distance_, kKept * n_faces, 0.0f);
}

double KeptPoints::nearest_from(const Vec3& x, const FanFace* fan, int n_fan, double stop,
                                int first, double first2, int* at) {
  double best = HUGE_VAL, best2 = HUGE_VAL;  // best is the root of best2
  int best_at = -1;
  if (first >= 0) {
    best2 = first2;
    best = std::sqrt(best2);
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
      const double beyond = best + fan[i].radius;
      if (to_centre2 >= beyond * beyond) continue;
    }
    // The root only when the square is below best's: the root keeps the order, so a square
    // at or above it is a distance at or above `best`.
    const double d2 = point_triangle_squared_distance(x, fan[i].a, fan[i].b, fan[i].c);
    if (!(d2 < best2)) continue;
    const double d = std::sqrt(d2);
    if (d < best) {
      best2 = d2;
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
  // The faces' lists were asked for ahead (prefetch(): the collapse loop does when it reads
  // v's ring); the points' positions are below (input_distance() says why).
  // The fan lists v's faces but those at v-u first, in the order of old_faces.
  for (int i = 0, j = 0; i < n_old; ++i) {
    const uint32_t f = old_faces[i];
    const int hint = j < n_fan && fan[j].face == f ? j++ : -1;
    uint32_t* kept = const_cast<uint32_t*>(&point_[kKept * std::size_t{f}]);
    for (int k = 0; k < kKept && kept[k] != kNone; ++k) {
      moving[n++] = {kept[k], hint};
      if (take) kept[k] = kNone;
    }
  }
  for (int i = 0; i < n; ++i) __builtin_prefetch(xyz_ + 3 * std::size_t{moving[i].point});
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
  Vec3 points[3 * kMaxMoved];
  int hint[3 * kMaxMoved];
  int n_points = 0;
  for (int i = 0, j = 0; i < moved && i < kMaxMoved; ++i) {
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

void KeptPoints::InputSurface::build(std::vector<uint32_t> corner_ids, std::size_t n_vertices) {
  corners = std::move(corner_ids);
  begin.assign(n_vertices + 1, 0);
  for (uint32_t x : corners) ++begin[x + 1];
  for (std::size_t x = 0; x < n_vertices; ++x) begin[x + 1] += begin[x];
  faces.resize(corners.size());
  std::vector<uint32_t> fill(begin.begin(), begin.end() - 1);
  for (std::size_t i = 0; i < corners.size(); ++i)
    faces[fill[corners[i]]++] = static_cast<uint32_t>(i / 3);
}

void KeptPoints::nearer_around(const Vec3& x, uint32_t vertex, uint32_t skip,
                               const InputSurface& input, uint32_t* f, double* d) const {
  // Only a square below *d's (with room for the rounding of *d * *d and of the root) can
  // have a root below *d: the others are not rooted (the root keeps the order, nearest()).
  // Where *d * *d is below the normal doubles, its rounding has no such bound: every face is
  // rooted (below 0).
  constexpr double kRoom = 1 + 1e-14;
  auto square_bound = [](double distance) {
    const double bound = distance * distance * kRoom;
    return bound >= std::numeric_limits<double>::min() ? bound : -1.0;
  };
  double below = square_bound(*d);
  for (uint32_t i = input.begin[vertex]; i < input.begin[vertex + 1]; ++i) {
    const uint32_t g = input.faces[i];
    if (g == skip) continue;
    const uint32_t* c = &input.corners[3 * std::size_t{g}];
    const double dg2 =
        point_triangle_squared_distance(x, position(c[0]), position(c[1]), position(c[2]));
    if (below >= 0 && !(dg2 < below)) continue;
    const double dg = std::sqrt(dg2);
    if (dg < *d) *d = dg, *f = g, below = square_bound(*d);
  }
}

double KeptPoints::walk_input(const Vec3& x, uint32_t* f, double d, double stop,
                              const InputSurface& input, Searched& searched) const {
  for (int step = 0; step < kWalkSteps && d > stop; ++step) {
    uint32_t best_f = *f;
    double best_d = d;
    const uint32_t* c = &input.corners[3 * std::size_t{*f}];
    for (int k = 0; k < 3; ++k) {
      if (searched.has(c[k])) continue;
      nearer_around(x, c[k], *f, input, &best_f, &best_d);
      searched.add(c[k]);
    }
    if (best_f == *f) break;  // a local minimum of the distance on the input
    *f = best_f;
    d = best_d;
  }
  return d;
}

double KeptPoints::input_distance(const FanFace* fan, int moved, const Vec3& pu,
                                  const uint32_t* region, int n_region, const uint32_t* old_faces,
                                  int n_old, const InputSurface& input, double worst) const {
  if (moved == 0) return worst;
  // The grid points: each moved face's inside, then its edges at u, those its neighbour
  // shares measured once (the same two corners, the same sums: the same point, bit for bit).
  constexpr int kPerFace = (kInputSteps - 1) * (kInputSteps - 2) / 2 + 2 * (kInputSteps - 1);
  Vec3 points[kMaxMoved * kPerFace];
  int n_points = 0;
  for (int g = 0; g < moved && g < kMaxMoved; ++g) {
    const Vec3* corners[3] = {&fan[g].a, &fan[g].b, &fan[g].c};
    int at_u = 0;
    while (at_u < 3 && *corners[at_u] != pu) ++at_u;
    if (at_u == 3) at_u = 0;  // no corner at u: any, its edges are measured then
    const Vec3 &p0 = *corners[at_u], &p1 = *corners[(at_u + 1) % 3], &p2 = *corners[(at_u + 2) % 3];
    for (int i = 1; i < kInputSteps; ++i)
      for (int j = 1; i + j < kInputSteps; ++j)
        points[n_points++] = (p0 * double(kInputSteps - i - j) + p1 * double(i) + p2 * double(j)) /
                             double(kInputSteps);
    for (const Vec3* w : {&p1, &p2})
      for (int t = 1; t < kInputSteps; ++t) {
        const Vec3 x = (p0 * double(kInputSteps - t) + *w * double(t)) / double(kInputSteps);
        if (std::find(points, points + n_points, x) == points + n_points) points[n_points++] = x;
      }
  }
  // The region's input faces, each once (a small open-addressed set on the stack). The
  // input's rows are far apart in memory, and a face's corners and their positions farther:
  // gathered in steps (all rows' starts, all rows, all new faces' corners, all their
  // positions), each step asks for what the next reads before reading it, so that the
  // cache misses overlap instead of following each other (the gathering took 14% of the
  // loop on nefertiti, most of it waiting for memory).
  constexpr int kSlots = 4 * kMaxInputFaces;
  uint32_t seen[kSlots];
  std::fill(seen, seen + kSlots, kNone);
  FanFace faces[kMaxInputFaces];
  int n_faces = 0;
  bool region_whole = true;  // every input face around the region is in `faces`
  auto add_around = [&](const uint32_t* xs, int n_xs) {
    for (int i = 0; i < n_xs; ++i) __builtin_prefetch(&input.begin[xs[i]]);
    for (int i = 0; i < n_xs; ++i) __builtin_prefetch(&input.faces[input.begin[xs[i]]]);
    uint32_t added[kMaxInputFaces];
    int n_added = 0;
    for (int k = 0; k < n_xs; ++k) {
      const uint32_t x = xs[k];
      for (uint32_t i = input.begin[x]; i < input.begin[x + 1]; ++i) {
        if (n_faces + n_added == kMaxInputFaces) {
          region_whole = false;
          break;
        }
        const uint32_t f = input.faces[i];
        uint32_t slot = (f * 0x9E3779B1u) & (kSlots - 1);  // Fibonacci hashing
        while (seen[slot] != kNone && seen[slot] != f) slot = (slot + 1) & (kSlots - 1);
        if (seen[slot] == f) continue;
        seen[slot] = f;
        added[n_added++] = f;
        __builtin_prefetch(&input.corners[3 * std::size_t{f}]);
      }
    }
    for (int i = 0; i < n_added; ++i) {
      const uint32_t* c = &input.corners[3 * std::size_t{added[i]}];
      for (int k = 0; k < 3; ++k) __builtin_prefetch(xyz_ + 3 * std::size_t{c[k]});
    }
    for (int i = 0; i < n_added; ++i) {
      const uint32_t* c = &input.corners[3 * std::size_t{added[i]}];
      faces[n_faces++] = FanFace::make(added[i], position(c[0]), position(c[1]), position(c[2]));
    }
  };
  // A point within `worst` of some region face cannot raise it, whatever is nearer still;
  // the others (pending) keep their nearest region face and its distance.
  int pending[kMaxMoved * kPerFace];
  int n_pending = 0;
  double pending_d[kMaxMoved * kPerFace];
  uint32_t pending_f[kMaxMoved * kPerFace];
  add_around(region, n_region);
  {
    int hint = -1;  // the points come face by face: the last one's face first
    for (int p = 0; p < n_points; ++p) {
      int at;
      const double d = nearest(points[p], faces, n_faces, worst, hint, &at);
      if (at >= 0) hint = at;
      if (!(d > worst) || d == HUGE_VAL) continue;
      pending_d[n_pending] = d;
      pending_f[n_pending] = faces[at].face;
      pending[n_pending++] = p;
    }
  }
  if (n_pending == 0) return worst;
  // A point not settled starts from the nearer of its nearest region face and the nearest
  // input face around the kept point nearest to it (the kept points lie on the old faces,
  // among the input faces the moved ones have come to stand for), then walks on the input.
  Vec3 kept_at[kMaxMoved * kKept];
  uint32_t kept_points[kMaxMoved * kKept];
  int n_kept = 0;
  for (int i = 0; i < n_old; ++i) {
    const uint32_t* kept = &point_[kKept * std::size_t{old_faces[i]}];
    for (int k = 0; k < kKept && kept[k] != kNone; ++k) kept_points[n_kept++] = kept[k];
  }
  for (int i = 0; i < n_kept; ++i) kept_at[i] = position(kept_points[i]);
  for (int p = 0; p < n_pending; ++p) {
    double d = pending_d[p];
    if (!(d > worst)) continue;
    const Vec3& x = points[pending[p]];
    uint32_t f = pending_f[p];
    int nearest_kept = -1;
    double nearest_kept2 = HUGE_VAL;
    for (int i = 0; i < n_kept; ++i) {
      const double d2 = (x - kept_at[i]).sqrnorm();
      if (d2 < nearest_kept2) nearest_kept2 = d2, nearest_kept = i;
    }
    // The region's vertices when all their faces were tried: the point's distance is at most
    // theirs (nearest() stopped at no face: the point is farther than `worst`, its `stop`).
    Searched searched;
    if (region_whole)
      for (int i = 0; i < n_region; ++i) searched.add(region[i]);
    if (nearest_kept >= 0 && !searched.has(kept_points[nearest_kept])) {
      nearer_around(x, kept_points[nearest_kept], kNone, input, &f, &d);
      searched.add(kept_points[nearest_kept]);
    }
    d = walk_input(x, &f, d, worst, input, searched);
    if (d > worst) worst = d;
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
    const double d = nearest(position(moving[i].point), fan, n_fan, worst, moving[i].hint, &at);
    if (d > worst) worst = d;
  }
  return worst;
}

double KeptPoints::collapse(uint32_t v, const uint32_t* old_faces, int n_old, const FanFace* fan,
                            int n_fan) {
  if (n_fan == 0) return 0;
  Moving moving[kMaxMoving];
  const int n_moving = gather(v, old_faces, n_old, fan, n_fan, true, moving);
  double farthest = 0;
  for (int i = 0; i < n_moving; ++i) {
    int at;
    const double d = nearest(position(moving[i].point), fan, n_fan, 0.0, moving[i].hint, &at);
    if (at < 0) continue;  // no distance compares (not on finite input): the record's
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
    if (kept[slot] != kNone && !(float(d) > kept_distance[slot])) continue;
    kept[slot] = moving[i].point;
    kept_distance[slot] = float(d);
  }
  return farthest;
}

}  // namespace pm::collapse_loop
