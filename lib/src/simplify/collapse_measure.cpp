// The collapse loop's measured distance of the candidate at the top of the heap (collapse_loop.h's
// apply()): the kept points' distance to the new fan (kept_points.h, after Klein, Liebich and
// Straßer 1996), then the moved faces' distance to the old fan and to the input. Internal to
// simplify/.
#include "simplify/collapse_loop.h"

#include <algorithm>

namespace pm::collapse_loop {

bool CollapseLoop::measured_at_top(Worker& worker, uint32_t v, uint32_t u, const Star& star,
                                   const Neighbour* ring_v, int n, const KeptPoints::FanFace* fan,
                                   int n_fan, int moved, const uint32_t* old_faces, int n_old) {
  // The quadric orders the candidates; the kept points' distance is measured only for
  // the one at the top, which goes back with its new key when that puts it behind the
  // next (lazy evaluation, as the former default loop's remeasure(); Klein, Liebich and Straßer
  // 1996 measure the distance of the removed points, kept_points.h). In two steps, each
  // a lower bound of the whole: the kept points' distance to the new fan (and a texture
  // seam's drift), then the new fan's distance to the old one, only for a candidate still
  // at the top after the first (most go back after it: 2.3 of the 2.8 measures per
  // collapse on armadillo did). Either way the candidate is collapsed at the top with its
  // whole measured key, which replaces the cost find_best() queued it with.
  // EncodeOptions::fast: no measured distance, the key stays the cost, but for a texture
  // seam's drift (cheap, and what keeps the seams from sliding off their texture).
  // 3.7 times faster on nefertiti (100K faces: 0.35 s against 1.28 s), the levels'
  // Hausdorff distance twice as far from the input and the RMS 1.2 times (geometric means
  // on the shared meshes at 50, 10 and 2%). The records are the same bound either way
  // (the tracked points, apply()).
  if (!measure_) {
    if (seam_drift_ && measured_[v] != kMeasuredWhole) {
      measured_[v] = kMeasuredWhole;
      const double drift = seam_drift(star);
      if (drift > 0 && !top_with_measure(worker, v, drift)) return false;
    }
  } else if (!whole_measured(measured_[v])) {
    if (measured_[v] != kMeasuredPoints) {
      // When only points moved onto v's faces since its whole was measured (a collapse
      // onto a neighbour, apply()), the fan's part of it still holds: the whole is the
      // larger of that part and the points' (kPointsMovedFanAbove: measured_worst_ holds
      // the fan's part), or the points' alone when they are as far as they were, the fan's
      // part at most that then (kPointsMovedFanBelow: measured_worst_ holds a bound of it).
      // 4% of the whole measures on nefertiti and armadillo. The steps and keys are those of
      // a measure from nothing: the points' key first, then the whole's, each queued afresh
      // when it differs (equal keys go oldest first, Worker::queue()). So the sequence is
      // the one without the reuse (test_encoder.cpp's MeasuredLoop), unless the fan's part
      // measured again would differ: input_distance() starts its search from the kept
      // points, which move, and a part's rounding depends on the distance it starts from.
      // On nefertiti after a Loop step, 1 of 20,761 reused parts did; on the shared meshes
      // and the samples none.
      const uint8_t before = measured_[v];
      const double fan_part = measured_worst_[v];
      double worst = kept_.points_distance(v, old_faces, n_old, fan, n_fan);
      worst = std::max(worst, seam_drift(star));
      const bool fan_known = before == kPointsMovedFanAbove ||
                             (before == kPointsMovedFanBelow && worst >= fan_part);
      measured_[v] = kMeasuredPoints;
      measured_worst_[v] = worst;
      if (!top_with_measure(worker, v, worst)) {
        // Back in the heap with the points' key. A fan's part known to be at most the
        // points' makes that key the whole already (the measure from nothing would find so).
        if (fan_known && worst >= fan_part) measured_[v] = kMeasuredWhole;
        return false;
      }
      if (fan_known) {
        measured_[v] = fan_part > worst ? kMeasuredWholeFanAbove : kMeasuredWhole;
        measured_worst_[v] = std::max(worst, fan_part);
        return top_with_measure(worker, v, measured_worst_[v]);
      }
    }
    if (!whole_measured(measured_[v])) {  // the fan's part, unless it still held above
      const double points_worst = measured_worst_[v];
      KeptPoints::FanFace old_fan[kMaxValence];
      for (int i = 0; i < n_old; ++i) old_fan[i] = old_fan_face(old_faces[i]);
      double worst =
          KeptPoints::surface_distance(fan, moved, old_fan, n_old, point(u), points_worst);
      // Schroeder's metric: the old fan against the new one too (kept_points.h).
      if (schroeder_)
        worst = KeptPoints::grid_distance(old_fan, n_old, fan, n_fan,
                                          KeptPoints::kSchroederOldFanSteps, worst);
      // The moved faces against the input around v and its neighbours (kept_points.h).
      uint32_t region[kMaxValence + 1];
      int n_region = 0;
      region[n_region++] = v;
      for (int i = 0; i < n; ++i) region[n_region++] = ring_v[i].vertex;
      worst = kept_.input_distance(fan, moved, point(u), region, n_region, old_faces, n_old,
                                   input_, worst);
      measured_[v] = worst > points_worst ? kMeasuredWholeFanAbove : kMeasuredWhole;
      measured_worst_[v] = worst;  // what the key holds now (queued_measured_key())
      if (!top_with_measure(worker, v, worst)) return false;
    }
  }
  return true;
}

}  // namespace pm::collapse_loop
