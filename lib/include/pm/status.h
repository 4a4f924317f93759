// Errors as values: every fallible library function returns a Status (or fills one).
// The library never prints and never exits; the command-line tools map ErrorCode to
// exit codes (see README.md, "Exit codes").
#pragma once

#include <string>
#include <utility>

namespace pm {

// Stable codes: the numbers never change meaning; new codes are appended.
enum class ErrorCode : int {
  kOk = 0,
  kInvalidArgument = 1,     // a caller's argument is out of range
  kIoError = 2,             // a file could not be opened, read or written
  kParseError = 3,          // a mesh file is malformed
  kUnsupportedFormat = 4,   // unknown file extension or mesh format
  kCorruptStream = 5,       // a .pm stream violates the format
  kTruncatedStream = 6,     // a .pm stream ends early
  kUnsupportedVersion = 7,  // a .pm stream of a version this reader does not know
  kChecksumMismatch = 8,    // a header or section checksum does not match
  kEmptyMesh = 9,           // the input has no faces and no vertices
  kResourceLimit = 10,      // a count exceeds what this build can hold
  kInternal = 11,           // a bug: an invariant of the library itself failed
};

// The stable name of a code, e.g. "corrupt-stream".
const char* error_code_name(ErrorCode code);

class Status {
 public:
  Status() = default;
  Status(ErrorCode code, std::string message) : code_(code), message_(std::move(message)) {}
  static Status ok() { return Status(); }

  bool is_ok() const { return code_ == ErrorCode::kOk; }
  explicit operator bool() const { return is_ok(); }
  ErrorCode code() const { return code_; }
  // One line, lower case, no file name (the caller knows the file): "face 12 uses vertex 99 of 40".
  const std::string& message() const { return message_; }

 private:
  ErrorCode code_ = ErrorCode::kOk;
  std::string message_;
};

}  // namespace pm
