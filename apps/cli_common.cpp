#include "cli_common.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>

namespace pm::cli {
namespace {

Status io_error(const std::string& what) {
  return Status(ErrorCode::kIoError, what + ": " + std::strerror(errno));
}

Status over_limit(uint64_t size, uint64_t max_bytes) {
  return Status(ErrorCode::kResourceLimit, "input is " + std::to_string(size) +
                                               " bytes, more than the memory limit of " +
                                               std::to_string(max_bytes) + " bytes");
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

ExitCode exit_code_for_write(const Status& status) {
  return status.code() == ErrorCode::kInvalidArgument ? kExitUsage : kExitCannotWrite;
}

bool is_binary_format(MeshFormat format) {
  return format == MeshFormat::kPly || format == MeshFormat::kStl || format == MeshFormat::kGlb;
}

Status write_mesh_output(const Mesh& mesh, MeshFormat format, const std::string& path,
                         bool create_directories, bool* output_failed) {
  AtomicOutput output;
  bool opened = false;
  *output_failed = false;
  const auto open = [&]() -> Status {
    opened = true;
    if (create_directories && path != "-") {
      if (Status status = make_parent_directories(path); !status) return status;
    }
    return output.open(path, is_binary_format(format));
  };
  bool sink_failed = false;
  Status status = write_mesh_to_sink(mesh, format, [&](std::string_view piece) -> Status {
    Status written = opened ? Status::ok() : open();
    if (written) written = output.write(piece);
    sink_failed = !written;
    return written;
  });
  if (status && !opened) {  // no piece: an empty file (no format makes one)
    status = open();
    sink_failed = !status;
  }
  if (!status) {
    *output_failed = sink_failed;
    return status;
  }
  status = output.commit();
  *output_failed = !status;
  return status;
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

void return_large_blocks_when_freed() {
#if defined(__GLIBC__)
  // Setting it also turns off glibc's raising of it (mallopt(3), M_MMAP_THRESHOLD).
  mallopt(M_MMAP_THRESHOLD, 256 * 1024);
#endif
}

}  // namespace pm::cli
