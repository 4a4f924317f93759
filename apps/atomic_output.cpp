#include "atomic_output.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <system_error>
#include <thread>

namespace pm::cli {
namespace {

// The temporary files being written, one slot per writing thread, for the signal handler.
// Async-signal-safe: fixed buffers, lock-free atomics, unlink() and _exit() only.
constexpr int kTemporarySlots = 512;
enum SlotState : int { kSlotFree = 0, kSlotClaimed = 1, kSlotLive = 2 };
struct TemporarySlot {
  std::atomic<int> state{kSlotFree};
  char path[4096] = {0};
};
TemporarySlot g_temporaries[kTemporarySlots];
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler needs lock-free atomics");

// Permissions of a new output: 0644 less the umask, read once (umask() can only be read by
// setting it, which is not safe while other threads create files).
mode_t g_output_mode = 0644;
std::atomic<bool> g_output_mode_known{false};

mode_t output_mode() {
  if (!g_output_mode_known.load()) {
    const mode_t mask = umask(0);
    umask(mask);
    g_output_mode = 0644 & ~mask;
    g_output_mode_known.store(true);
  }
  return g_output_mode;
}

// Held while a temporary is created and published, and while it is renamed and retired, so
// that the signal thread, which takes it before removing the temporaries, never sees a file
// that exists but is not yet published (or is published but already renamed into place).
std::mutex g_temporaries_mutex;

void remove_live_temporaries() {
  for (TemporarySlot& slot : g_temporaries)
    if (slot.state.load(std::memory_order_acquire) == kSlotLive) unlink(slot.path);
}

// SIGPIPE only (it is sent to the thread that wrote, so it cannot be waited for): runs on
// that thread, async-signal-safe.
void remove_temporaries_and_exit(int signal_number) {
  remove_live_temporaries();
  _exit(128 + signal_number);
}

// Claims a slot and publishes path in it; -1 if every slot is taken (the file is then not
// removed on a signal, but the write goes on).
int publish_temporary(const std::string& path) {
  if (path.size() >= sizeof g_temporaries[0].path) return -1;
  for (int i = 0; i < kTemporarySlots; ++i) {
    int expected = kSlotFree;
    if (g_temporaries[i].state.compare_exchange_strong(expected, kSlotClaimed)) {
      std::memcpy(g_temporaries[i].path, path.c_str(), path.size() + 1);
      g_temporaries[i].state.store(kSlotLive, std::memory_order_release);
      return i;
    }
  }
  return -1;
}

void retire_temporary(int slot) {
  if (slot >= 0) g_temporaries[slot].state.store(kSlotFree, std::memory_order_release);
}

const char* const kTemporaryInfix = ".tmp.";
constexpr std::size_t kTemporaryRandomChars = 6;  // mkstemp's XXXXXX

Status io_error(const std::string& what) {
  return Status(ErrorCode::kIoError, what + ": " + std::strerror(errno));
}

bool write_all(int fd, std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd, bytes.data(), bytes.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
  return true;
}

}  // namespace

AtomicOutput::~AtomicOutput() { discard(); }

void AtomicOutput::discard() {
  if (fd_ < 0) return;
  ::close(fd_);
  fd_ = -1;
  std::lock_guard<std::mutex> lock(g_temporaries_mutex);
  unlink(temp_.c_str());
  retire_temporary(slot_);
  slot_ = -1;
}

Status AtomicOutput::open(const std::string& path, bool binary) {
  discard();
  path_ = path;
  to_stdout_ = path == "-";
  if (to_stdout_) {
    if (binary && isatty(STDOUT_FILENO))
      return Status(ErrorCode::kInvalidArgument, "refusing to write binary data to a terminal");
    return Status::ok();
  }
  temp_ = path + kTemporaryInfix + std::string(kTemporaryRandomChars, 'X');
  {
    // Published before the first byte is written, so an interrupt removes the file.
    std::lock_guard<std::mutex> lock(g_temporaries_mutex);
    fd_ = mkostemp(temp_.data(), O_CLOEXEC);
    if (fd_ >= 0) slot_ = publish_temporary(temp_);
  }
  if (fd_ < 0) return io_error("cannot create output");
  return Status::ok();
}

Status AtomicOutput::write(std::string_view piece) {
  if (to_stdout_) {
    if (!write_all(STDOUT_FILENO, piece)) return io_error("cannot write to standard output");
    return Status::ok();
  }
  if (fd_ < 0) return Status(ErrorCode::kInternal, "output written before it was opened");
  if (write_all(fd_, piece)) return Status::ok();
  Status status = io_error("cannot write output");
  discard();
  return status;
}

Status AtomicOutput::commit() {
  if (to_stdout_) return Status::ok();
  if (fd_ < 0) return Status(ErrorCode::kInternal, "output committed before it was opened");
  Status status = fsync(fd_) == 0 ? Status::ok() : io_error("cannot write output");
  fchmod(fd_, output_mode());
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0 && status) status = io_error("cannot write output");
  std::lock_guard<std::mutex> lock(g_temporaries_mutex);
  if (status && std::rename(temp_.c_str(), path_.c_str()) != 0)
    status = io_error("cannot rename output");
  if (!status) unlink(temp_.c_str());
  retire_temporary(slot_);
  slot_ = -1;
  return status;
}

