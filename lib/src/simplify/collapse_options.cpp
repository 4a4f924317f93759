// Which collapse the collapse loop queues for a vertex v (collapse_loop.h, evaluate()): v's kind
// decides which of its edges it may collapse along (Schroeder, Zarge and Lorensen 1992,
// §3.1, with Schroeder 1997's corner rule), each is an option with a cost, and the options
// are ranked: special edges first (a corner's), then by cost (Schroeder's metric: by length,
// schroeder_costs.cpp), ties to the shortest edge, then to the smaller neighbour id.
// Garland and Heckbert 1997, §4: the cheapest pair, here among v's half-edge collapses.
//
// With attributes, the quadric metric's cost is v's planes at the target plus the
// attributes' error in the same units (Hoppe 1999, §4's attribute error over v's faces:
// CornerAttributes::star_fields() and collapse_cost(), about a quarter of the time of the
// loop without its measure on the 950K-face textured mesh, perf). That
// term is never negative, so an option's geometric cost alone is a lower bound of its whole
// cost (rounding is monotone): in order of geometric cost, the first option whose bound
// already ranks behind the best whole cost found ends the search, and the options after it
// are never priced. The same option and cost as pricing them all. Without the measure
// (EncodeOptions::fast), a vertex whose cheapest geometric cost, a bound of its whole cost,
// already ranks behind the heap's top is queued at that bound and priced only if it comes
// to the top (apply()): most are evaluated again before, when a collapse next to them
// changes their options (lazy, as the measure is: collapse_measure.cpp). Counted on the
// 950K-face textured mesh, one thread: v's faces' attribute functions made 1.31M times (0.54M
// of them at the top) where 3.05M before; the sequence 10% to 15% faster.
#include <algorithm>
#include <cmath>

#include "simplify/collapse_loop.h"

namespace pm::collapse_loop {

namespace {

// The options with a finite cost (not NaN or infinite), in their order; their count.
template <typename Option>
int finite_only(Option* options, int count) {
  return static_cast<int>(std::remove_if(options, options + count,
                                         [](const Option& o) { return !(o.cost < HUGE_VAL); }) -
                          options);
}

// The options in order of whole cost (ranks_before()), each priced (price(o) adds its
// attribute cost to o.cost and o.rank) only when it must be: in order of geometric cost (a
// lower bound of the whole), an option is priced while its bound does not rank behind the
// best priced one not yet given, which is then the next in whole order. The options with
// no finite cost are never given. The same order as pricing them all.
template <typename Option, typename Price, typename RanksBefore>
class InOrderOfWholeCost {
 public:
  InOrderOfWholeCost(Option* options, int count, Price price, RanksBefore ranks_before)
      : options_(options),
        count_(finite_only(options, count)),
        price_(price),
        ranks_before_(ranks_before) {
    std::sort(options_, options_ + count_, ranks_before_);
  }
  // The next option; null after the last.
  const Option* next() {
    int best = -1;
    for (int i = 0; i < n_waiting_; ++i)
      if (best < 0 || ranks_before_(*waiting_[i], *waiting_[best])) best = i;
    for (; priced_ < count_ && (best < 0 || !ranks_before_(*waiting_[best], options_[priced_]));
         ++priced_) {
      Option& o = options_[priced_];
      price_(o);
      if (!(o.cost < HUGE_VAL)) continue;
      waiting_[n_waiting_] = &o;
      if (best < 0 || ranks_before_(o, *waiting_[best])) best = n_waiting_;
      ++n_waiting_;
    }
    if (best < 0) return nullptr;
    const Option* o = waiting_[best];
    waiting_[best] = waiting_[--n_waiting_];
    return o;
  }

