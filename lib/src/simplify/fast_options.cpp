// Which collapse the fast loop queues for a vertex v (fast_loop.h, evaluate()): v's kind
// decides which of its edges it may collapse along (Schroeder, Zarge and Lorensen 1992,
// §3.1, with Schroeder 1997's corner rule), each is an option with a cost, and the options
// are ranked: special edges first (a corner's), then by cost (Schroeder's metric: by length,
// fast_schroeder.cpp), ties to the shortest edge. Garland and Heckbert 1997, §4: the
// cheapest pair, here among v's half-edge collapses.
//
// With attributes, the quadric metric's cost is v's planes at the target plus the
// attributes' error in the same units (Hoppe 1999, §4's attribute quadrics:
// CornerAttributes::collapse_cost, ~18% of the loop's instructions with attributes). That
// term is never negative, so an option's geometric cost alone is a lower bound of its whole
// cost (rounding is monotone): in order of geometric cost, the first option whose bound
// already ranks behind the best whole cost found ends the search, and the options after it
// are never priced. The same option and cost as pricing them all.
#include <algorithm>
#include <cmath>

#include "simplify/fast_loop.h"

namespace pm::fast_loop {

namespace {

// The options with a finite cost (not NaN or infinite), in their order; their count.
template <typename Option>
int finite_only(Option* options, int count) {
  return static_cast<int>(std::remove_if(options, options + count,
                                         [](const Option& o) { return !(o.cost < HUGE_VAL); }) -
                          options);
}

}  // namespace

bool FastSimplifier::ranks_before(const Option& a, const Option& b) {
  if (a.special != b.special) return a.special;
  if (a.rank != b.rank) return a.rank < b.rank;
  return a.length != b.length ? a.length < b.length : a.index < b.index;
}

const FastSimplifier::Option* FastSimplifier::cheapest_priced(
    const Neighbour* ring_v, Option* options, int count, Star& star,
    const CornerAttributes::StarWedges& wedges) const {
  count = finite_only(options, count);
  std::sort(options, options + count, ranks_before);
  const Option* best = nullptr;
  for (int i = 0; i < count; ++i) {
    Option& o = options[i];
    // Its geometric cost alone ranks behind the best: so does every later option's.
    if (best && ranks_before(*best, o)) break;
    const Neighbour& to = ring_v[o.index];
    o.cost += attribute_cost(to.vertex, to.edge, star, wedges);
    o.rank = o.cost;
    if (o.cost < HUGE_VAL && (!best || ranks_before(o, *best))) best = &o;
  }
  return best;
}

bool FastSimplifier::find_best(Worker& worker, uint32_t v, bool check_legal) {
  if (!owns(worker, v) || vertex_[v].dead || vertex_[v].pinned) return false;
  Neighbour ring_v[kMaxValence];
  bool boundary_v;
  const int n = ring(v, ring_v, kMaxValence, &boundary_v);
  if (n <= 0) return false;
  Option options[kMaxValence];
  int boundary_edges = 0, feature_edges = 0;
  for (int i = 0; i < n; ++i) {
    const uint32_t e = ring_v[i].edge;
    const bool boundary = half_[e].twin == kNone, feature = !boundary && is_feature(e);
    boundary_edges += boundary;
    feature_edges += feature;
    options[i] = {boundary || feature, 0.0, 0.0, 0.0, i};
  }
  const VertexKind kind = vertex_[v].input_corner ? VertexKind::kCorner
                                                  : kind_from_edges(boundary_edges, feature_edges);
  CollapseEdges edges = kCollapseEdges[static_cast<int>(kind)];
  if (kind == VertexKind::kCorner && options_.keep_corners) edges = CollapseEdges::kNone;
  if (edges == CollapseEdges::kNone) return false;
  int count = n;
  if (edges == CollapseEdges::kSpecialOnly)
    count = static_cast<int>(
        std::remove_if(options, options + n, [](const Option& o) { return !o.special; }) - options);
  const Vec3 pv = point(v);
  Star star;
  CornerAttributes::StarWedges wedges;  // v's, the same for every target
  if (attributes_) {
    make_star(v, ring_v, n, star);
    attributes_->star_wedges(star.c, wedges);
  }
  for (int i = 0; i < count; ++i) {
    const Neighbour& to = ring_v[options[i].index];
    options[i].length = (point(to.vertex) - pv).sqrnorm();
    if (!schroeder_) options[i].cost = options[i].rank = geometric_cost(v, to.vertex);
  }
  // Schroeder's, with their attribute costs.
  if (schroeder_) schroeder_costs(v, kind, ring_v, n, options, count, star, wedges);
  auto queue = [&](const Option& o, bool cheapest) {
    if (!owns(worker, ring_v[o.index].vertex)) return false;
    best_[v] = {ring_v[o.index].vertex, ring_v[o.index].edge, static_cast<float>(o.cost)};
    measured_[v] = kNotMeasured;
    vertex_[v].simple = kind == VertexKind::kSimple;
    vertex_[v].cheapest = cheapest;
    worker.queue(v, queued_key(o.cost));
    return true;
  };
  const bool attribute_costs_to_add = attributes_ && !schroeder_;
  if (attribute_costs_to_add && !check_legal) {
    const Option* best = cheapest_priced(ring_v, options, count, star, wedges);
    return best && queue(*best, true);
  }
  if (attribute_costs_to_add) {
    // Legality in order of whole cost, priced lazily as cheapest_priced(): in order of
    // geometric cost (a lower bound), an option is priced only while its bound does not
    // rank behind the best priced one not yet asked, which is then the next in whole order.
    // The same options asked in the same order as pricing them all.
    count = finite_only(options, count);
    std::sort(options, options + count, ranks_before);
    Option* waiting[kMaxValence];  // priced, finite, not yet asked
    int n_waiting = 0, priced = 0, asked = 0;
    for (;;) {
      int best = -1;
      for (int i = 0; i < n_waiting; ++i)
        if (best < 0 || ranks_before(*waiting[i], *waiting[best])) best = i;
      for (; priced < count && (best < 0 || !ranks_before(*waiting[best], options[priced]));
           ++priced) {
        Option& o = options[priced];
        const Neighbour& to = ring_v[o.index];
        o.cost += attribute_cost(to.vertex, to.edge, star, wedges);
        o.rank = o.cost;
        if (!(o.cost < HUGE_VAL)) continue;
        waiting[n_waiting] = &o;
        if (best < 0 || ranks_before(o, *waiting[best])) best = n_waiting;
        ++n_waiting;
      }
      if (best < 0) return false;
      const Option& o = *waiting[best];
      waiting[best] = waiting[--n_waiting];
      const Neighbour& to = ring_v[o.index];
      if (!owns(worker, to.vertex)) return false;
      if (legal(v, to.vertex, to.edge, ring_v, n, boundary_v, &star)) return queue(o, asked == 0);
      ++asked;
    }
  }
  count = finite_only(options, count);
  if (count == 0) return false;
  if (!check_legal) return queue(*std::min_element(options, options + count, ranks_before), true);
  // Legality in order of rank until an option passes.
  std::sort(options, options + count, ranks_before);
  for (int i = 0; i < count; ++i) {
    const Neighbour& to = ring_v[options[i].index];
    if (!owns(worker, to.vertex)) return false;
    if (legal(v, to.vertex, to.edge, ring_v, n, boundary_v, &star))
      return queue(options[i], i == 0);
  }
  return false;
}

}  // namespace pm::fast_loop
