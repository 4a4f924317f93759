// What pmenc and pmdec share: exit codes, error lines, whole-file input, atomic output.
// The library knows nothing of this; it returns Status values that land here.
#pragma once

#include <chrono>
#include <string>
#include <string_view>

#include "pm/status.h"

namespace pm::cli {

// Documented in README.md ("Exit codes"); the numbers are stable.
enum ExitCode : int {
  kExitOk = 0,
  kExitInternal = 1,     // a bug in pm: please report it
  kExitUsage = 2,        // bad command line
  kExitCannotRead = 3,   // input missing or unreadable
  kExitBadInput = 4,     // input malformed: mesh syntax, empty mesh, corrupt or truncated .pm
  kExitCannotWrite = 5,  // output cannot be written
  kExitUnsupported = 6,  // unknown file format or .pm version
  kExitTooLarge = 7,     // input exceeds what pm can hold
};

ExitCode exit_code_for(ErrorCode code);

// Prints "tool: file: message" on stderr and returns the exit code for the status.
int fail(std::string_view tool, std::string_view file, const Status& status);

// Reads a whole file, or standard input for "-".
Status read_whole_input(const std::string& path, std::string& bytes);

// Writes bytes to path through a temporary file in the same directory, renamed into place
// once complete, so a failure or a signal never leaves a partial file. "-" writes to
// standard output; binary data is refused when standard output is a terminal.
Status write_output_atomically(const std::string& path, std::string_view bytes, bool binary);

// Installs SIGINT/SIGTERM/SIGHUP handlers that remove the temporary file being written.
void install_cleanup_handlers();

// Seconds since a start point, for the summary lines.
double seconds_since(std::chrono::steady_clock::time_point start);

// "1.23 MB", "456 kB", "789 B".
std::string human_bytes(std::size_t bytes);

}  // namespace pm::cli
