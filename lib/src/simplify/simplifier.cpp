// The collapse loop: see simplifier.h. Garland and Heckbert 1997, "Surface
// simplification using quadric error metrics" (§5 quadrics, §6.1 area weights, §6.2
// boundary constraint planes), as half-edge collapses recorded for Hoppe 1996's vertex
// splits, on Campagna, Kobbelt and Seidel 1998's directed edges: half-edge h = 3f + k of
// triangle f leaves the triangle's k-th corner, next and previous are implicit, and one
// array holds each half-edge's twin, so a collapse rewrites a few integers in place.
#include "simplify/simplifier.h"

#include <algorithm>
#include <cstddef>
#include <functional>
#include <queue>
#include <utility>
#include <vector>

#include "core/memory_pages.h"
#include "core/in_turn.h"
#include "simplify/collapse_loop.h"
#include "simplify/face_renumbering.h"

namespace pm {
namespace collapse_loop {

void CollapseLoop::run() {
  const std::size_t n_vertices = vertex_.size();
  if (!schroeder_) initialize_quadrics();  // Schroeder's metric has none: all zero
  // Without feature edges (no feature angle, no seams) a vertex's ring holds no special
  // edge but its two boundary edges, if on a boundary: no vertex is a corner, and input_corner
  // stays 0 without a walk around every vertex (16 ms of 2 s on nefertiti after two Loop
  // steps).
  if (features_) {
    run_in_slices(n_vertices, threads_, [&](std::size_t lo, std::size_t hi) {
      for (auto v = static_cast<uint32_t>(lo); v < hi; ++v)
        vertex_[v].input_corner = kind_of(v) == VertexKind::kCorner;
    });
  }
  if (schroeder_) mark_sharp_corners();
  detail::assign_preferring_huge_pages(best_, n_vertices, Best{kNone, kNone, 0});
  detail::assign_preferring_huge_pages(dead_vertex_, n_vertices, 0);
  if (keyed_by_measure()) detail::assign_preferring_huge_pages(measured_, n_vertices, kNotMeasured);
  // The measure's points, and the input's faces before any collapse (kept_.input_distance()).
  if (measure_) {
    kept_.reset(half_.size() / 3, xyz_.data());
    detail::assign_preferring_huge_pages(measured_worst_, n_vertices, 0.0);
    std::vector<uint32_t> corners(half_.size());
    for (std::size_t h = 0; h < half_.size(); ++h) corners[h] = half_[h].vertex;
    input_.build(std::move(corners), n_vertices);
  }
  tracked_.reset(half_.size() / 3, n_vertices, xyz_.data());
  faces_alive_ = half_.size() / 3;
  vertices_alive_ = n_vertices;
  out_.collapses.reserve(n_vertices);
  if (partitioned_) run_rounds();
  // One heap for the rest (or all) of the sequence. As the former default loop: a final sweep
  // re-evaluates every vertex, so the loop ends only when no legal collapse remains.
  std::vector<Worker> one(1);
  Worker& w = one[0];
  w.hi = static_cast<uint32_t>(n_vertices);
  w.heap = IndexedHeap(n_vertices);
  w.record_floor = bound_;
  // Its points tracked on a thread of their own, beside it: most of the moving is in these
  // last collapses (tracking_thread.h). pmenc without the measure on two
  // threads, alternating runs against the tracking in turn: nefertiti after two Loop steps
  // 2.71 -> 2.28 s (the kept lists and slack before: 2.45 and 2.22 s in the same runs), the
  // bunny after three 7.81 -> 7.54 s (6.60 and 6.86).
  TrackingThread tracking;
  if (threads_ > 1 && tracking.start(tracked_, measure_, bound_)) w.tracking = &tracking;
  set_budgets(w, 1);
  // The worker's collapses go into the sequence every kMergeEvery: merged at the end, they
  // would be held twice there, beside their copy in out_, where memory peaks (its record
  // lists are handed on whole, record_list.h, but the collapses are copied in the merged
  // order). With one worker, merge() keeps the order, and
  // set_budgets() after it leaves the same room (the budgets count from what is alive).
  constexpr std::size_t kMergeEvery = 1 << 16;
  for (bool first = true;; first = false) {
    w.heap.clear();
    // After the rounds, every vertex as they left it (requeue()): evaluated afresh, each
    // would be measured again (the whole encode took 5% longer on nefertiti after a Loop
    // step, 400K faces, and 3% on the bunny after one). The later sweeps evaluate every
    // vertex.
    for (uint32_t v = 0; v < n_vertices; ++v) {
      if (first && partitioned_)
        requeue(w, v);
      else
        evaluate(w, v);
    }
    bool more = false;
    // The least key first, equal keys oldest first (Worker::queue()).
    while (!w.heap.empty() && !w.full) {
      fetch(w.next_cheapest());
      apply(w, w.cheapest());
      if (w.collapses.size() >= kMergeEvery && !w.full) {
        more = true;
        merge(one);
        set_budgets(w, 1);
      }
    }
    more |= !w.collapses.empty();
    merge(one);
    set_budgets(w, 1);
    if (w.full || !more) break;
  }
  tracking.stop();
  one.clear();
  std::vector<Best>().swap(best_);
  std::vector<uint8_t>().swap(measured_);
  std::vector<double>().swap(measured_worst_);
  kept_.reset(0, nullptr);
  tracked_.reset(0, 0, nullptr);
  input_.clear();
  seam_drift_.reset();  // it reads xyz_
  std::vector<uint8_t>().swap(seam_);
  if (attributes_) attributes_->end_collapses();  // before xyz_ goes
  out_.points.resize(3 * vertex_.size());
  for (std::size_t i = 0; i < vertex_of_.size(); ++i)
    for (int c = 0; c < 3; ++c) out_.points[3 * vertex_of_[i] + c] = xyz_[3 * i + c];
  std::vector<float>().swap(xyz_);
  std::vector<VertexRecord>().swap(vertex_);
  to_given_ids();
  write_base();
  if (attributes_) {
    attributes_->finish(face_of_, vertex_of_, face_dead_);
    out_.attributes = std::move(attributes_);
  }
}

void CollapseLoop::attach_attributes(const Mesh& input, const uint32_t* input_face,
                                     const uint32_t* input_vertex,
                                     const std::function<void()>& input_read) {
  if (options_.drop_attributes ||
      !(input.has_uvs() || input.has_normals() || input.has_materials())) {
    if (input_read) input_read();
    return;
  }
  // In local ids: each local face's and vertex's input one. The faces' vertices are read
  // where the loop keeps them, its half-edges.
  static_assert(sizeof(HalfEdge) == 2 * sizeof(uint32_t) && offsetof(HalfEdge, vertex) == 0,
                "FaceVertices reads a half-edge's vertex every two words");
  const std::size_t n_faces = half_.size() / 3, n_vertices = vertex_of_.size();
  std::vector<uint32_t> faces(n_faces), vertices(n_vertices);
  for (std::size_t f = 0; f < n_faces; ++f)
    faces[f] = input_face ? input_face[face_of_[f]] : face_of_[f];
  for (std::size_t x = 0; x < n_vertices; ++x)
    vertices[x] = input_vertex ? input_vertex[vertex_of_[x]] : vertex_of_[x];
  // Once the faces' records hold their ids, these copies and the input's arrays go.
  const auto read = [&] {
    std::vector<uint32_t>().swap(faces);
    std::vector<uint32_t>().swap(vertices);
    if (input_read) input_read();
  };
  const FaceVertices corners{half_.empty() ? nullptr : &half_[0].vertex, 2};
  attributes_ =
      std::make_unique<CornerAttributes>(input, corners, n_faces, xyz_.data(), n_vertices,
                                         faces.data(), vertices.data(), threads_, read);
  if (!attributes_->any()) {
    attributes_.reset();
    return;
  }
  if (!schroeder_) attributes_->weigh_costs(kUvCostWeight, 1.0);  // Schroeder's: the default's
  if (attributes_->has_uvs())
    seam_drift_ = std::make_unique<SeamDrift>(xyz_.data(), n_vertices, *attributes_);
  features_ = true;  // seams and material borders are feature edges
  plane_term_ = false;  // it moved the levels away from the input there (FanPlanes)
  detail::assign_preferring_huge_pages(seam_, half_.size(), 0);
  // Each interior edge by its lower half-edge: no byte is written twice.
  run_in_slices(half_.size(), threads_, [&](std::size_t lo, std::size_t hi) {
    for (auto h = static_cast<uint32_t>(lo); h < hi; ++h)
      if (half_[h].twin != kNone && h < half_[h].twin)
        seam_[h] = seam_[half_[h].twin] = seam_now(h);
  });
}

void CollapseLoop::run_rounds() {
  constexpr std::size_t kRegions = 8;      // enough for two threads to end a round together
  constexpr std::size_t kMostWaiting = 8;  // the rounds end when 1/8 of the vertices wait
  const std::size_t n = vertex_.size();
  // Without the measure, more regions on large meshes: at most kRegionVertices each, so
  // that the state a region's collapses read and write (its vertex records, half-edges,
  // positions and tracked points: about 10 MB) stays in the cache while the region
  // runs. The loop without the measure waits on memory (find_best()'s ring walks, each
  // load a miss once a region is larger than the cache). One thread, medians of 5
  // alternating runs: the bunny after three Loop steps (2.2M vertices, 45 regions instead
  // of 8) 13.8 -> 11.3 s, armadillo after two (415K: 9) 2.22 -> 2.09, nefertiti after two
  // (800K: 16) 4.13 -> 3.86 (7 runs); the textured 950K-face mesh (476K: 10) the same.
  // Their levels at 10%, 2% and 1% as close to the input (nefertiti and the bunny:
  // Hausdorff 1.022 times, RMS 1.007, geometric means; the bunny at 1% 1.23 times, its other
  // targets from 5% to 0.5% 0.96 to 1.00). With the measure, whose time is
  // the distances' arithmetic, not memory, eight (the textured mesh on two threads, 9.27
  // s with 8, 9.64 with 10), which keeps its sequence on meshes of fewer vertices than that.
  // 12,500 since 2026-12-02 (the state about 2.5 MB): one thread, alternating runs, the
  // sequence on nefertiti after two Loop steps 3.51 -> 3.14 s (medians of 7; 25,000: 3.29,
  // 6,250: 3.33), the bunny after three 10.2 -> 8.5 s (medians of 3; 25,000: 9.2), the
  // textured mesh 3.72 -> 3.67 s. Their levels a little farther from the input: RMS at 50%,
  // 10% and 2% 1.056, 1.035, 1.004 times on nefertiti and 1.059, 1.054, 1.000 times on the
  // bunny (Hausdorff 1.27, 1.02, 0.99 and 1.05, 1.00, 1.00), still 0.09 to 0.71 times
  // meshopt_simplify's RMS (tests/bench/README.md has 25,000's, halfway on both sides).
  constexpr std::size_t kRegionVertices = 12500;
  const std::size_t first_regions =
      measure_ ? kRegions : std::max(kRegions, (n + kRegionVertices - 1) / kRegionVertices);
  // At the end, one region per thread (below).
  constexpr std::size_t kFewestRegions = 2;
  const std::size_t tail = std::max<std::size_t>(n / 32, 1024);
  const std::size_t min_vertices = std::max<std::size_t>(options_.min_vertices, 1);
  std::size_t n_regions = first_regions;
  detail::assign_preferring_huge_pages(band_, n, 0);
  std::vector<Worker> regions;
  std::vector<float> keys;
  for (int round = 0;
       vertices_alive_ > min_vertices + tail && faces_alive_ > options_.min_faces + 2 * tail;
       ++round) {
    const bool second = round % 2 == 1;
    const uint32_t* rank = second ? rank_b_.data() : nullptr;
    const uint32_t* at = second ? order_b_.data() : nullptr;
    // The band: the vertices of every face across regions (an edge between two regions
    // is in such a face, and all three of its vertices then have a neighbour elsewhere).
    std::size_t size = 0, waiting = 0;
    auto mark_band = [&] {
      size = (n + n_regions - 1) / n_regions;
      std::fill(band_.begin(), band_.end(), 0);
      const auto region_of = [&](uint32_t v) { return (rank ? rank[v] : v) / size; };
      for (std::size_t f = 0; f < face_dead_.size(); ++f) {
        if (face_dead_[f]) continue;
        const uint32_t a = half_[3 * f].vertex, b = half_[3 * f + 1].vertex,
                       c = half_[3 * f + 2].vertex;
        const std::size_t region = region_of(a);
        if (region_of(b) != region || region_of(c) != region) band_[a] = band_[b] = band_[c] = 1;
      }
      waiting = 0;
      for (std::size_t v = 0; v < n; ++v) waiting += band_[v] && !dead_vertex_[v];
    };
    // When the cuts hold a good part of what is left, the waiting vertices would hoard
    // the coarse levels' vertices (the rest simplified past them): fewer, larger regions,
    // whose cuts hold fewer of them, down to kFewestRegions; then one heap from here. With
    // eight regions throughout, the rounds ended near a tenth of the vertices and the one
    // heap, on one thread, took a third of the wall time on two (the 950K-face textured
    // mesh: 3.3 s of 9.9); with four at the end, 11% and 12% less wall time on nefertiti
    // after a Loop step and armadillo after two (400K and 830K faces), the levels as far
    // from the input (on those, the bunny after a step and the textured mesh, at 10% to 1%
    // of the faces: Hausdorff 0.996 times what it was and RMS 1.002, geometric means); with
    // two at the end, one region per thread, the one heap holds less again (nefertiti: 0.39 s
    // of its 0.81 s loop, then 0.08 of 0.68): two threads, medians of 5, nefertiti 0.93 ->
    // 0.86 s, armadillo 0.49 -> 0.43, the bunny 0.69 -> 0.59, the textured mesh 9.63 -> 9.27
    // (3 runs), armadillo after two steps the same; the levels as close to the input (those
    // meshes and the 8 shared ones at 50/10/2%: Hausdorff 1.003 and 1.002, RMS 1.000 and
    // 1.001 times). Without the measure too: the one heap after eight regions took the
    // last 0.45 s of the textured mesh's encode on one thread; with two, pmenc --fast on it
    // 3.36 -> 3.19 s (medians of 5, alternating), one thread as fast (nefertiti after two
    // Loop steps 2.24 -> 2.20 s), the levels as close to the input (the two Loop meshes of
    // fast_loop_meshes.md at 50, 10 and 2% the same; the 8 shared meshes: Hausdorff against
    // meshopt's 0.917 against 0.920, RMS 0.845 against 0.843, geometric means).
    const std::size_t most_waiting = vertices_alive_ / kMostWaiting;
    mark_band();
    while (waiting > most_waiting && n_regions > kFewestRegions) {
      n_regions = std::max(kFewestRegions, n_regions / 2);
      mark_band();
    }
    if (waiting > most_waiting) break;
    // Made in place: a worker cannot move without a copy (std::deque's move may throw, so a
    // growing vector would copy them, and record lists are not copied).
    regions = std::vector<Worker>((n + size - 1) / size);
    for (std::size_t i = 0; i < regions.size(); ++i) {
      regions[i].lo = static_cast<uint32_t>(i * size);
      regions[i].hi = static_cast<uint32_t>(std::min(n, (i + 1) * size));
      regions[i].rank = rank;
      regions[i].at = at;
      regions[i].record_floor = bound_;
    }
    in_rounds_ = true;
    in_turn(regions, [&](Worker& w) {
      w.heap = IndexedHeap(w.hi - w.lo);
      // Each vertex as the last round left it (requeue()): queued at its cost alone, every
      // vertex would be measured again in every round (nefertiti after a Loop step, 400K
      // faces: 14.4 measures of the kept points and 5.0 of the whole per collapse in the
      // rounds, against 3.5 and 1.7 in one heap; 4.0 and 1.9 so, and half the time).
      for (uint32_t r = w.lo; r < w.hi; ++r) requeue(w, w.vertex_at(r));
    });
    keys.clear();
    for (const Worker& w : regions) w.heap.append_keys(keys);
    if (keys.empty()) break;
    // A round ends at the median of the queued keys with the measure. Without it, at the
    // 7/8 quantile: fewer rounds, so fewer requeues and bands, whose share grows as the
    // collapses cost less. Nefertiti after two Loop steps, one thread, medians of alternating
    // runs: 2418 -> 2083 ms (3/4: 2199); the levels a little farther from the input (the
    // two Loop meshes at 50, 10 and 2%: Hausdorff 1.034 times, RMS 1.018, geometric means,
    // the bunny after three steps at 2% 1.17 times; the 8 shared meshes 1.018 and 1.011),
    // still a third of meshopt's on the Loop meshes (tests/bench/fast_loop_meshes.md).
    // With attributes, the first round ends at the median too. It came for the wedges'
    // quadrics, compacted between the rounds, which have gone since (corner_attributes.h);
    // it stays because it was no slower (pmenc --fast on the 950K-face textured mesh, one
    // thread, 3 alternating runs, 3.92 -> 3.81 s) and the levels are measured with it
    // (attr_quality.md, uv.md).
    const bool to_median = measure_ || (round == 0 && attributes_);
    const std::size_t q_at = to_median ? keys.size() / 2 : keys.size() * 7 / 8;
    std::nth_element(keys.begin(), keys.begin() + q_at, keys.end());
    const float last_key = keys[q_at];
    // Each region may take its share of what is left above the limits and the tail.
    in_turn(regions, [&](Worker& w) {
      set_budgets(w, regions.size());
      w.vertex_budget = std::min(w.vertex_budget, (vertices_alive_ - tail) / regions.size());
      while (!w.heap.empty() && !w.full && w.key(w.cheapest()) <= last_key) {
        fetch(w.next_cheapest());
        apply(w, w.cheapest());
      }
      w.heap = IndexedHeap(0);
    });
    std::size_t made = 0;
    for (const Worker& w : regions) made += w.collapses.size();
    merge(regions);
    if (options_.progress) report_progress(out_.collapses.size());
    if (made == 0) break;
    // Once a quarter of the faces are dead, the arrays shrink to the live ones: the record
    // grows round by round beside them.
    if (compact_faces_ && 4 * faces_alive_ <= 3 * face_dead_.size()) compact_faces();
  }
  in_rounds_ = false;
  std::vector<uint8_t>().swap(band_);
  std::vector<uint32_t>().swap(order_b_);
  std::vector<uint32_t>().swap(rank_b_);
}

void CollapseLoop::merge(std::vector<Worker>& workers) {
  // The workers' records go into the sequence's lists as they are, block by block (in
  // worker order, which no place depends on): each collapse's places move by its worker's
  // shift. The lists a collapse fills together share their blocks' layout, so one shift
  // serves the moved faces and their ids, another the new faces' ids of both kinds.
  // Their records first, when a thread tracks them.
  for (Worker& w : workers)
    if (w.tracking) w.record_floor = w.tracking->drain();
  std::vector<uint32_t> moved_shift(workers.size(), 0), new_face_shift(workers.size(), 0);
  for (std::size_t i = 0; i < workers.size(); ++i) {
    moved_shift[i] = out_.moved_faces.take(workers[i].moved_faces);
    new_face_shift[i] = out_.attribute_record.take(workers[i].record);
  }
  // Each worker's next collapse, the least bound first, ties to the earlier worker: a heap
  // of (bound, worker) rather than a look at every worker per collapse (16 on nefertiti
  // after two Loop steps).
  using Head = std::pair<float, std::size_t>;
  std::priority_queue<Head, std::vector<Head>, std::greater<Head>> heads;
  for (std::size_t i = 0; i < workers.size(); ++i)
    if (!workers[i].collapses.empty()) heads.push({workers[i].collapses.front().bound, i});
  while (!heads.empty()) {
    const std::size_t i = heads.top().second;
    heads.pop();
    Worker& from = workers[i];
    const float recorded = from.recorded.front();
    Collapse c = from.collapses.front();
    from.recorded.pop_front();
    from.collapses.pop_front();
    if (!from.collapses.empty()) heads.push({from.collapses.front().bound, i});
    c.moved_begin += moved_shift[i];
    c.new_faces_begin += new_face_shift[i];
    // The record's error: the largest so far of the collapses' own (the largest distance of
    // a point each moved to its new face: tracked_points.h), so non-increasing from the base
    // to full detail, and at least the distance of every input vertex to the level's
    // surface. The order above stays the keys' (and kept points' distance) alone.
    bound_ = std::max(bound_, recorded);
    c.bound = bound_;
    out_.collapses.push_back(c);
  }
  for (Worker& w : workers) {
    faces_alive_ -= w.removed_faces;
    vertices_alive_ -= w.removed_vertices;
    w.removed_faces = w.removed_vertices = 0;  // its collapses and records were taken above
  }
}

void CollapseLoop::initialize_quadrics() {
  constexpr double kConstraintWeight = 4.0;
  const std::size_t n_faces = half_.size() / 3;
  for (uint32_t f = 0; f < n_faces; ++f) {
    const Vec3 a = point(half_[3 * f].vertex), b = point(half_[3 * f + 1].vertex),
               c = point(half_[3 * f + 2].vertex);
    const Vec3 n = area_vector(a, b, c);
    const double twice_area = n.norm();
    if (twice_area == 0) continue;
    for (int k = 0; k < 3; ++k) {
      const uint32_t x = half_[3 * f + k].vertex;
      vertex_[x].quadric.add_plane(n / twice_area, a, 0.5 * twice_area, point(x));
    }
  }
  for (uint32_t h = 0; h < half_.size(); ++h) {
    if (!is_special(h)) continue;
    const Vec3 a = point(half_[h].vertex), b = point(half_[next_of(h)].vertex);
    Vec3 n = (b - a) % face_normal(h / 3);
    const double length = n.norm();
    if (length == 0) continue;
    n /= length;
    const double w = kConstraintWeight * (b - a).sqrnorm();
    for (const uint32_t x : {half_[h].vertex, half_[next_of(h)].vertex})
      vertex_[x].quadric.add_plane(n, a, w, point(x));
  }
}

namespace {
constexpr std::size_t kFetchAhead = 16;  // records: their lookups' misses overlap
}  // namespace

void CollapseLoop::to_given_ids() {
  faces_to_given_ids();
  auto& collapses = out_.collapses;
  for (std::size_t k = 0; k < collapses.size(); ++k) {
    if (k + kFetchAhead < collapses.size()) {
      const Collapse& ahead = collapses[k + kFetchAhead];
      for (const uint32_t x : {ahead.v, ahead.u, ahead.vl, ahead.vr}) {
        if (x != kNoVertex) __builtin_prefetch(vertex_of_.data() + x);
      }
    }
    Collapse& c = collapses[k];
    c.v = vertex_of_[c.v];
    c.u = vertex_of_[c.u];
    if (c.vl != kNoVertex) c.vl = vertex_of_[c.vl];
    if (c.vr != kNoVertex) c.vr = vertex_of_[c.vr];
  }
}

void CollapseLoop::faces_to_given_ids() {
  auto& collapses = out_.collapses;
  for (std::size_t k = given_faces_collapses_; k < collapses.size(); ++k) {
    if (k + kFetchAhead < collapses.size()) {
      const Collapse& ahead = collapses[k + kFetchAhead];
      for (const int f : {ahead.fl, ahead.fr}) {
        if (f >= 0) __builtin_prefetch(face_of_.data() + f);
      }
    }
    Collapse& c = collapses[k];
    if (c.fl >= 0) c.fl = static_cast<int>(face_of_[c.fl]);
    if (c.fr >= 0) c.fr = static_cast<int>(face_of_[c.fr]);
  }
  given_faces_collapses_ = collapses.size();
  out_.moved_faces.for_each_block(
      [&](uint32_t* moved, uint32_t count) {
        for (uint32_t k = 0; k < count; ++k) {
          if (k + kFetchAhead < count) __builtin_prefetch(face_of_.data() + moved[k + kFetchAhead]);
          moved[k] = face_of_[moved[k]];
        }
      },
      given_faces_blocks_);
  given_faces_blocks_ = out_.moved_faces.block_count();
}

void CollapseLoop::compact_faces() {
  static_assert(FaceRenumbering::kGone == kNone, "a dead face's half-edge renamed is kNone");
  // Every record so far names faces by their ids now: in the given ids before they change.
  faces_to_given_ids();
  ++out_.face_renamings;
  const FaceRenumbering faces(face_dead_);
  if (attributes_) attributes_->compact(faces, face_of_.data());
  for (std::size_t f = 0; f < faces.new_id.size(); ++f) {
    const uint32_t to = faces.new_id[f];
    if (to == FaceRenumbering::kGone) continue;
    for (uint32_t k = 0; k < 3; ++k) {
      HalfEdge e = half_[3 * f + k];
      if (e.twin != kNone) e.twin = faces.half_edge(e.twin);  // a live face's twin is live
      half_[3 * std::size_t{to} + k] = e;
    }
  }
  detail::shrink_in_place(half_, 3 * faces.live);
  faces.compact(seam_, 3);
  faces.compact(face_of_, 1);
  faces.compact(face_dead_, 1);  // all alive now
  tracked_.compact(faces);
  kept_.compact(faces);
  // A vertex's outgoing half-edge is a live face's while the vertex lives; a candidate's
  // edge may have died since it was queued (apply() then finds v's best again): kNone.
  for (std::size_t v = 0; v < vertex_.size(); ++v) {
    uint32_t& out = vertex_[v].outgoing;
    if (out != kNone) out = faces.half_edge(out);
    uint32_t& edge = best_[v].edge;
    if (edge != kNone) edge = faces.half_edge(edge);
  }
}

void CollapseLoop::write_base() {
  BaseMesh& base = out_.base;
  for (uint32_t v = 0; v < vertex_of_.size(); ++v)
    if (!dead_vertex_[v]) base.vertices.push_back(vertex_of_[v]);
  std::sort(base.vertices.begin(), base.vertices.end());
  std::vector<uint32_t> alive;
  for (uint32_t f = 0; f < face_dead_.size(); ++f)
    if (!face_dead_[f]) alive.push_back(f);
  std::sort(alive.begin(), alive.end(),
            [&](uint32_t a, uint32_t b) { return face_of_[a] < face_of_[b]; });
  for (uint32_t f : alive) {
    base.faces.push_back(face_of_[f]);
    for (int k = 0; k < 3; ++k) base.corners.push_back(vertex_of_[half_[3 * f + k].vertex]);
  }
}

}  // namespace collapse_loop

using collapse_loop::CollapseLoop;

Status simplify(const Mesh& input, ManifoldMesh& repaired, const EncodeOptions& options,
                Simplification& out, const LoopSwitches& switches,
                const std::function<void()>& loop_built) {
  // The triangles and points of the repaired mesh, then its memory goes back.
  HalfEdgeMesh& mesh = repaired.mesh;
  const std::size_t n_faces = mesh.n_faces(), n_vertices = mesh.n_vertices();
  std::vector<uint32_t> triangles;
  triangles.reserve(3 * n_faces);
  for (auto f : mesh.faces()) {
    auto h = mesh.halfedge_handle(f);
    for (int k = 0; k < 3; ++k, h = mesh.next_halfedge_handle(h))
      triangles.push_back(static_cast<uint32_t>(mesh.from_vertex_handle(h).idx()));
  }
  std::vector<float> points(3 * n_vertices);
  for (std::size_t v = 0; v < n_vertices; ++v)
    for (int c = 0; c < 3; ++c) points[3 * v + c] = mesh.point(mesh.vertex_handle(int(v)))[c];
  mesh.clean();
  CollapseLoop simplifier(&repaired, options, switches, out);
  if (!simplifier.build(triangles.data(), n_faces, points.data(), n_vertices, &repaired.pinned,
                        /*faceless_allowed=*/true))
    return Status(ErrorCode::kInternal, "the repaired mesh is not a manifold");
  // The loop holds its own copies of these.
  std::vector<uint32_t>().swap(triangles);
  std::vector<float>().swap(points);
  simplifier.attach_attributes(input, repaired.input_face.data(), repaired.input_vertex.data(),
                               loop_built);
  simplifier.run();
  return Status::ok();
}

bool simplify_direct(const Mesh& input, const EncodeOptions& options, Simplification& out,
                     const LoopSwitches& switches, const std::function<void()>& loop_built) {
  CollapseLoop simplifier(nullptr, options, switches, out);
  if (!simplifier.build(input.triangles.data(), input.face_count(), input.positions.data(),
                        input.vertex_count(), nullptr, /*faceless_allowed=*/false))
    return false;
  simplifier.attach_attributes(input, nullptr, nullptr, loop_built);
  simplifier.run();
  return true;
}

}  // namespace pm
