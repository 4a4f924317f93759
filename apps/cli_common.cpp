#include "cli_common.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>

namespace pm::cli {
namespace {

// The temporary file being written, for the signal handler (async-signal-safe: a fixed
// buffer, unlink() and _exit() only).
char g_temp_path[4096] = {0};

void remove_temp_and_exit(int signal_number) {
  if (g_temp_path[0] != '\0') unlink(g_temp_path);
  _exit(128 + signal_number);
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

int fail(std::string_view tool, std::string_view file, const Status& status) {
  std::cerr << tool << ": " << (file == "-" ? "(stdin)" : file) << ": " << status.message()
            << std::endl;
  return exit_code_for(status.code());
}

Status read_whole_input(const std::string& path, std::string& bytes) {
  const bool from_stdin = path == "-";
  const int fd = from_stdin ? STDIN_FILENO : ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return io_error("cannot open");
  struct stat st {};
  if (fstat(fd, &st) == 0 && S_ISDIR(st.st_mode)) {
    if (!from_stdin) ::close(fd);
    return Status(ErrorCode::kIoError, "is a directory");
  }
  bytes.clear();
  if (S_ISREG(st.st_mode)) bytes.reserve(static_cast<std::size_t>(st.st_size));
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      Status s = io_error("cannot read");
      if (!from_stdin) ::close(fd);
      return s;
    }
    if (n == 0) break;
    bytes.append(buffer, static_cast<std::size_t>(n));
  }
  if (!from_stdin) ::close(fd);
  return Status::ok();
}

Status write_output_atomically(const std::string& path, std::string_view bytes, bool binary) {
  if (path == "-") {
    if (binary && isatty(STDOUT_FILENO))
      return Status(ErrorCode::kInvalidArgument, "refusing to write binary data to a terminal");
    if (!write_all(STDOUT_FILENO, bytes)) return io_error("cannot write to standard output");
    return Status::ok();
  }
  std::string temp = path + ".tmp.XXXXXX";
  if (temp.size() >= sizeof g_temp_path) return Status(ErrorCode::kIoError, "output path too long");
  const int fd = mkstemp(temp.data());
  if (fd < 0) return io_error("cannot create output");
  // Published before the first byte is written, so an interrupt removes the file.
  std::memcpy(g_temp_path, temp.c_str(), temp.size() + 1);
  const bool written = write_all(fd, bytes) && fsync(fd) == 0;
  Status status = written ? Status::ok() : io_error("cannot write output");
  fchmod(
      fd, 0644 & ~[] {
        mode_t m = umask(0);
        umask(m);
        return m;
      }());
  if (::close(fd) != 0 && status) status = io_error("cannot write output");
  if (status && std::rename(temp.c_str(), path.c_str()) != 0)
    status = io_error("cannot rename output");
  if (!status) unlink(temp.c_str());
  g_temp_path[0] = '\0';
  if (!status) return Status(ErrorCode::kIoError, status.message());
  return status;
}

void install_cleanup_handlers() {
  struct sigaction action {};
  action.sa_handler = remove_temp_and_exit;
  sigemptyset(&action.sa_mask);
  for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaction(s, &action, nullptr);
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
