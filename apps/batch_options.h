// The batch options pmenc and pmdec share (inputs, -r, --from-list, -o templates,
// --out-dir, -j, --shard, --skip-existing, --json, --dry-run, -q) and the plan they make:
// one Task per input of this shard, with its output names.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <utility>
#include <vector>

#include "batch.h"

namespace pm::cli {

struct BatchCommandLine {
  std::vector<std::string> inputs;
  std::vector<std::string> lists;
  std::string output;
  std::string out_dir;
  std::string shard_text;
  bool recursive = false;
  bool json = false;
  bool skip_existing = false;
  bool dry_run = false;
  bool quiet = false;
  unsigned jobs = 0;                          // 0: default_jobs()
  const CLI::Option* shard_option = nullptr;  // given, even empty

  // Adds the options to app; the help texts name the tool's own file kinds.
  void add_options(CLI::App& app, const std::string& input_help, const std::string& output_help);

  RunOptions run_options(const char* tool) const;
};

// One set of outputs per input: pmenc has one variant (no extra placeholder), pmdec one per
// level of --lods ({"lod", "25"}).
using OutputVariant = std::vector<std::pair<std::string, std::string>>;

struct PlanSettings {
  std::vector<std::string> extensions;   // what -r picks up
  std::string default_template;          // with --out-dir and no -o ("{dir}/{stem}.pm")
  std::vector<std::string> extra_names;  // placeholders beyond {stem} {ext} {name} {dir}
  std::vector<OutputVariant> variants;   // at least one
  std::string stdin_default_output;      // the output of "-" without -o ("-" or empty)
};

// Gathers the inputs, names their outputs and keeps this shard's. Errors: kInvalidArgument
// (a usage error: its message says what to change), kIoError (a --from-list file).
Status plan_tasks(const BatchCommandLine& command, const PlanSettings& settings,
                  std::vector<Task>& tasks);

// A check for count options (faces, vertices): digits only. CLI11 reads "-3" into an unsigned
// option as 2^64 - 3, so a typo would silently mean "no limit".
const CLI::Validator& whole_number();

}  // namespace pm::cli
