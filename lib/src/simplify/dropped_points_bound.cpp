// The slack of the collapse loop's dropped points: see dropped_points_bound.h (after Cohen,
// Manocha and Olano 1997's successive mappings).
#include "simplify/dropped_points_bound.h"

#include "core/huge_pages.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace pm::collapse_loop {
namespace {

struct Point2 {
  double x, y;
};
double cross(const Point2& o, const Point2& a, const Point2& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

// A triangle of the plane with the 3D triangle over it: affine from one to the other.
struct Lifted {
  Point2 a, b, c;  // counter-clockwise
  Vec3 pa, pb, pc;
  double area2;  // twice the area, > 0
  Vec3 at(const Point2& x) const {
    const double beta = cross(a, x, c) / area2, gamma = cross(a, b, x) / area2;
    return pa + (pb - pa) * beta + (pc - pa) * gamma;
  }
};

// A convex polygon of the plane: a triangle clipped by others' half-planes (at most 3 + 3
// corners for one triangle against another).
struct Polygon {
  Point2 p[9];
  int n = 0;
};

// Keeps the part of `in` to the left of a -> b (Sutherland and Hodgman 1974).
void clip(const Polygon& in, const Point2& a, const Point2& b, Polygon& out) {
  out.n = 0;
  for (int i = 0; i < in.n; ++i) {
    const Point2& p = in.p[i];
    const Point2& q = in.p[(i + 1) % in.n];
    const double sp = cross(a, b, p), sq = cross(a, b, q);
    if (sp >= 0) out.p[out.n++] = p;
    if ((sp >= 0) != (sq >= 0)) {
      const double t = sp / (sp - sq);
      out.p[out.n++] = {p.x + t * (q.x - p.x), p.y + t * (q.y - p.y)};
    }
  }
}

// The corners of the overlay cell old ∩ next; n = 0 when they do not overlap.
void overlay_cell(const Lifted& old, const Lifted& next, Polygon& cell) {
  Polygon a, b;
  a.n = 3;
  a.p[0] = old.a, a.p[1] = old.b, a.p[2] = old.c;
  clip(a, next.a, next.b, b);
  clip(b, next.b, next.c, a);
  clip(a, next.c, next.a, cell);
}

bool disjoint_boxes(const Lifted& s, const Lifted& t) {
  auto lo = [](const Lifted& x, double Point2::*c) { return std::min({x.a.*c, x.b.*c, x.c.*c}); };
  auto hi = [](const Lifted& x, double Point2::*c) { return std::max({x.a.*c, x.b.*c, x.c.*c}); };
  return hi(s, &Point2::x) < lo(t, &Point2::x) || hi(t, &Point2::x) < lo(s, &Point2::x) ||
         hi(s, &Point2::y) < lo(t, &Point2::y) || hi(t, &Point2::y) < lo(s, &Point2::y);
}

// The projected area must be a fair share of the triangle's own (its plane at most about
// 89.9 degrees from the projection's), else the lift back to it magnifies rounding.
constexpr double kLeastProjectedShare = 1e-3;

bool make_lifted(const Point2& a, const Point2& b, const Point2& c, const Vec3& pa, const Vec3& pb,
                 const Vec3& pc, Lifted& out) {
  const double area2 = cross(a, b, c);
  if (!(area2 > kLeastProjectedShare * area_vector(pa, pb, pc).norm())) return false;
  out = {a, b, c, pa, pb, pc, area2};
  return true;
}

// The direction d of largest least d . n over the unit normals: the normals' mean first,
// then each normal, then a few steps from the best towards the normal it faces least
// (Cohen, Manocha and Olano 1997 solve this as a linear program; a few candidates find a
// direction for all but the sharpest stars, which take the coarse bound). Zero when the
// mean is zero and no candidate faces every normal.
Vec3 best_direction(const Vec3& mean, const Vec3* normals, int n) {
  auto least = [&](const Vec3& d, int* at) {
    double m = HUGE_VAL;
    for (int i = 0; i < n; ++i) {
      const double c = d | normals[i];
      if (c < m) m = c, *at = i;
    }
    return m;
  };
  Vec3 best(0, 0, 0);
  double best_least = -HUGE_VAL;
  int worst = 0;
  auto consider = [&](const Vec3& d) {
    const double norm = d.norm();
    if (!(norm > 0)) return;
    int at = 0;
    const double m = least(d / norm, &at);
    if (m > best_least) best_least = m, best = d / norm, worst = at;
  };
  consider(mean);
  if (n == 0 || best_least > 0.5) return best;  // within 60 degrees of every face: enough
  for (int i = 0; i < n; ++i) consider(normals[i]);
  for (int step = 0; step < 8 && n > 0; ++step) consider(best + normals[worst] * 0.5);
  return best_least > 0 ? best : Vec3(0, 0, 0);
}

}  // namespace

void DroppedPointsBound::reset(std::size_t n_faces) {
  if (n_faces == 0) {
    std::vector<float>().swap(slack_);
    return;
  }
  detail::assign_preferring_huge_pages(slack_, n_faces, -1.0f);
  lost_ = false;
}

void DroppedPointsBound::raise(uint32_t face, double d) {
  if (!(d <= FLT_MAX)) {  // past the largest float (or NaN): no finite slack holds it
    lost_ = true;
    return;
  }
  float f = static_cast<float>(d);
  if (double(f) < d) f = std::nextafter(f, FLT_MAX);
  slack_[face] = std::max(slack_[face], f);
}

bool DroppedPointsBound::coarse(const Vec3& a, const Vec3& b, const Vec3& c, double r,
                                const KeptPoints::FanFace* fan, int n_fan, double* to_fan) {
  if (n_fan <= 0) return false;
  // The points of the grid: (i, j) at a + i/N (b - a) + j/N (c - a), i + j <= N, and
  // their distances to each fan face.
  constexpr int N = kCoarseSplits;
  constexpr int kPoints = (N + 1) * (N + 2) / 2;
  auto index = [](int i, int j) { return j * (N + 1) - j * (j - 1) / 2 + i; };
  constexpr int kMaxFan = 128;  // two rings of the collapse loop's largest valence
  if (n_fan > kMaxFan) return false;
  // Squared distances: their roots are taken only where they decide (the root keeps the
  // order, so the largest square's root is the largest distance, and a square at or above
  // the best's is a distance at or above the best).
  double squared[kPoints * kMaxFan];  // kPoints per fan face
  for (int j = 0; j <= N; ++j)
    for (int i = 0; i + j <= N; ++i) {
      const Vec3 x = a + (b - a) * (double(i) / N) + (c - a) * (double(j) / N);
      for (int t = 0; t < n_fan; ++t)
        squared[std::size_t{kPoints} * t + index(i, j)] =
            point_triangle_squared_distance(x, fan[t].a, fan[t].b, fan[t].c);
    }
  // Each small triangle of the grid: its best face, by its corners.
  auto piece = [&](int p, int q, int s) {
    double best = HUGE_VAL, best2 = HUGE_VAL;  // best is best2's root
    int best_at = -1;
    for (int t = 0; t < n_fan; ++t) {
      const double* d2 = &squared[std::size_t{kPoints} * t];
      const double h2 = std::max({d2[p], d2[q], d2[s]});
      if (!(h2 < best2)) continue;
      const double h = std::sqrt(h2);
      if (h < best) best = h, best2 = h2, best_at = t;
    }
    if (best_at >= 0) to_fan[best_at] = std::max(to_fan[best_at], r + best);
    return best_at >= 0;
  };
  bool placed = true;
  for (int j = 0; j < N; ++j)
    for (int i = 0; i + j < N; ++i) {
      placed = piece(index(i, j), index(i + 1, j), index(i, j + 1)) && placed;
      if (i + j + 1 < N)
        placed = piece(index(i + 1, j), index(i + 1, j + 1), index(i, j + 1)) && placed;
    }
  return placed;
}

double DroppedPointsBound::collapse(const Star& star, const KeptPoints::FanFace* fan, int n_fan) {
  constexpr int kMaxRing = 64;  // as the collapse loop's valence
  const int n = star.n, n_faces = star.closed ? n : n - 1;
  if (n_faces <= 0) return 0;
  if (n > kMaxRing) return HUGE_VAL;  // beyond the collapse loop's valence: never
  bool any = false;
  for (int i = 0; i < n_faces; ++i) any = any || slack_[star.faces[i]] >= 0;
  if (!any) return 0;  // the usual case early on: nothing dropped around v
  auto next = [&](int i) { return i + 1 == n ? 0 : i + 1; };
  auto removed = [&](int i) { return star.faces[i] == star.fl || star.faces[i] == star.fr; };
  const bool u_in_ring = star.u_at >= 0 && star.u_at < n;  // always, as u is v's neighbour
  const Vec3& pu = star.ring[u_in_ring ? star.u_at : 0];

  // The plane: across a direction that every face, before and after, faces (the larger
  // the least cosine, the less the projection folds or magnifies).
  Vec3 normals[2 * kMaxRing];
  int n_normals = 0;
  Vec3 normal(0, 0, 0);
  for (int i = 0; i < n_faces; ++i) {
    const int j = next(i);
    const Vec3 a = area_vector(star.v, star.ring[i], star.ring[j]);
    normal += a;
    if (a.norm() > 0) normals[n_normals++] = a / a.norm();
    if (removed(i)) continue;
    const Vec3 b = area_vector(pu, star.ring[i], star.ring[j]);
    if (b.norm() > 0) normals[n_normals++] = b / b.norm();
  }
  normal = best_direction(normal, normals, n_normals);
  Lifted old_face[kMaxRing], new_face[kMaxRing];
  bool mapped = u_in_ring && normal.norm() > 0;
  // An open ring maps onto the new fan only when u is one of its ends (v collapses along
  // the boundary): the part of v's faces beyond the new boundary edge then maps onto it.
  const bool open_end = !star.closed && (star.u_at == 0 || star.u_at == n - 1);
  mapped = mapped && (star.closed || open_end);
  Point2 o{}, w[kMaxRing];
  if (mapped) {
    const Vec3 z = normal / normal.norm();
    const Vec3 helper = std::abs(z[0]) < 0.6 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    Vec3 e1 = helper % z;
    e1 /= e1.norm();
    const Vec3 e2 = z % e1;
    auto project = [&](const Vec3& p) { return Point2{p | e1, p | e2}; };
    o = project(star.v);
    for (int i = 0; i < n; ++i) w[i] = project(star.ring[i]);
    for (int i = 0; i < n_faces && mapped; ++i) {
      const int j = next(i);
      mapped = make_lifted(o, w[i], w[j], star.v, star.ring[i], star.ring[j], old_face[i]);
      if (mapped && !removed(i))
        mapped = make_lifted(w[star.u_at], w[i], w[j], pu, star.ring[i], star.ring[j], new_face[i]);
    }
  }
  // The strip between v and the new boundary edge (open ring): the triangle ring[n - 1], v,
  // ring[0], mapped to that edge, which the moved face holding both ring ends carries.
  Lifted strip{};
  bool has_strip = false;
  int edge_face = -1;
  if (mapped && open_end) {
    edge_face = star.u_at == 0 ? n - 2 : 0;
    if (edge_face < 0 || removed(edge_face)) {
      mapped = false;
    } else {
      const double area2 = cross(w[n - 1], o, w[0]);
      if (area2 > 0)
        has_strip = make_lifted(w[n - 1], o, w[0], star.ring[n - 1], star.v, star.ring[0], strip);
      else if (area2 < 0)
        has_strip = make_lifted(w[0], o, w[n - 1], star.ring[0], star.v, star.ring[n - 1], strip);
      // A strip of no area holds no point of v's faces; one too thin to lift: coarse bound.
      if (area2 != 0 && !has_strip) mapped = false;
    }
  }

  // The slack each new face takes, by moved face (mapped) or fan face (coarse).
  double to_moved[kMaxRing], to_fan[2 * kMaxRing];
  std::fill(to_moved, to_moved + n_faces, -1.0);
  std::fill(to_fan, to_fan + n_fan, -1.0);
  double largest = 0;
  bool lost = false;
  for (int i = 0; i < n_faces; ++i) {
    const double r = slack_[star.faces[i]];
    if (r < 0) continue;
    if (mapped) {
      Polygon cell;
      for (int j = 0; j < n_faces; ++j) {
        if (removed(j) || disjoint_boxes(old_face[i], new_face[j])) continue;
        overlay_cell(old_face[i], new_face[j], cell);
        if (cell.n == 0) continue;
        // The distance to the new face itself, at most the mapped point's: convex along g
        // too, so its largest over the cell is at the cell's corners.
        const Lifted& t = new_face[j];
        double h2 = 0;  // the largest squared distance: its root is the largest distance
        for (int k = 0; k < cell.n; ++k) {
          // A corner at a ring vertex of both faces (clip() copies the corners it keeps, so
          // it is that vertex exactly) lifts to the vertex itself, a corner of t: at 0. Two
          // in five of the cells' corners on nefertiti after two Loop steps.
          const Point2& p = cell.p[k];
          auto at_ring = [&](int x) { return p.x == w[x].x && p.y == w[x].y; };
          if ((at_ring(i) && (i == j || i == next(j))) ||
              (at_ring(next(i)) && (next(i) == j || next(i) == next(j))))
            continue;
          h2 = std::max(h2, point_triangle_squared_distance(old_face[i].at(p), t.pa, t.pb, t.pc));
        }
        to_moved[j] = std::max(to_moved[j], r + std::sqrt(h2));
      }
      if (has_strip && !disjoint_boxes(old_face[i], strip)) {
        overlay_cell(old_face[i], strip, cell);
        const Lifted& t = new_face[edge_face];  // it holds the edge
        double h2 = -1;
        for (int k = 0; k < cell.n; ++k) {
          const Vec3 x = old_face[i].at(cell.p[k]);
          h2 = std::max(h2, point_triangle_squared_distance(x, t.pa, t.pb, t.pc));
        }
        if (h2 >= 0) to_moved[edge_face] = std::max(to_moved[edge_face], r + std::sqrt(h2));
      }
    } else {
      if (!coarse(star.v, star.ring[i], star.ring[next(i)], r, fan, n_fan, to_fan)) lost = true;
    }
  }
  for (int i = 0; i < n_faces; ++i) slack_[star.faces[i]] = -1.0f;
  for (int j = 0; j < n_faces; ++j)
    if (to_moved[j] >= 0) {
      raise(star.faces[j], to_moved[j]);
      largest = std::max(largest, to_moved[j]);
    }
  for (int j = 0; j < n_fan; ++j)
    if (to_fan[j] >= 0) {
      raise(fan[j].face, to_fan[j]);
      largest = std::max(largest, to_fan[j]);
    }
  return lost ? HUGE_VAL : largest;
}

}  // namespace pm::collapse_loop
