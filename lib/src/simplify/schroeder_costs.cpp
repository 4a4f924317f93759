// Schroeder's metric in the collapse loop (Metric::kSchroeder): the
// default loop's rules (commit 3cb92db; deleted in issue 25) on the collapse loop's
// flat arrays. Schroeder, Zarge and Lorensen 1992, "Decimation of triangle meshes": §3.1
// the vertex's kind (collapse_options.cpp, find_best(): simple, boundary, interior edge, corner),
// §3.2 its error (distance to the average plane, or to the boundary or feature line);
// Schroeder 1997, "A topology modifying progressive decimation algorithm": §3 the corner
// rule, §3.2 the shortest legal edge first. The formulas are schroeder_error.h's, the
// default loop's. In place of Schroeder 1997 §3.3's error accumulation, the collapse loop's
// measure (kept_points.h) joins the key as the larger of the two.
//
// The measure (collapse_measure.cpp) is the quadric metric's, the moved faces against the
// input (KeptPoints::input_distance()), and one more grid: the old fan against the new one
// (KeptPoints::kSchroederOldFanSteps), which sees the input points a collapse leaves behind
// where it pulls a boundary or a crease in. The queued key holds no guess of the measure:
// the order stays greedy. Measurements: tests/bench/fast_schroeder.md and
// tests/bench/README.md.
#include <algorithm>
#include <cmath>

#include "simplify/collapse_loop.h"
#include "simplify/schroeder_error.h"

namespace pm::collapse_loop {

void CollapseLoop::schroeder_costs(uint32_t v, VertexKind kind, const Neighbour* ring_v, int n,
                                   Option* options, int count, Star& star,
                                   const CornerAttributes::StarFields& fields) const {
  const Vec3 pv = point(v);
  const double weight = vertex_[v].sharp_corner ? kSharpCornerWeight : 1.0;
  // The attributes' error in model units joins the distance as the larger of the two, as
  // in the former default loop (Hoppe 1999, §4's attribute error, a squared distance).
  auto attribute_distance = [&](const Option& o) {
    if (!attributes_) return 0.0;
    const Neighbour& to = ring_v[o.index];
    return std::sqrt(attribute_cost(to.vertex, to.edge, star, fields));
  };
  if (kind != VertexKind::kCorner) {
    // One error whichever edge it goes along; the shortest legal edge first.
    double error = 0;
    if (kind == VertexKind::kSimple) {
      error = average_plane_distance(pv, [&](auto&& visit) {
        for (int i = 0; i < n; ++i) {
          const uint32_t e = ring_v[i].edge;
          if (half_[e].vertex != v) continue;  // a boundary's last entry: no face of its own
          const uint32_t f = e / 3;
          const Vec3 a = point(half_[3 * f].vertex), b = point(half_[3 * f + 1].vertex),
                     c = point(half_[3 * f + 2].vertex);
          const Vec3 twice = area_vector(a, b, c);
          const double length = twice.norm();
          visit(a, b, c, length > 0 ? twice / length : Vec3(0, 0, 0), 0.5 * length);
        }
      });
    } else if (count == 2) {
      // Boundary or interior edge: its options are its two special edges, whose far ends
      // make the line.
      error = point_line_distance(pv, point(ring_v[options[0].index].vertex),
                                  point(ring_v[options[1].index].vertex));
    }
    for (int i = 0; i < count; ++i) {
      options[i].rank = options[i].length;
      options[i].cost = weight * std::max(error, attribute_distance(options[i]));
    }
    return;
  }
  // A corner: the true distance of each collapse (v to the triangles that replace its
  // fan); its special edges first, the least of them, else the shortest other legal edge.
  const bool special_first =
      std::any_of(options, options + count, [](const Option& o) { return o.special; });
  for (int i = 0; i < count; ++i) {
    Option& o = options[i];
    const Neighbour& to = ring_v[o.index];
    const uint32_t u = to.vertex;
    const Sides s = sides(v, to.edge);
    const uint32_t fl = s.h == kNone ? kNone : s.h / 3, fr = s.t == kNone ? kNone : s.t / 3;
    const Vec3 pu = point(u);
    const double distance = collapse_distance_over(
        pv, pu,
        [&](auto&& visit) {
          for (int j = 0; j < n; ++j) {
            const uint32_t e = ring_v[j].edge;
            if (half_[e].vertex != v) continue;
            const uint32_t f = e / 3;
            if (f == fl || f == fr) continue;
            Vec3 corner[3];
            for (int k = 0; k < 3; ++k) {
              const uint32_t w = half_[3 * f + k].vertex;
              corner[k] = w == v ? pu : point(w);
            }
            visit(corner[0], corner[1], corner[2]);
          }
        },
        [&](auto&& visit) {
          for (int j = 0; j < n; ++j)
            if (ring_v[j].vertex != u) visit(point(ring_v[j].vertex));
        });
    o.cost = weight * std::max(distance, attribute_distance(o));
    o.rank = o.special == special_first ? o.cost : o.length;
  }
}

void CollapseLoop::mark_sharp_corners() {
  // As the former default loop: an edge of the input corner sharper than kSharpCornerDeg, by its
  // faces' normals, or a seam or material border (is_feature_edge's rule at that angle).
  const double cos_sharp = std::cos(kSharpCornerDeg * M_PI / 180.0);
  run_in_slices(vertex_.size(), threads_, [&](std::size_t lo, std::size_t hi) {
    for (auto v = static_cast<uint32_t>(lo); v < hi; ++v) {
      if (!vertex_[v].input_corner) continue;
      Neighbour ring_v[kMaxValence];
      bool boundary;
      const int n = ring(v, ring_v, kMaxValence, &boundary);
      for (int i = 0; i < n && !vertex_[v].sharp_corner; ++i) {
        const uint32_t e = ring_v[i].edge, t = half_[e].twin;
        if (t == kNone) continue;
        vertex_[v].sharp_corner =
            (attributes_ && seam_[e]) || (face_normal(e / 3) | face_normal(t / 3)) < cos_sharp;
      }
    }
  });
}

}  // namespace pm::collapse_loop
