#include "cli_common.h"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <mutex>
#include <set>
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

Status over_limit(uint64_t size, uint64_t max_bytes) {
  return Status(ErrorCode::kResourceLimit, "input is " + std::to_string(size) +
                                               " bytes, more than the memory limit of " +
                                               std::to_string(max_bytes) + " bytes");
}

const char* const kTemporaryInfix = ".tmp.";
constexpr std::size_t kTemporaryRandomChars = 6;  // mkstemp's XXXXXX

}  // namespace

ExitCode exit_code_for(ErrorCode code) {
  switch (code) {
    case ErrorCode::kOk:
      return kExitOk;
    case ErrorCode::kInvalidArgument:
      return kExitUsage;
    case ErrorCode::kIoError:
      return kExitCannotRead;
    case ErrorCode::kParseError:
    case ErrorCode::kCorruptStream:
    case ErrorCode::kTruncatedStream:
    case ErrorCode::kChecksumMismatch:
    case ErrorCode::kEmptyMesh:
      return kExitBadInput;
    case ErrorCode::kUnsupportedFormat:
    case ErrorCode::kUnsupportedVersion:
      return kExitUnsupported;
    case ErrorCode::kResourceLimit:
      return kExitTooLarge;
    case ErrorCode::kInternal:
      return kExitInternal;
  }
  return kExitInternal;
}

ExitCode exit_code_for_write(const Status& status) {
  return status.code() == ErrorCode::kInvalidArgument ? kExitUsage : kExitCannotWrite;
}

std::string error_line(std::string_view tool, std::string_view file, std::string_view message) {
  std::string line(tool);
  line += ": ";
  line += file == "-" ? "(stdin)" : file;
  line += ": ";
  line += message;
  return line;
}

int fail(std::string_view tool, std::string_view file, const Status& status) {
  std::cerr << error_line(tool, file, status.message()) << std::endl;
  return exit_code_for(status.code());
}

Status read_whole_input(const std::string& path, std::string& bytes, uint64_t max_bytes) {
  const bool from_stdin = path == "-";
  const int fd = from_stdin ? STDIN_FILENO : ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return io_error("cannot open");
  auto close_file = [&] {
    if (!from_stdin) ::close(fd);
  };
  struct stat st {};
  if (fstat(fd, &st) == 0 && S_ISDIR(st.st_mode)) {
    close_file();
    return Status(ErrorCode::kIoError, "is a directory");
  }
  bytes.clear();
  if (S_ISREG(st.st_mode)) {
    if (max_bytes > 0 && static_cast<uint64_t>(st.st_size) > max_bytes) {
      close_file();
      return over_limit(static_cast<uint64_t>(st.st_size), max_bytes);
    }
    bytes.reserve(static_cast<std::size_t>(st.st_size));
  }
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      Status s = io_error("cannot read");
      close_file();
      return s;
    }
    if (n == 0) break;
    bytes.append(buffer, static_cast<std::size_t>(n));
    if (max_bytes > 0 && bytes.size() > max_bytes) {
      close_file();
      return over_limit(bytes.size(), max_bytes);
    }
  }
  close_file();
  return Status::ok();
}

Status write_output_atomically(const std::string& path, std::string_view bytes, bool binary) {
  if (path == "-") {
    if (binary && isatty(STDOUT_FILENO))
      return Status(ErrorCode::kInvalidArgument, "refusing to write binary data to a terminal");
    if (!write_all(STDOUT_FILENO, bytes)) return io_error("cannot write to standard output");
    return Status::ok();
  }
  std::string temp = path + kTemporaryInfix + std::string(kTemporaryRandomChars, 'X');
  int fd = -1;
  int slot = -1;
  {
    // Published before the first byte is written, so an interrupt removes the file.
    std::lock_guard<std::mutex> lock(g_temporaries_mutex);
    fd = mkostemp(temp.data(), O_CLOEXEC);
    if (fd >= 0) slot = publish_temporary(temp);
  }
  if (fd < 0) return io_error("cannot create output");
  const bool written = write_all(fd, bytes) && fsync(fd) == 0;
  Status status = written ? Status::ok() : io_error("cannot write output");
  fchmod(fd, output_mode());
  if (::close(fd) != 0 && status) status = io_error("cannot write output");
  std::lock_guard<std::mutex> lock(g_temporaries_mutex);
  if (status && std::rename(temp.c_str(), path.c_str()) != 0)
    status = io_error("cannot rename output");
  if (!status) unlink(temp.c_str());
  retire_temporary(slot);
  return status;
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
  std::thread([waited] {
    int signal_number = 0;
    while (sigwait(&waited, &signal_number) != 0) {
    }
    g_temporaries_mutex.lock();
    remove_live_temporaries();
    _exit(128 + signal_number);
  }).detach();
  struct sigaction action {};
  action.sa_handler = remove_temporaries_and_exit;
  sigemptyset(&action.sa_mask);
  // SIGPIPE too: a reader that goes away (pmenc --json | head -1) ends the run, and the
  // temporaries with it.
  sigaction(SIGPIPE, &action, nullptr);
}