 private:
  Option* options_;
  int count_;
  Price price_;
  RanksBefore ranks_before_;
  Option* waiting_[kMaxValence];  // priced, finite, not yet given
  int n_waiting_ = 0, priced_ = 0;
};

}  // namespace

bool CollapseLoop::ranks_before(const Option& a, const Option& b) {
  if (a.special != b.special) return a.special;
  if (a.rank != b.rank) return a.rank < b.rank;
  // The last tie to the neighbour of smaller id, not the earlier place in v's ring: the ring
  // walk starts where a collapse left v's outgoing half-edge, and a vertex whose options
  // did not change must make the same choice when evaluated again (apply() relies on it for
  // vl and vr). Only ties of cost and length reach it (fandisk's flat parts).
  return a.length != b.length ? a.length < b.length : a.vertex < b.vertex;
}

bool CollapseLoop::find_best(Worker& worker, uint32_t v, bool check_legal) {
  if (!owns(worker, v) || dead_vertex_[v] || vertex_[v].pinned) return false;
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
    options[i] = {boundary || feature, 0.0, 0.0, 0.0, i, ring_v[i].vertex};
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
  const bool lazy = !check_legal && pricing_at_top();
  Star star;
  CornerAttributes::StarFields fields;  // v's, the same for every target
  if (attributes_) make_star(v, ring_v, n, star);
  // The plane term (collapse_loop.h, FanPlanes), never negative, joins the quadric's cost.
  Vec3 to_ring[kMaxValence];
  for (int i = 0; i < n; ++i) to_ring[i] = point(ring_v[i].vertex) - pv;
  FanPlanes planes;
  if (plane_term_) fan_planes(to_ring, n, boundary_v, planes);
  for (int i = 0; i < count; ++i) {
    const Neighbour& to = ring_v[options[i].index];
    const Vec3& d = to_ring[options[i].index];
    options[i].length = d.sqrnorm();
    if (schroeder_) continue;
    options[i].cost = geometric_cost(v, to.vertex);
    if (planes.count > 0) options[i].cost += kPlaneWeight * planes.worst(d);
    options[i].rank = options[i].cost;
  }
  // v's faces' attribute functions once the geometric costs are known: make_star() asked
  // for the faces' records, which have come meanwhile (the 950K-face textured mesh without
  // the measure, one thread, single alternating runs: about 4.3 -> 4.1 s).
  // Priced at the top (pricing_at_top()): when even v's cheapest geometric cost, a lower
  // bound of its cheapest whole cost, ranks behind the heap's top, v is queued at that
  // bound, unpriced, and apply() prices it if it comes to the top (most are evaluated again
  // before: a collapse next to them changes their options). Otherwise v is priced now,
  // while its faces' records are in the cache. Either way the order stays greedy.
  bool bound_only = false;
  if (lazy && !worker.heap.empty()) {
    double least = HUGE_VAL;
    for (int i = 0; i < count; ++i) least = std::min(least, options[i].cost);
    bound_only = static_cast<float>(least) > worker.key(worker.cheapest());
  }
  if (attributes_ && !bound_only) attributes_->star_fields(star.c, fields);
  // Schroeder's, with their attribute costs.
  if (schroeder_) schroeder_costs(v, kind, ring_v, n, options, count, star, fields);
  auto queue = [&](const Option& o, bool cheapest) {
    if (!owns(worker, ring_v[o.index].vertex)) return false;
    best_[v] = {ring_v[o.index].vertex, ring_v[o.index].edge, static_cast<float>(o.cost)};
    unmeasure(v);
    vertex_[v].simple = kind == VertexKind::kSimple;
    vertex_[v].cheapest = cheapest;
    vertex_[v].unpriced = bound_only;
    worker.queue(v, queued_key(o.cost));
    return true;
  };
  if (attributes_ && !schroeder_ && !bound_only) {
    auto price = [&](Option& o) {
      const Neighbour& to = ring_v[o.index];
      o.cost += attribute_cost(to.vertex, to.edge, star, fields);
      o.rank = o.cost;
    };
    InOrderOfWholeCost order(options, count, price, ranks_before);
    // Legality in order of whole cost until an option passes.
    for (int asked = 0;; ++asked) {
      const Option* o = order.next();
      if (!o) return false;
      if (!check_legal) return queue(*o, true);
      const Neighbour& to = ring_v[o->index];
      if (!owns(worker, to.vertex)) return false;
      if (legal(v, to.vertex, to.edge, ring_v, n, boundary_v, &star)) return queue(*o, asked == 0);
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

bool CollapseLoop::keeps_best_with_attributes(Worker& worker, uint32_t v, uint32_t u,
                                              double geometric) {
  if (best_[v].edge == kNone) return false;  // its face died (compact_faces()): evaluated again
  Star star;
  CornerAttributes::StarFields fields;
  Neighbour ring_v[kMaxValence];
  bool boundary_v;
  const int n = ring(v, ring_v, kMaxValence, &boundary_v);
  const Neighbour* to = std::find_if(ring_v, ring_v + std::max(n, 0),
                                     [&](const Neighbour& x) { return x.vertex == u; });
  if (to == ring_v + std::max(n, 0)) return false;
  make_star(v, ring_v, n, star);
  attributes_->star_fields(star.c, fields);
  // The geometric cost alone already above the key: so is the sum (attribute_cost() >= 0).
  if (!(static_cast<float>(geometric) > best_[v].key) &&
      !(static_cast<float>(geometric + attribute_cost(u, to->edge, star, fields)) > best_[v].key))
    return false;
  const Best& best = best_[v];
  worker.queue(v, queued_key(cost_of(v, best.target, best.edge, star, fields)));
  return true;
}

}  // namespace pm::collapse_loop
