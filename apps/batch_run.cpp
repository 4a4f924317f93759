// Running a batch (batch.h): tasks on N threads, largest input first, with a progress bar
// or one line per file on stderr and JSON Lines on stdout.
#include <sched.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>
#include <numeric>
#include <system_error>
#include <thread>

#include "batch.h"
#include "cli_common.h"

namespace pm::cli {

unsigned default_jobs() {
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof set, &set) == 0) {
    const int count = CPU_COUNT(&set);
    if (count > 0) return static_cast<unsigned>(count);
  }
  return std::max(1u, std::thread::hardware_concurrency());
}

bool stderr_wants_progress_bar() {
  if (!isatty(STDERR_FILENO)) return false;
  const char* term = std::getenv("TERM");
  return !(term && std::strcmp(term, "dumb") == 0);
}

namespace {

// What one worker thread is converting, for the progress bar.
struct WorkerState {
  std::atomic<bool> busy{false};
  std::atomic<uint64_t> size{0};
  std::atomic<uint64_t> faces{0};
  std::atomic<double> fraction{0};
};

std::string count_text(double value) {
  char text[32];
  if (value >= 1e6)
    std::snprintf(text, sizeof text, "%.2fM", value / 1e6);
  else if (value >= 1e4)
    std::snprintf(text, sizeof text, "%.0fk", value / 1e3);
  else
    std::snprintf(text, sizeof text, "%.0f", value);
  return text;
}

std::string duration_text(double seconds) {
  const long s = std::lround(seconds);
  char text[32];
  if (s >= 3600)
    std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  else
    std::snprintf(text, sizeof text, "%ld:%02ld", s / 60, s % 60);
  return text;
}

int terminal_width() {
  winsize size{};
  if (ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col >= 20) return size.ws_col;
  return 80;
}

// Everything a batch prints: error and note lines and the bar on stderr, JSON and the tools'
// text on stdout, one whole line at a time under one lock.
class Board {
 public:
  Board(const RunOptions& options, const std::vector<Task>& tasks,
        std::vector<WorkerState>& workers)
      : options_(options), workers_(workers), task_count_(tasks.size()) {
    for (const Task& task : tasks) total_bytes_ += task.input.size;
  }

  void note(const std::string& line) {
    if (options_.quiet) return;
    std::lock_guard<std::mutex> lock(mutex_);
    print_locked(std::string(options_.tool) + ": " + line);
  }

  void finish(const Task& task, Outcome& outcome, double seconds) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++done_;
    done_bytes_ += task.input.size;
    done_faces_ += outcome.faces;
    const bool failed = !outcome.status;
    if (failed) {
      ++failed_;
      if (outcome.exit_code == kExitOk) outcome.exit_code = exit_code_for(outcome.status.code());
      const std::string& file = outcome.error_file.empty() ? task.input.path : outcome.error_file;
      print_locked(error_line(options_.tool, file, outcome.status.message()));
    } else {
      if (outcome.skipped) ++skipped_;
      if (outcome.exit_code != kExitOk) ++warned_;  // done, with a warning (pmdec: truncated)
      // With the bar, per-file lines are for a single file only (the bar counts the others).
      const bool lines_wanted = !options_.progress_bar || task_count_ == 1;
      if (!options_.quiet && lines_wanted && !outcome.summary.empty())
        print_locked(std::string(options_.tool) + ": " + outcome.summary);
    }
    if (options_.json) print_json_locked(task, outcome, seconds);
    if (!outcome.stdout_text.empty()) {
      std::fwrite(outcome.stdout_text.data(), 1, outcome.stdout_text.size(), stdout);
      std::fflush(stdout);
    }
    if (bar_visible_) draw_bar_locked();
  }

  void draw_bar() {
    std::lock_guard<std::mutex> lock(mutex_);
    draw_bar_locked();
  }

