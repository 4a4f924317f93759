// The tracked points on a thread of their own: see tracking_thread.h.
#include "simplify/tracking_thread.h"

#include <algorithm>
#include <chrono>

#include "core/in_turn.h"

namespace pm::collapse_loop {
namespace {

// Waits for `ready` to hold: a short spin (a collapse takes microseconds), then yields. The
// tracking thread, waiting for work, sleeps after a long wait (a merge, or a loop held up),
// so as not to keep a core from others; the loop, waiting for room, never does: its wait ends
// as soon as a collapse is tracked. pmenc --fast on nefertiti after two Loop steps, two
// threads: both sleeping 2.65 s against 2.28 with neither; this one sleeping, 2.37 against
// 2.35 (medians of 4 alternating runs).
template <typename Ready, typename Help>
void wait_until(Ready ready, bool may_sleep, Help help) {
  for (uint64_t spins = 0; !ready(); ++spins) {  // unsigned: a long wait wraps, harmlessly
    help();
    if (may_sleep && spins >= 4096) {
      std::this_thread::sleep_for(std::chrono::microseconds(50));
    } else if (spins >= 256) {
      std::this_thread::yield();
    } else {
#if defined(__x86_64__) || defined(__i386__)
      __builtin_ia32_pause();
#endif
    }
  }
}

}  // namespace

bool TrackingThread::start(TrackedPoints& tracked, bool measured, float record_floor) {
  stop();  // a thread of an earlier start, if any
  tracked_ = &tracked;
  measured_ = measured;
  floor_ = record_floor;
  failure_ = nullptr;
  stopping_ = false;
  pushed_ = 0;
  done_ = 0;
  parts_helped_ = 0;
  if (!slots_) slots_.reset(new Task[kSlots]);
  // No thread to be had: the caller tracks in turn.
  return try_start_thread(thread_, [this] { run(); });
}

void TrackingThread::push(uint32_t v, const uint32_t* old_faces, int n_old,
                          const KeptPoints::FanFace* fan, int n_fan, double farthest,
                          float* record) {
  const uint64_t at = pushed_.load(std::memory_order_relaxed);
  wait_until([&] { return at - done_.load(std::memory_order_acquire) < kSlots; }, false,
             [this] { help(); });
  Task& task = slots_[at % kSlots];
  task.v = v;
  task.n_old = n_old;
  task.n_fan = n_fan;
  task.farthest = farthest;
  task.record = record;
  std::copy(old_faces, old_faces + n_old, task.old_faces);
  std::copy(fan, fan + n_fan, task.fan);
  pushed_.store(at + 1, std::memory_order_release);
}

void TrackingThread::run() {
  for (uint64_t next = 0;; ++next) {
    wait_until(
        [&] {
          return pushed_.load(std::memory_order_acquire) > next ||
                 stopping_.load(std::memory_order_acquire);
        },
        true, [] {});
    if (pushed_.load(std::memory_order_acquire) <= next) return;  // stopping, none left
    if (!failure_) {
      try {
        track(slots_[next % kSlots]);
      } catch (...) {  // scratch_'s growth: drain() rethrows it; the rest only count
        failure_ = std::current_exception();
      }
    }
    done_.store(next + 1, std::memory_order_release);
  }
}

// As CollapseLoop::apply() does in turn, the collapse's parts on this thread and the loop's.
void TrackingThread::track(const Task& task) {
  *task.record = tracked_->track(task.v, task.old_faces, task.n_old, task.fan, task.n_fan,
                                 measured_, task.farthest, &floor_, scratch_, this);
}

void TrackingThread::run_parts(uint32_t count, const std::function<void(uint32_t)>& part) {
  // Published before the epoch that opens them (release): a helper that takes a part of it
  // (acquire) reads these. They change only once every part is done, below.
  part_.store(&part, std::memory_order_relaxed);
  part_count_.store(count, std::memory_order_relaxed);
  parts_done_.store(0, std::memory_order_relaxed);
  const uint64_t epoch = (ticket_.load(std::memory_order_relaxed) >> 32) | 1;  // odd: open
  ticket_.store(epoch << 32, std::memory_order_release);
  while (run_a_part()) {
  }
  // The parts the loop's thread took, until it has done them (a few microseconds each).
  wait_until([&] { return parts_done_.load(std::memory_order_acquire) == count; }, false,
             [] {});
  ticket_.store((epoch + 1) << 32, std::memory_order_release);  // even: closed
}

bool TrackingThread::run_a_part() {
  uint64_t ticket = ticket_.load(std::memory_order_acquire);
  for (;;) {
    if (((ticket >> 32) & 1) == 0) return false;  // no parts open
    const auto index = static_cast<uint32_t>(ticket);
    if (index >= part_count_.load(std::memory_order_relaxed)) return false;  // all taken
    // Taken only while the epoch and the place are still these: a ticket of the next
    // collapse's parts fails here, and reads again.
    if (ticket_.compare_exchange_weak(ticket, ticket + 1, std::memory_order_acq_rel,
                                      std::memory_order_acquire)) {
      (*part_.load(std::memory_order_relaxed))(index);
      parts_done_.fetch_add(1, std::memory_order_release);
      return true;
    }
  }
}

float TrackingThread::drain() {
  const uint64_t all = pushed_.load(std::memory_order_relaxed);
  wait_until([&] { return done_.load(std::memory_order_acquire) >= all; }, false,
             [this] { help(); });
  if (failure_) std::rethrow_exception(failure_);
  return floor_;
}

void TrackingThread::stop() {
  if (!thread_.joinable()) return;
  stopping_.store(true, std::memory_order_release);
  thread_.join();
}

}  // namespace pm::collapse_loop