bool parse_size(std::string_view text, uint64_t& bytes) {
  std::size_t i = 0;
  while (i < text.size() && (std::isdigit(static_cast<unsigned char>(text[i])) || text[i] == '.'))
    ++i;
  const std::string number(text.substr(0, i));
  if (number.empty() || number.find_first_of("0123456789") == std::string::npos) return false;
  std::string_view unit = text.substr(i);
  double multiplier = 1;
  if (!unit.empty()) {
    const char* const prefixes = "KMGT";
    const char* found = std::strchr(prefixes, std::toupper(static_cast<unsigned char>(unit[0])));
    if (found && *found) {
      multiplier = std::pow(1024.0, static_cast<double>(found - prefixes + 1));
      unit.remove_prefix(1);
      if (!unit.empty() && unit[0] == 'i') unit.remove_prefix(1);
    }
  }
  if (unit == "B" || unit == "b") unit.remove_prefix(1);
  if (!unit.empty()) return false;
  char* end = nullptr;
  const double value = std::strtod(number.c_str(), &end);
  if (*end != '\0' || !std::isfinite(value)) return false;
  const double total = std::round(value * multiplier);
  if (!(total >= 1) || total > 1.8e19) return false;
  bytes = static_cast<uint64_t>(total);
  return true;
}

MeshFormat sniff_mesh_format(std::string_view bytes) {
  // Binary STL first: its 80-byte header is free text and may begin like anything else.
  if (bytes.size() >= 84) {
    const auto* count = reinterpret_cast<const unsigned char*>(bytes.data() + 80);
    const uint64_t triangles = uint64_t{count[0]} | uint64_t{count[1]} << 8 |
                               uint64_t{count[2]} << 16 | uint64_t{count[3]} << 24;
    if (84 + 50 * triangles == bytes.size()) return MeshFormat::kStl;
  }
  if (bytes.substr(0, 4) == "glTF") return MeshFormat::kGlb;  // GLB magic (glTF 2.0, §4.4.1)
  if (bytes.substr(0, 3) == "\xEF\xBB\xBF") bytes.remove_prefix(3);
  // The first keyword: skip blanks and '#' comment lines (OBJ and OFF allow them).
  std::size_t i = 0;
  for (;;) {
    while (i < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[i]))) ++i;
    if (i < bytes.size() && bytes[i] == '#') {
      i = bytes.find('\n', i);
      if (i == std::string_view::npos) return MeshFormat::kUnknown;
      continue;
    }
    break;
  }
  std::size_t end = i;
  while (end < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[end]))) ++end;
  const std::string_view keyword = bytes.substr(i, end - i);
  if (keyword == "ply") return MeshFormat::kPly;
  if (!keyword.empty() && keyword[0] == '{') return MeshFormat::kGltf;  // a JSON object
  if (keyword == "solid") return MeshFormat::kStl;
  if (keyword.size() >= 3 && keyword.substr(keyword.size() - 3) == "OFF") return MeshFormat::kOff;
  for (const char* obj : {"v", "vt", "vn", "vp", "f", "l", "p", "o", "g", "s", "usemtl", "mtllib"})
    if (keyword == obj) return MeshFormat::kObj;
  return MeshFormat::kUnknown;
}

std::string json_string(std::string_view text) {
  std::string out = "\"";
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
      ++i;
    } else if (c < 0x20) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\u%04x", c);
      out += escaped;
      ++i;
    } else if (c < 0x80) {
      out += static_cast<char>(c);
      ++i;
    } else {
      // A well-formed UTF-8 sequence is copied; anything else becomes U+FFFD.
      const std::size_t length = c >= 0xF0 && c < 0xF5 ? 4 : c >= 0xE0 ? 3 : c >= 0xC2 ? 2 : 0;
      bool valid = length > 0 && c < 0xF5 && i + length <= text.size();
      for (std::size_t k = 1; valid && k < length; ++k)
        valid = (static_cast<unsigned char>(text[i + k]) & 0xC0) == 0x80;
      if (valid && length == 3) {
        const auto c1 = static_cast<unsigned char>(text[i + 1]);
        valid = !(c == 0xE0 && c1 < 0xA0) && !(c == 0xED && c1 >= 0xA0);
      }
      if (valid && length == 4) {
        const auto c1 = static_cast<unsigned char>(text[i + 1]);
        valid = !(c == 0xF0 && c1 < 0x90) && !(c == 0xF4 && c1 >= 0x90);
      }
      if (valid) {
        out.append(text.substr(i, length));
        i += length;
      } else {
        out += "\xEF\xBF\xBD";
        ++i;
      }
    }
  }
  out += '"';
  return out;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string human_bytes(std::size_t bytes) {
  char text[32];
  if (bytes >= 1000000)
    std::snprintf(text, sizeof text, "%.2f MB", bytes / 1e6);
  else if (bytes >= 1000)
    std::snprintf(text, sizeof text, "%.1f kB", bytes / 1e3);
  else
    std::snprintf(text, sizeof text, "%zu B", bytes);
  return text;
}

}  // namespace pm::cli
