// Batch conversion for pmenc and pmdec: which files (arguments, -r, --from-list), under which
// names (--out-dir, -o templates), which part of them (--shard), and converting them on
// N threads (-j) with a progress bar or one line per file on stderr and JSON Lines on stdout.
// The conversion itself is the tool's: a Job called once per file.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "pm/status.h"

namespace pm::cli {

// ---------------------------------------------------------------------------------------
// Inputs
// ---------------------------------------------------------------------------------------

struct InputOptions {
  std::vector<std::string> arguments;   // files, directories (with recursive), or "-"
  std::vector<std::string> list_files;  // --from-list: one path per line; "-" is stdin
  bool recursive = false;               // -r: directories are searched
  std::vector<std::string> extensions;  // what -r picks up: lower case, no dot ("obj")
};

struct Input {
  std::string path;   // as given, or as found under a directory given
  uint64_t size = 0;  // bytes (0 when unknown), for scheduling and the ETA
  Status problem;     // a failure known before converting (a directory without -r, ...)
};

// Arguments and list lines in order; a directory's files sorted by name; a path met again
// (normalized) is dropped. A list file that cannot be read is an error (kIoError); an
// unreadable argument is an Input that fails.
Status gather_inputs(const InputOptions& options, std::vector<Input>& inputs);

// ---------------------------------------------------------------------------------------
// Output names
// ---------------------------------------------------------------------------------------

// An -o value: a path with placeholders. {stem} is the input's file name without its
// extension, {ext} the extension without the dot, {name} the whole file name, {dir} the
// directory as given ("." for none); tools add their own ({lod} in pmdec).
class OutputTemplate {
 public:
  // kInvalidArgument for an unknown placeholder or an unmatched brace.
  static Status parse(const std::string& text, const std::vector<std::string>& extra_names,
                      OutputTemplate& result);
  bool has_placeholder(std::string_view name) const;
  bool has_placeholders() const;
  std::string expand(const std::string& input,
                     const std::vector<std::pair<std::string, std::string>>& extra = {}) const;

 private:
  struct Piece {
    bool placeholder = false;
    std::string text;  // literal text or placeholder name
  };
  std::vector<Piece> pieces_;
};

// Where an expanded name lands. Without out_dir: the name, normalized ("./a//b" is "a/b").
// With out_dir: out_dir/name with the name made relative (a leading "/" and leading ".."
// dropped), so that the input tree is mirrored below out_dir and never written outside it.
std::string place_output(const std::string& out_dir, const std::string& expanded);

// ---------------------------------------------------------------------------------------
// Shards
// ---------------------------------------------------------------------------------------

// --shard I/N, 1 <= I <= N: the I-th of N parts of the inputs, by a hash of each input's
// normalized path, so that the parts are disjoint, cover the inputs, and do not depend on
// the order inputs were listed in or on which other inputs exist.
struct Shard {
  uint32_t index = 1, count = 1;
  static bool parse(std::string_view text, Shard& shard);
  bool contains(const std::string& input_path) const;
};

// ---------------------------------------------------------------------------------------
// Running
// ---------------------------------------------------------------------------------------

struct Task {
  Input input;
  std::vector<std::string> outputs;  // "-" for standard output
  // Set when an output is also an earlier task's: this task fails (kInvalidArgument) once
  // its input is read, so that an invalid input still reports its own problem.
  Status conflict;
};

// Marks each task that would write an output of an earlier task (in list order, so that all
// shards agree) with a conflict naming that task.
void mark_output_conflicts(std::vector<Task>& tasks);

// Whether every output of the task exists (--skip-existing: outputs are renamed into place
// complete, so one that exists is whole).
bool all_outputs_exist(const Task& task);

// --dry-run: one line per task that would run (with skip_existing, not those whose outputs
// exist) on stdout, "input<TAB>output[<TAB>output...]", or with json
// {"input":...,"output":...} (outputs_as_array: "outputs":[...]).
void print_plan(const std::vector<Task>& tasks, bool json, bool outputs_as_array,
                bool skip_existing);

// What a Job says about one file.
struct Outcome {
  Status status;            // the failure, if any
  int exit_code = 0;        // the file's own exit code
  std::string error_file;   // what the error line names (default: the input)
  bool skipped = false;     // --skip-existing found every output
  std::string summary;      // the per-file line on stderr, without "tool: " (empty: none)
  std::string json;         // the tool's JSON members, "\"key\":value,..." (no braces)
  std::string stdout_text;  // printed on stdout once the file is done
  uint64_t faces = 0;       // work done, for the faces-per-second figure

  // A copy of this outcome (its JSON members kept) that failed with `why`; its exit code
  // follows from why's code when the run finishes it (exit_code_for).
  Outcome failed_with(const Status& why) const {
    Outcome failed = *this;
    failed.status = why;
    return failed;
  }
};

// Handed to a Job: what it is doing, for the progress bar, and notes for stderr.
class JobProgress {
 public:
  virtual ~JobProgress() = default;
  // The size of the work in faces, once known (the input's, or the output's).
  virtual void set_faces(uint64_t faces) = 0;
  // Fraction of this file's work done, in [0, 1]; called from the Job's thread.
  virtual void set_fraction(double fraction) = 0;
  // A line for stderr ("tool: " is prepended), dropped with -q. Repairs, requests clamped.
  virtual void note(const std::string& line) = 0;
};

using Job = std::function<Outcome(const Task&, JobProgress&)>;

struct RunOptions {
  const char* tool = "";
  unsigned jobs = 1;          // threads; at most one per task
  bool quiet = false;         // -q: errors only
  bool json = false;          // one JSON object per file on stdout
  bool progress_bar = false;  // stderr is a terminal: a bar instead of one line per file
};

// Converts every task, largest input first, on options.jobs threads; a failure does not
// stop the others. Returns the single task's exit code, or for several tasks kExitOk when
// all succeeded (or were skipped) and kExitSomeFailed otherwise.
int run_batch(const std::vector<Task>& tasks, const RunOptions& options, const Job& job);

// The default number of threads: the cores this process may use.
unsigned default_jobs();

// Whether a progress bar suits stderr: a terminal that is not "dumb".
bool stderr_wants_progress_bar();

}  // namespace pm::cli
