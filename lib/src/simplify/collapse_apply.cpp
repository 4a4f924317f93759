// The collapse loop's step (collapse_loop.h): the collapse at the top of a heap, if it is still
// legal, with its record (Hoppe 1996, §3: the vertex split that undoes it), its measure
// (collapse_measure.cpp) and the bound it records (tracked_points.h, and kept_points.h with
// the measure), then
// the quadrics' sum (Garland and Heckbert 1997, §4) and the neighbours' candidates found again.
// Internal to simplify/.
#include "simplify/collapse_loop.h"

namespace pm::collapse_loop {

static_assert(TrackedPoints::kMaxOldFaces >= kMaxValence, "v's faces fit TrackedPoints::collapse()");

void CollapseLoop::apply(Worker& worker, uint32_t v) {
  // Queued at a bound (pricing_at_top()): priced now, with legality, and queued at its
  // whole cost; the caller takes the top again, v or another.
  if (vertex_[v].unpriced) {
    evaluate(worker, v, true);
    return;
  }
  const uint32_t edge = best_[v].edge;
  // The candidate's edge may have gone, or changed, since it was queued (kNone: its face
  // died before the faces were renamed, compact_faces()).
  if (edge == kNone || face_dead_[edge / 3] ||
      (half_[edge].vertex != v && half_[next_of(edge)].vertex != v)) {
    evaluate(worker, v, true);
    return;
  }
  const uint32_t u = half_[edge].vertex == v ? half_[next_of(edge)].vertex : half_[edge].vertex;
  Neighbour ring_v[kMaxValence];
  bool boundary_v;
  const int n = ring(v, ring_v, kMaxValence, &boundary_v);
  // The neighbours' records are read after the collapse (their re-evaluation): asked for
  // now, they arrive while legality is decided.
  for (int i = 0; i < n; ++i) {
    __builtin_prefetch(&vertex_[ring_v[i].vertex]);
    // And v's faces' kept and tracked points, which the collapse reads (a third of the
    // kept points' time went to waiting for their lists).
    const uint32_t e = ring_v[i].edge;
    if (half_[e].vertex != v) continue;
    if (measure_) kept_.prefetch(e / 3);
    if (!worker.tracking) tracked_.prefetch(e / 3);  // else the tracking thread reads them
  }
  // With attributes, v's star, aimed at u: legality, the seam drift and the record read it.
  Star star;
  if (attributes_ && n > 0) make_star(v, ring_v, n, star);
  if (n <= 0 || !legal(v, u, edge, ring_v, n, boundary_v, &star)) {
    evaluate(worker, v, true);
    return;
  }
  const Sides s = sides(v, edge);
  KeptPoints::FanFace fan[2 * kMaxValence];
  uint32_t old_faces[kMaxValence];
  int n_old = 0, moved = 0;
  const int n_fan = make_fan(v, u, s, ring_v, n, fan, old_faces, &n_old, &moved);
  if (!measured_at_top(worker, v, u, star, ring_v, n, fan, n_fan, moved, old_faces, n_old))
    return;
  const std::size_t removed_faces = (s.h != kNone) + (s.t != kNone);
  if (worker.removed_faces + removed_faces > worker.face_budget ||
      worker.removed_vertices >= worker.vertex_budget) {
    worker.full = true;
    return;
  }
  const uint32_t fl = s.h == kNone ? kNone : s.h / 3, fr = s.t == kNone ? kNone : s.t / 3;
  // The record, in local ids until the loop ends (to_given_ids()).
  const uint32_t vl = s.h == kNone ? kNone : half_[prev_of(s.h)].vertex;
  const uint32_t vr = s.t == kNone ? kNone : half_[prev_of(s.t)].vertex;
  Collapse c;
  c.v = v;
  c.u = u;
  c.fl = fl == kNone ? -1 : static_cast<int>(fl);
  c.fr = fr == kNone ? -1 : static_cast<int>(fr);
  c.vl = vl == kNone ? kNoVertex : vl;
  c.vr = vr == kNone ? kNoVertex : vr;
  // Room in the record lists for v's faces (at most n), and their places; merge() moves
  // them into the sequence's.
  worker.moved_faces.make_room(static_cast<uint32_t>(n));
  if (attributes_)
    worker.record.make_room(attributes_->has_uvs(), attributes_->has_normals(),
                            static_cast<uint32_t>(n));
  c.moved_begin = worker.moved_faces.end();
  c.new_faces_begin = worker.record.new_faces_place();
  // Without a seam at v or at u, none is at u after the collapse: v's corners take u's one
  // wedge per kind, and the faces that meet across u's edges agreed at their other ends
  // before (the removed faces' outer edges too: each agreed with the removed face there).
  // So seam_ at u holds as it is (update_seams_at() below). The textured 950K-face mesh's
  // loop without its measure, one thread, medians of 6 alternating runs: 2688 -> 2632 ms.
  const bool seamless_after = attributes_ && star.c.seamless && seamless_at(u);
  if (attributes_) {
    // In the order of the moved faces below (v's ring), before the corners change.
    if (seam_drift_) seam_drift_->collapse(star.c);
    attributes_->collapse(star.c, worker.record);
  }
  // The record's points. With the measure, which reads the kept points, each goes to its
  // nearest face (kept_points.h), and their largest distance is exact. Then every removed
  // point moves onto the new fan (tracked_points.h): one within `settled` of the face it was
  // on stays there, else it goes to its nearest. `settled` is a distance the sequence records
  // anyway at this collapse: the kept points' (this record holds it) with the measure;
  // without it, the largest record this worker knows of (Worker::record_floor; merge() makes
  // the records a running maximum). With the measure, the floor instead of the kept points'
  // distance: 1% less time on nefertiti, within the noise, and other records. Without the
  // measure no kept point is read: tracking alone is the record, and the cheaper. Nefertiti,
  // one thread, CPU time, medians of 5 alternating runs: 0.148 -> 0.137 s against the kept
  // points and a slack per face for those they dropped (dropped_points_bound.cpp, deleted
  // after 4db28b0: records 1.0 to 5.8 times the exact distance, tests/bench/bound.md then).
  const double farthest = measure_ ? kept_.collapse(v, old_faces, n_old, fan, n_fan) : 0;
  // What the record claims: the largest distance of a point it moved to its new face
  // (TrackedPoints::record()). On the tracking thread when there is one (tracking_thread.h),
  // which writes it before merge() reads it.
  if (worker.tracking) {
    worker.recorded.push_back(0);
    worker.tracking->push(v, old_faces, n_old, fan, n_fan, farthest, &worker.recorded.back());
  } else {
    // Not the key: its quadric, attribute and surface terms are no distance of an input
    // vertex, and only loosened the record (sqrt of the key: 1.3-9.4x the exact distance).
    worker.recorded.push_back(tracked_.track(v, old_faces, n_old, fan, n_fan, measure_, farthest,
                                             &worker.record_floor, worker.tracked_scratch));
  }
  for (int i = 0; i < n; ++i) {
    const uint32_t e = ring_v[i].edge;
    if (half_[e].vertex != v) continue;
    const uint32_t f = e / 3;
    if (f == fl || f == fr) continue;
    worker.moved_faces.push_back(f);
    for (int k = 0; k < 3; ++k)
      if (half_[3 * f + k].vertex == v) half_[3 * f + k].vertex = u;
  }
  c.moved_count = worker.moved_faces.end() - c.moved_begin;
  // Its own key, at least the kept points' distance (with the measure); merge() orders the
  // workers' collapses by it.
  // At most the largest float: no distance on a mesh encode() accepts (its diagonal is
  // at most kMaxEncodeDiagonal, below that) is larger, where the key's square overflows.
  c.bound =
      static_cast<float>(std::min<double>(std::max<double>(key_distance(worker.key(v)), farthest),
                                          std::numeric_limits<float>::max()));
  worker.collapses.push_back(c);

  // Who is on a boundary now stays so, and u becomes so if v was: their walks must start
  // at their boundary half-edge again (start_at_boundary), the others' anywhere.
  const bool boundary_vl = vl != kNone && half_[vertex_[vl].outgoing].twin == kNone;
  const bool boundary_vr = vr != kNone && half_[vertex_[vr].outgoing].twin == kNone;
  const bool boundary_u = boundary_v || half_[vertex_[u].outgoing].twin == kNone;
  // The faces at v-u go: their outer edges' twins become each other's.
  auto remove_face = [&](uint32_t h) {
    const uint32_t a = half_[next_of(h)].twin, b = half_[prev_of(h)].twin;
    if (a != kNone) half_[a].twin = b;
    if (b != kNone) half_[b].twin = a;
    face_dead_[h / 3] = 1;
    // The apex and u may have had their outgoing half-edge in this face.
    const uint32_t apex = half_[prev_of(h)].vertex;
    vertex_[apex].outgoing = a != kNone ? a : next_of(b);
  };
  if (s.h != kNone) remove_face(s.h);
  if (s.t != kNone) remove_face(s.t);
  // u: any outgoing half-edge of a face still alive.
  {
    uint32_t out = kNone;
    if (s.h != kNone) {
      const uint32_t b = half_[next_of(s.h)].twin;  // twin of the edge u-vl, now vl's side
      out = b != kNone ? next_of(b) : kNone;
    }
    if (out == kNone && s.h != kNone) {
      const uint32_t b = half_[prev_of(s.h)].twin;
      if (b != kNone) out = b;  // v -> vl, now u -> vl
    }
    if (out == kNone && s.t != kNone) {
      const uint32_t d = half_[prev_of(s.t)].twin;  // u -> vr
      if (d != kNone)
        out = d;
      else if (half_[next_of(s.t)].twin != kNone)
        out = next_of(half_[next_of(s.t)].twin);
    }
    vertex_[u].outgoing = out;
  }
  if (boundary_u) start_at_boundary(u);
  if (boundary_vl) start_at_boundary(vl);
  if (boundary_vr) start_at_boundary(vr);
  vertex_[v].outgoing = kNone;
  dead_vertex_[v] = 1;
  if (attributes_ && !seamless_after) update_seams_at(u);
  worker.removed_faces += removed_faces;
  ++worker.removed_vertices;
  // Garland and Heckbert 1997, §4: Q = Q1 + Q2.
  vertex_[u].quadric.add(vertex_[v].quadric, point(u) - point(v));
  worker.drop(v);

  // Re-evaluated, as in the former default loop: u, and v's other neighbours, whose one-rings
  // changed; u's other neighbours keep their best collapse unless it became illegal,
  // which apply() finds when it is popped.
  evaluate(worker, u);
  // Points moved onto u's faces: a neighbour's key that holds a measure of them is
  // measured again when it comes to the top (as the former default loop's keyed_by_measure_).
  if (keyed_by_measure()) {
    Neighbour ring_u[kMaxValence];
    bool boundary_u_now;
    const int n_u = ring(u, ring_u, kMaxValence, &boundary_u_now);
    // With the measure, those not next to v keep their fan's part (their faces, their ring
    // and their candidate did not change; collapse_measure.cpp measures the points' part
    // alone then), either metric, with attributes or without. It skips work, 4% of the
    // time on nefertiti and on the 950K-face textured mesh, and leaves the sequence as it
    // was (test_encoder.cpp's MeasuredLoop; collapse_measure.cpp says where it may not).
    // v's neighbours and u are measured from nothing (their fans changed: reset here, for
    // the fast loop's seam drift too, whether evaluate() below queues them again or not).
    const bool keep_fan_part = measure_ && reuse_fan_part_;
    for (int i = 0; i < n_u; ++i) {
      uint8_t& m = measured_[ring_u[i].vertex];
      if (!keep_fan_part)
        m = kNotMeasured;
      else if (m == kMeasuredWhole)
        m = kPointsMovedFanBelow;
      else if (m == kMeasuredWholeFanAbove)
        m = kPointsMovedFanAbove;
      else if (m != kPointsMovedFanBelow && m != kPointsMovedFanAbove)  // those still hold
        m = kNotMeasured;
    }
    for (int i = 0; i < n; ++i) unmeasure(ring_v[i].vertex);
    unmeasure(u);
  }
  for (int i = 0; i < n; ++i) {
    const uint32_t w = ring_v[i].vertex;
    if (w == u) continue;
    // A simple vertex of v's ring other than vl and vr stays simple (only the angle could
    // make a feature edge here: seams and material borders slide with the collapse, w's
    // edge to v becoming its edge to u on the same side of them) and only traded its
    // option w -> v for w -> u; the others cost what they did. Unless it was queued towards
    // v, or w -> u is no dearer, its queued candidate is still its best. With attributes
    // that is an approximation since the attribute error went memoryless (4f1fb0e): the two
    // faces w shares with v now have u's corner there, so the attribute functions of w's
    // options moved a little; its queued candidate keeps its place only when it was its
    // cheapest, and is queued again at its cost now (keeps_best_with_attributes()).
    // Evaluating every such w again instead, measured on 2026-11-30 (pm_bench_attr_quality
    // at 50/10/2%): with the measure, spot at 2% Hausdorff 5.06 -> 6.53% of the diagonal,
    // the textured sample at 2% RMS 0.91 -> 1.01 times meshopt_simplify's, the 950K-face
    // textured mesh 6% slower; without it (--fast) two points better and two worse (spot
    // at 10% H 1.06 -> 0.89 times meshopt's, the 950K-face mesh at 2% 0.60 -> 0.73).
    // vl and vr, geometry only, lost their option to v and kept the others at their cost,
    // and stay simple (their edges to v and u become one, a boundary edge if either was).
    // When their queued candidate was their cheapest, legal or not, and not towards v,
    // evaluate() would queue it again (ranks_before()'s last tie is the neighbour's id, not
    // its place in the ring): queued again at its key, behind the ties queued before, the
    // same sequence with fewer evaluations (nefertiti after two Loop steps: 4.5 per
    // collapse, 5.9 before; 4% less time without the measure). With attributes their
    // options' corners changed (v's became u's in the faces they share).
    // Without the measure, priced at the top (pricing_at_top()): a w queued at its
    // cheapest geometric cost, unpriced, keeps it as geometry only (keeps_best()); a priced
    // one is evaluated again, at most as far as that bound when it ranks behind the top
    // (collapse_options.cpp), which is cheaper than keeps_best_with_attributes(). The levels
    // moved little: attr_quality.md's 950K-face textured mesh at 2%, Hausdorff 0.60 ->
    // 0.67 times meshopt_simplify's, RMS 0.83 -> 0.82; pm_bench_uv on it, the texture's
    // RMS at 2% 0.00035 -> 0.000124 (meshopt's 0.00109); tests/bench/README.md has the
    // small meshes.
    const bool apex = w == vl || w == vr;
    const bool bound_queued = pricing_at_top() && vertex_[w].unpriced;
    const bool may_keep = pricing_at_top() ? bound_queued && (!apex || keep_apex_candidates_)
                          : apex ? keep_apex_candidates_ && !attributes_ && vertex_[w].cheapest
                                 : !attributes_ || vertex_[w].cheapest;
    // Without the measure, w's plane term (collapse_loop.h, FanPlanes) moved with its faces
    // at v, and its queued key keeps the one it had: evaluating every such w again took the
    // shared meshes' levels from 0.746 to 0.721 times the Hausdorff distance of the quadric
    // alone (RMS 0.966 to 0.952, geometric means), for 54% more evaluations (nefertiti:
    // 385K against 250K, 232K without the plane term).
    if (!schroeder_ && !angle_features_ && vertex_[w].simple && may_keep && worker.queued(w) &&
        best_[w].target != v) {
      if (keeps_best(worker, w, u)) {  // its measure was reset above
        if (apex) worker.queue(w, queued_key(best_[w].key));
        continue;
      }
    }
    evaluate(worker, w);
  }
  // With one heap; rounds report after each merge, on the caller's thread.
  if (options_.progress && !in_rounds_ && worker.collapses.size() % 4096 == 0)
    report_progress(out_.collapses.size() + worker.collapses.size());
}

}  // namespace pm::collapse_loop
