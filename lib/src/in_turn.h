// Independent tasks on this thread and one more: each thread takes the next task left
// (a shared counter), so that tasks of uneven size still end together. For the fast loop's
// regions (fast_simplifier.cpp) and other work that splits into parts sharing nothing
// that changes. Two threads: the machines this is measured on have two cores.
#pragma once

#include <atomic>
#include <cstddef>
#include <exception>
#include <thread>

namespace pm {

// Runs f(task, caller) for every task in [0, tasks), caller telling whether this thread
// runs it (the one that may report progress). On a single core, all on this thread, in
// order. An exception from f is rethrown here once both threads are done.
template <typename F>
void run_in_turn(std::size_t tasks, F&& f) {
  std::atomic<std::size_t> next{0};
  auto work = [&](bool caller) {
    for (std::size_t i = next++; i < tasks; i = next++) f(i, caller);
  };
  if (tasks < 2 || std::thread::hardware_concurrency() < 2) return work(true);
  std::exception_ptr failure;
  std::thread second([&] {
    try {
      work(false);
    } catch (...) {
      next = tasks;  // the caller's thread stops taking tasks too
      failure = std::current_exception();
    }
  });
  try {
    work(true);
  } catch (...) {
    next = tasks;
    second.join();
    throw;
  }
  second.join();
  if (failure) std::rethrow_exception(failure);
}

// Runs f(begin, end) on slices of [0, n) that cover it, in turn as above; one slice, here,
// when n is small (a thread costs more than it saves there).
template <typename F>
void run_in_slices(std::size_t n, F&& f) {
  constexpr std::size_t kSlices = 16, kSmall = std::size_t{1} << 15;
  if (n < kSmall) return f(std::size_t{0}, n);
  run_in_turn(kSlices,
              [&](std::size_t slice, bool) { f(n * slice / kSlices, n * (slice + 1) / kSlices); });
}

}  // namespace pm