  // Clears the bar and prints the totals of a batch of several files.
  void close(double seconds) {
    std::lock_guard<std::mutex> lock(mutex_);
    clear_bar_locked();
    bar_visible_ = false;
    if (options_.quiet || task_count_ < 2) return;
    char line[256];
    std::snprintf(line, sizeof line,
                  "%s: %zu files: %zu converted, %zu skipped, %zu failed, %s faces in %.2f s",
                  options_.tool, task_count_, done_ - failed_ - skipped_, skipped_, failed_,
                  count_text(static_cast<double>(done_faces_)).c_str(), seconds);
    print_locked(line);
  }

  std::size_t failed() const { return failed_; }
  std::size_t warned() const { return warned_; }

 private:
  void print_locked(const std::string& line) {
    clear_bar_locked();
    std::string text = line + "\n";
    std::fwrite(text.data(), 1, text.size(), stderr);
    if (bar_visible_) draw_bar_locked();
    std::fflush(stderr);
  }

  void clear_bar_locked() {
    if (bar_drawn_) std::fputs("\r\x1b[K", stderr);
    bar_drawn_ = false;
  }

  void draw_bar_locked() {
    if (!options_.progress_bar || options_.quiet) return;
    bar_visible_ = true;
    const double elapsed = seconds_since(start_);
    double bytes = static_cast<double>(done_bytes_);
    double faces = static_cast<double>(done_faces_);
    for (const WorkerState& worker : workers_) {
      if (!worker.busy.load()) continue;
      const double fraction = std::clamp(worker.fraction.load(), 0.0, 1.0);
      bytes += fraction * static_cast<double>(worker.size.load());
      faces += fraction * static_cast<double>(worker.faces.load());
    }
    const double done = total_bytes_ > 0 ? bytes / static_cast<double>(total_bytes_)
                                         : static_cast<double>(done_) / task_count_;
    constexpr int kBarWidth = 20;
    const int filled = std::clamp(static_cast<int>(done * kBarWidth), 0, kBarWidth);
    std::string line = std::string(options_.tool) + " " + std::to_string(done_) + "/" +
                       std::to_string(task_count_) + " files [" + std::string(filled, '#') +
                       std::string(kBarWidth - filled, '.') + "] ";
    char figures[128];
    std::snprintf(figures, sizeof figures, "%3d%%  %s faces/s  ETA %s",
                  static_cast<int>(done * 100),
                  count_text(elapsed > 0 ? faces / elapsed : 0).c_str(),
                  done > 0.005 && elapsed > 0.5 ? duration_text(elapsed * (1 - done) / done).c_str()
                                                : "-:--");
    line += figures;
    if (failed_) line += "  " + std::to_string(failed_) + " failed";
    const std::size_t width = static_cast<std::size_t>(terminal_width() - 1);
    if (line.size() > width) line.resize(width);
    std::fputs(("\r" + line + "\x1b[K").c_str(), stderr);
    std::fflush(stderr);
    bar_drawn_ = true;
  }

  void print_json_locked(const Task& task, const Outcome& outcome, double seconds) {
    const char* status = !outcome.status ? "failed" : outcome.skipped ? "skipped" : "ok";
    std::string line = "{\"input\":" + json_string(task.input.path) + ",";
    if (!outcome.json.empty()) line += outcome.json + ",";
    line += std::string("\"status\":\"") + status +
            "\",\"error\":" + (outcome.status ? "null" : json_string(outcome.status.message())) +
            ",\"error_code\":" +
            (outcome.status ? "null" : json_string(error_code_name(outcome.status.code()))) +
            ",\"exit_code\":" + std::to_string(outcome.exit_code);
    char tail[64];
    std::snprintf(tail, sizeof tail, ",\"seconds\":%.3f}\n", seconds);
    line += tail;
    std::fwrite(line.data(), 1, line.size(), stdout);
    std::fflush(stdout);
  }

  const RunOptions& options_;
  std::vector<WorkerState>& workers_;
  const std::size_t task_count_;
  uint64_t total_bytes_ = 0;
  const std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::mutex mutex_;
  std::size_t done_ = 0, failed_ = 0, skipped_ = 0, warned_ = 0;
  uint64_t done_bytes_ = 0, done_faces_ = 0;
  bool bar_visible_ = false;  // the bar has been shown and is to be redrawn after lines
  bool bar_drawn_ = false;    // the bar is on the current line of the terminal now
};

