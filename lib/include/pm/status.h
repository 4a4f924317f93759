// Errors as values: every fallible library function returns a Status (or fills one).
// The library never prints and never exits; the command-line tools map ErrorCode to
// exit codes (see README.md, "Exit codes").
//
// The contract, for every public function that returns a Status:
//  - It never throws: running out of memory (std::bad_alloc, or a container's length_error)
//    is kResourceLimit "out of memory". Functions that return a value instead (extract_level,
//    RuntimeLod, to_mesh, ...) throw std::bad_alloc when memory runs out, as the standard
//    containers they return do.
//  - Status is [[nodiscard]], and so is every such function: ignoring one is a warning
//    (an error with -Werror=unused-result).
//  - One code per kind of bad input, whatever the entry point (below).
#pragma once

#include <string>
#include <utility>

namespace pm {

// Stable codes: the numbers never change meaning; new codes are appended.
enum class ErrorCode : int {
  kOk = 0,
  // The caller's data or options, in memory, are wrong: an option out of range; a Mesh that
  // is not well formed (arrays of the wrong length, a vertex, texture-coordinate, normal or
  // material index out of range, a coordinate that is not finite: validate_attributes());
  // a ProgressiveMesh that fails validate(); a call out of order (PmStreamReader::take
  // before finish).
  kInvalidArgument = 1,
  kIoError = 2,             // a file could not be opened, read or written
  // A mesh file (OBJ, PLY, OFF, STL) is malformed, whatever is wrong in it: a bad number,
  // any index out of range, a non-finite value. The message names the line or element.
  kParseError = 3,
  kUnsupportedFormat = 4,   // unknown file extension or mesh format
  kCorruptStream = 5,       // a .pm stream violates the format (any inconsistency in it)
  kTruncatedStream = 6,     // a .pm stream ends early
  kUnsupportedVersion = 7,  // a .pm stream of a version this reader does not know
  kChecksumMismatch = 8,    // a header or section checksum does not match
  kEmptyMesh = 9,           // the input has no faces and no vertices
  // A count exceeds what this build or the format can hold (2^30 vertices, a memory bound
  // the caller set), or memory ran out ("out of memory").
  kResourceLimit = 10,
  kInternal = 11,           // a bug: an invariant of the library itself failed
};

// The stable name of a code, e.g. "corrupt-stream".
const char* error_code_name(ErrorCode code);

// A value: owns its message; copyable and movable.
class [[nodiscard]] Status {
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