Status write_output_atomically(const std::string& path, std::string_view bytes, bool binary) {
  AtomicOutput output;
  if (Status status = output.open(path, binary); !status) return status;
  if (Status status = output.write(bytes); !status) return status;
  return output.commit();
}

bool is_temporary_for(std::string_view file_name, std::string_view output_name) {
  const std::size_t infix = std::strlen(kTemporaryInfix);
  return file_name.size() == output_name.size() + infix + kTemporaryRandomChars &&
         file_name.substr(0, output_name.size()) == output_name &&
         file_name.substr(output_name.size(), infix) == kTemporaryInfix;
}

void remove_stale_temporaries(const std::vector<std::string>& outputs) {
  // One directory scan per output directory, however many outputs it holds.
  std::map<std::string, std::set<std::string>> names_by_directory;
  for (const std::string& output : outputs) {
    if (output == "-") continue;
    const std::filesystem::path path(output);
    const std::string directory = path.has_parent_path() ? path.parent_path().string() : ".";
    names_by_directory[directory].insert(path.filename().string());
  }
  for (const auto& [directory, names] : names_by_directory) {
    DIR* d = opendir(directory.c_str());
    if (!d) continue;
    while (dirent* entry = readdir(d)) {
      const std::string_view name = entry->d_name;
      const std::size_t infix = name.rfind(kTemporaryInfix);
      if (infix == std::string_view::npos) continue;
      const std::string output_name(name.substr(0, infix));
      if (names.count(output_name) && is_temporary_for(name, output_name))
        unlink((directory + "/" + std::string(name)).c_str());
    }
    closedir(d);
  }
}

Status make_parent_directories(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  if (parent.empty()) return Status::ok();
  std::error_code error;
  std::filesystem::create_directories(parent, error);
  if (error && !std::filesystem::is_directory(parent))
    return Status(ErrorCode::kIoError,
                  "cannot create directory " + parent.string() + ": " + error.message());
  return Status::ok();
}

void install_cleanup_handlers() {
  output_mode();
  // SIGINT, SIGTERM and SIGHUP are blocked in this thread and so in every thread started after
  // it; one thread waits for them, takes the temporaries' lock (a writer between creating and
  // publishing a file, or between renaming and retiring it, finishes that step first), removes
  // what is being written and exits. A handler could run on any thread at any instruction.
  sigset_t waited;
  sigemptyset(&waited);
  for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&waited, s);
  pthread_sigmask(SIG_BLOCK, &waited, nullptr);
  struct sigaction action {};
  action.sa_handler = remove_temporaries_and_exit;
  sigemptyset(&action.sa_mask);
  try {
    std::thread([waited] {
      int signal_number = 0;
      while (sigwait(&waited, &signal_number) != 0) {
      }
      g_temporaries_mutex.lock();
      remove_live_temporaries();
      _exit(128 + signal_number);
    }).detach();
  } catch (const std::system_error&) {
    // No thread to be had (a process or thread limit): the signals unblocked again, each
    // with the handler SIGPIPE has below, which removes the temporaries as well as a handler
    // can (it may interrupt a writer between two steps).
    pthread_sigmask(SIG_UNBLOCK, &waited, nullptr);
    for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaction(s, &action, nullptr);
  }
  // SIGPIPE too: a reader that goes away (pmenc --json | head -1) ends the run, and the
  // temporaries with it.
  sigaction(SIGPIPE, &action, nullptr);
}

}  // namespace pm::cli