class WorkerProgress final : public JobProgress {
 public:
  WorkerProgress(WorkerState& state, Board& board) : state_(state), board_(board) {}
  void set_faces(uint64_t faces) override { state_.faces.store(faces); }
  void set_fraction(double fraction) override { state_.fraction.store(fraction); }
  void note(const std::string& line) override { board_.note(line); }

 private:
  WorkerState& state_;
  Board& board_;
};

Outcome run_one(const Task& task, const Job& job, JobProgress& progress) {
  try {
    return job(task, progress);
  } catch (const std::bad_alloc&) {
    Outcome outcome;
    outcome.status = Status(ErrorCode::kResourceLimit, "out of memory (try fewer jobs, -j 1)");
    return outcome;
  } catch (const std::exception& e) {
    Outcome outcome;
    outcome.status = Status(ErrorCode::kInternal, std::string("internal error: ") + e.what());
    return outcome;
  }
}

}  // namespace

int run_batch(const std::vector<Task>& tasks, const RunOptions& options, const Job& job) {
  const auto start = std::chrono::steady_clock::now();
  const unsigned threads = static_cast<unsigned>(
      std::clamp<std::size_t>(options.jobs, 1, std::max<std::size_t>(tasks.size(), 1)));
  std::vector<WorkerState> workers(threads);
  Board board(options, tasks, workers);

  // Largest first: the long conversions start early, so that no core waits at the end on
  // one big file while the others are idle.
  std::vector<std::size_t> order(tasks.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&tasks](std::size_t a, std::size_t b) {
    return tasks[a].input.size > tasks[b].input.size;
  });
  std::atomic<std::size_t> next{0};
  int single_exit_code = kExitOk;
  auto work = [&](unsigned worker) {
    WorkerProgress progress(workers[worker], board);
    for (;;) {
      const std::size_t i = next.fetch_add(1);
      if (i >= order.size()) return;
      const Task& task = tasks[order[i]];
      WorkerState& state = workers[worker];
      state.faces = 0;
      state.fraction = 0;
      state.size = task.input.size;
      state.busy = true;
      const auto task_start = std::chrono::steady_clock::now();
      Outcome outcome = run_one(task, job, progress);
      state.busy = false;
      board.finish(task, outcome, seconds_since(task_start));
      if (tasks.size() == 1) single_exit_code = outcome.exit_code;
    }
  };

  // The bar is redrawn by a ticker, so that the ETA moves while files take their time.
  std::mutex ticker_mutex;
  std::condition_variable ticker_wake;
  bool finished = false;
  std::thread ticker;
  if (options.progress_bar && !options.quiet) {
    try {
      ticker = std::thread([&] {
        std::unique_lock<std::mutex> lock(ticker_mutex);
        while (!finished) {
          board.draw_bar();
          ticker_wake.wait_for(lock, std::chrono::milliseconds(200));
        }
      });
    } catch (const std::system_error&) {
      // No thread to be had: no bar (the totals still close the batch).
    }
  }
  if (threads == 1) {
    work(0);
  } else {
    std::vector<std::thread> pool;
    pool.reserve(threads);  // so that only a thread's start can throw below
    try {
      for (unsigned t = 0; t < threads; ++t) pool.emplace_back(work, t);
    } catch (const std::system_error&) {
      // No more threads to be had (a process or thread limit): those started take every
      // file, or this one when none did.
      if (pool.empty()) work(0);
    }
    for (std::thread& thread : pool) thread.join();
  }
  if (ticker.joinable()) {
    {
      std::lock_guard<std::mutex> lock(ticker_mutex);
      finished = true;
    }
    ticker_wake.notify_all();
    ticker.join();
  }
  board.close(seconds_since(start));
  if (tasks.size() == 1) return single_exit_code;
  return board.failed() || board.warned() ? kExitSomeFailed : kExitOk;
}

}  // namespace pm::cli
