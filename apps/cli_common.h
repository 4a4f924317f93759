// What pmenc and pmdec share: exit codes, error lines, whole-file input, sizes, JSON
// strings (and, in atomic_output.h, outputs that are whole or absent). The library knows
// nothing of this; it returns Status values that land here.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "pm/mesh_io.h"
#include "pm/status.h"
#include "atomic_output.h"

namespace pm::cli {

// Documented in README.md ("Exit codes") and the man pages; the numbers are stable.
enum ExitCode : int {
  kExitOk = 0,
  kExitInternal = 1,     // a bug in pm: please report it
  kExitUsage = 2,        // bad command line
  kExitCannotRead = 3,   // input missing or unreadable
  kExitBadInput = 4,     // input malformed: mesh syntax, empty mesh, corrupt or truncated .pm
  kExitCannotWrite = 5,  // output cannot be written
  kExitUnsupported = 6,  // unknown file format or .pm version
  kExitTooLarge = 7,     // input exceeds what pm can hold, or pmdec --max-memory
  kExitSomeFailed = 8,   // several inputs: some failed (each reported), the others converted
  kExitTruncated = 9,    // pmdec: the .pm ended early; the output is the finest level it holds
};

ExitCode exit_code_for(ErrorCode code);
// For a Status from write_output_atomically: a refused terminal is a usage error, anything
// else is kExitCannotWrite.
ExitCode exit_code_for_write(const Status& status);

// Whether a mesh format's files are binary (PLY, STL, GLB): refused on a terminal.
bool is_binary_format(MeshFormat format);

// Writes mesh to path ("-": standard output) as format, whole or absent
// (AtomicOutput), given to the file piece by piece as the writer makes it
// (write_mesh_to_sink): the text of a large mesh is never whole in memory. The file, and with
// create_directories the directories above it, are made at the first piece, so a mesh the
// writer refuses leaves nothing behind. *output_failed: whether a failure was the output's
// (exit_code_for_write()) rather than the mesh's (exit_code_for()).
Status write_mesh_output(const Mesh& mesh, MeshFormat format, const std::string& path,
                         bool create_directories, bool* output_failed);

// "tool: file: message", with "(stdin)" for "-"; no newline.
std::string error_line(std::string_view tool, std::string_view file, std::string_view message);

// Prints error_line() on stderr and returns the exit code for the status.
int fail(std::string_view tool, std::string_view file, const Status& status);

// Reads a whole file, or standard input for "-". With max_bytes > 0, an input longer than
// that is kResourceLimit (checked before reading a regular file, while reading a pipe).
Status read_whole_input(const std::string& path, std::string& bytes, uint64_t max_bytes = 0);

// "1000000", "512k", "512M", "2G", "1T" (powers of 1024; an optional trailing "B" or "iB").
bool parse_size(std::string_view text, uint64_t& bytes);

// The format of mesh data by its content, for standard input: "ply" header, an OFF header
// keyword, binary STL by its size or ASCII STL by "solid", OBJ by its first keyword, GLB by
// its magic "glTF", a .gltf by its opening '{'.
MeshFormat sniff_mesh_format(std::string_view bytes);

// text as a JSON string literal, quotes included; bytes that are not UTF-8 become U+FFFD.
std::string json_string(std::string_view text);

// Seconds since a start point, for the summary lines.
double seconds_since(std::chrono::steady_clock::time_point start);

// "1.23 MB", "456 kB", "789 B".
std::string human_bytes(std::size_t bytes);

// Makes every heap block of 256 KiB or more a mapping of its own, given back to the system
// when it is freed (glibc's fixed mmap threshold; nothing elsewhere). By default glibc
// raises the threshold to the size of each such block freed, up to 32 MiB, and the blocks
// below it then come from the heap, whose freed memory the process keeps: pmenc's stages
// (the collapse loop, the assembly, the layering, the writer) each free tens of MiB of
// arrays before the next takes its own, and its peak held both; so did pmdec's (reading,
// replaying the splits, writing the mesh): full detail of the 950K-face textured mesh as
// OBJ, peak 372 -> 269 MB, as PLY 327 -> 233 MB, in the same time. Called once, first
// thing in main(): a process-wide policy, which the library leaves to its caller.
void return_large_blocks_when_freed();

}  // namespace pm::cli
