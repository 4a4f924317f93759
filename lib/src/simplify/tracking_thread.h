// The collapse loop's tracked points (tracked_points.h) on a thread of their own, one collapse
// behind the other: a pipeline of two stages. Internal to simplify/.
//
// Why: the points a collapse moves are all the points of v's faces, and a face holds more the
// coarser the level (about 3 N ln k moves to go from k faces to none, for N points), so most
// of the moving happens in the last percent of the collapses, which the loop makes in one heap
// on one thread after its rounds (simplifier.cpp). Nefertiti after two Loop steps without the
// measure: most of its 22.9 million moves, and pmenc's wall time on two threads 11% above the
// former kept lists and slack (the bunny after three: 18%). The moves need only what the collapse hands them (v, its
// faces, the fan's corners, and the kept points' distance with the measure), not the loop's
// state, so the loop goes on while they are made.
//
// The same records as TrackedPoints::collapse() called in order: the collapses are tracked in
// their order, each with a copy of its fan, and the floor of the loop without the measure
// (CollapseLoop::Worker::record_floor) is kept here from the records as they are made. So the
// .pm is the same for any thread count.
//
// And the loop's thread, while it waits (for room in the queue, or in drain()), takes parts of
// the collapse being tracked (TrackedPoints::PartRunner: a collapse that moves many points
// moves them in parts, the same on any thread). The last collapses move the most points, and
// the loop, whose heap is small by then, waited for them: pm_bench_encode --fast on two
// threads, the loop's thread waited 0.35 s of 1.89 on nefertiti after two Loop steps, 1.12 s
// of 5.56 on the bunny after three, 0.17 s of 1.79 on the 950K-face textured mesh; taking
// about half the parts, 0.25, 0.75 and 0.11 s (what is left is the walk along the lists,
// one dependent load a point, which stays on this thread). Wall time, medians of 4
// alternating rounds of 5 runs: nefertiti after two steps 1.60 -> 1.48 s, the textured mesh
// 1.77 -> 1.70 s (the bunny after three, rounds of 3: 5.04 -> 5.02, within the noise); one
// thread as before (nefertiti after two steps 2.40 and 2.41 s, nefertiti measured 0.92).
#pragma once

#include <atomic>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <thread>
#include <vector>

#include "simplify/kept_points.h"
#include "simplify/tracked_points.h"

namespace pm::collapse_loop {

class TrackingThread final : private TrackedPoints::PartRunner {
 public:
  TrackingThread() = default;
  TrackingThread(const TrackingThread&) = delete;
  TrackingThread& operator=(const TrackingThread&) = delete;
  ~TrackingThread() { stop(); }

  // Starts tracking into `tracked` (which the caller no longer touches until stop()), with
  // the measure or not (`measured`), and `record_floor` the largest record so far. False
  // when no thread can be had: the caller tracks in turn then.
  bool start(TrackedPoints& tracked, bool measured, float record_floor);

  // Queues the collapse v -> u (TrackedPoints::collapse()'s arguments, copied): `farthest`,
  // with the measure, the kept points' exact largest distance (the record holds it and points
  // settle within it; else the floor does); its record goes to *record when it is tracked
  // (drain()). Waits while the queue is full.
  void push(uint32_t v, const uint32_t* old_faces, int n_old, const KeptPoints::FanFace* fan,
            int n_fan, double farthest, float* record);
  // Waits until every queued collapse is tracked and returns the floor (the largest record
  // so far); rethrows what the tracking threw.
  float drain();
  // drain(), without rethrowing, and the thread ends.
  void stop();
  // How many parts of collapses the loop's thread has run since start() (tests read it).
  uint64_t parts_helped() const { return parts_helped_.load(std::memory_order_relaxed); }

 private:
  static constexpr int kSlots = 32;
  struct Task {
    uint32_t v;
    int n_old, n_fan;
    double farthest;
    float* record;
    uint32_t old_faces[TrackedPoints::kMaxOldFaces];
    KeptPoints::FanFace fan[2 * TrackedPoints::kMaxOldFaces];
  };
  void run();
  void track(const Task& task);
  // TrackedPoints::PartRunner, on the tracking thread: opens the collapse's parts to the
  // loop's thread (help()), takes them too, and returns when all are done.
  void run_parts(uint32_t count, const std::function<void(uint32_t)>& part) override;
  // Runs one open part, if there is one: whether it did.
  bool run_a_part();
  // On the loop's thread, while it waits: the open parts it can take.
  void help() {
    while (run_a_part()) parts_helped_.fetch_add(1, std::memory_order_relaxed);
  }

  TrackedPoints* tracked_ = nullptr;
  bool measured_ = false;
  std::unique_ptr<Task[]> slots_;
  std::atomic<uint64_t> pushed_{0}, done_{0};
  std::atomic<bool> stopping_{false};
  float floor_ = 0;  // the tracking thread's until drain()
  std::exception_ptr failure_;
  TrackedPoints::Scratch scratch_;
  // The open parts: (epoch << 32) | the next part to take; an odd epoch while they are
  // open, so that a part is taken only of the collapse whose parts it counts (the epoch and
  // the place change together, compare_exchange).
  std::atomic<uint64_t> ticket_{0};
  std::atomic<uint32_t> part_count_{0}, parts_done_{0};
  std::atomic<const std::function<void(uint32_t)>*> part_{nullptr};
  std::atomic<uint64_t> parts_helped_{0};
  std::thread thread_;
};

}  // namespace pm::collapse_loop
