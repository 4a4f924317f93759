// Independent tasks on several threads: each thread takes the next task left (a shared
// counter), so that tasks of uneven size still end together. For the collapse loop's regions
// (simplifier.cpp) and other work that splits into parts sharing nothing that changes.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

namespace pm {

// `requested` threads, or the machine's cores when 0; at least 1.
inline unsigned thread_count(unsigned requested) {
  return requested != 0 ? requested : std::max(1u, std::thread::hardware_concurrency());
}

// Starts f on a thread of its own in `thread` (empty before); false, with `thread` left empty,
// when the system has none to give (std::thread's std::system_error: pthread_create's EAGAIN
// under a process or thread limit). The caller then does that work itself: the library never
// fails for want of a thread. Every thread the library starts goes through here.
template <typename F>
bool try_start_thread(std::thread& thread, F&& f) {
  try {
    thread = std::thread(std::forward<F>(f));
    return true;
  } catch (const std::system_error&) {
    return false;
  }
}

// Starts up to `count` more threads, each running f, into `threads`, and stops at the first
// the system refuses (try_start_thread()); returns how many started. The callers share their
// work among those and their own thread, so fewer than asked is never an error.
template <typename F>
std::size_t start_threads(std::vector<std::thread>& threads, std::size_t count, const F& f) {
  threads.reserve(threads.size() + count);  // so that push_back() below cannot throw
  std::size_t started = 0;
  for (; started < count; ++started) {
    std::thread thread;
    if (!try_start_thread(thread, f)) break;
    threads.push_back(std::move(thread));
  }
  return started;
}

// Runs f(task, caller) for every task in [0, tasks), on this thread and up to threads - 1
// more; `caller` tells whether this thread runs it (the one that may report progress).
// With one thread, all here, in order. The first exception from f is rethrown here once
// every thread is done; the others stop taking tasks. A thread that cannot be started leaves
// its share to the others (never an exception of its own).
template <typename F>
void run_in_turn(std::size_t tasks, unsigned threads, F&& f) {
  std::atomic<std::size_t> next{0};
  auto work = [&](bool caller) {
    for (std::size_t i = next++; i < tasks; i = next++) f(i, caller);
  };
  const std::size_t helpers = std::min<std::size_t>(threads, tasks) - (threads > 0 ? 1 : 0);
  if (tasks < 2 || helpers == 0) return work(true);
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto guarded = [&](bool caller) {
    try {
      work(caller);
    } catch (...) {
      next = tasks;
      const std::lock_guard<std::mutex> lock(failure_mutex);
      if (!failure) failure = std::current_exception();
    }
  };
  // No more threads to be had: those started and this one take every task.
  std::vector<std::thread> others;
  start_threads(others, helpers, [&] { guarded(false); });
  guarded(true);
  for (std::thread& t : others) t.join();
  if (failure) std::rethrow_exception(failure);
}

// Runs f(begin, end) on slices of [0, n) that cover it, in turn as above; one slice, here,
// when n is small (a thread costs more than it saves there).
template <typename F>
void run_in_slices(std::size_t n, unsigned threads, F&& f) {
  constexpr std::size_t kSlices = 16, kSmall = std::size_t{1} << 15;
  if (n < kSmall || threads < 2) return f(std::size_t{0}, n);
  run_in_turn(kSlices, threads,
              [&](std::size_t slice, bool) { f(n * slice / kSlices, n * (slice + 1) / kSlices); });
}

}  // namespace pm
