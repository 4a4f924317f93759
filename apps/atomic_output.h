// Outputs that are whole or absent: each file is written to a temporary beside it and renamed
// into place, and a caught signal removes the temporaries being written before the process
// exits (SIGKILL's leftovers are removed by the next run). Shared by pmenc and pmdec.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "pm/status.h"

namespace pm::cli {

// Writes bytes to path through a temporary file in the same directory (path + ".tmp." and
// six random characters), renamed into place once complete, so a failure or a signal never
// leaves a partial file. Safe to call from several threads at once. "-" writes to standard
// output; binary data is refused when standard output is a terminal.
Status write_output_atomically(const std::string& path, std::string_view bytes, bool binary);

// One output written in pieces, whole or absent as write_output_atomically()'s (which is
// open(), write(), commit()): the pieces go to the temporary as they come, so that an output
// need not be whole in memory first (pmdec's meshes: write_mesh_to_sink()). Destroyed without
// commit(), or after a failed write(), it removes its temporary. For "-", the pieces go
// straight to standard output, which cannot be taken back.
class AtomicOutput {
 public:
  AtomicOutput() = default;
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;
  ~AtomicOutput();

  // Creates the temporary beside path (published for the signal handler before any byte is
  // written). binary: refused when path is "-" and standard output is a terminal.
  Status open(const std::string& path, bool binary);
  Status write(std::string_view piece);
  // Flushes the temporary to the disk and renames it into place.
  Status commit();

 private:
  void discard();

  std::string path_, temp_;
  int fd_ = -1;
  int slot_ = -1;
  bool to_stdout_ = false;
};

// Whether file_name is a temporary of write_output_atomically for output_name (both plain
// names in the same directory).
bool is_temporary_for(std::string_view file_name, std::string_view output_name);

// Removes the temporaries that an earlier run killed with SIGKILL left next to these outputs
// (signals that can be caught remove their own). Only these outputs' temporaries: another
// process may be writing other files of the same directory.
void remove_stale_temporaries(const std::vector<std::string>& outputs);

// Creates the directories above path (mkdir -p of its parent).
Status make_parent_directories(const std::string& path);

// On SIGINT/SIGTERM/SIGHUP/SIGPIPE, removes the temporary files being written and exits
// 128 + the signal's number; reads the umask once. Call before starting any thread (the three
// waited-for signals are blocked in the calling thread, and threads inherit that).
void install_cleanup_handlers();

}  // namespace pm::cli
