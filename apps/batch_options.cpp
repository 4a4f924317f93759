#include "batch_options.h"

#include <algorithm>

namespace pm::cli {
namespace {

Status usage(const std::string& message) {
  return Status(ErrorCode::kInvalidArgument, message);
}

}  // namespace

const CLI::Validator& whole_number() {
  static const CLI::Validator check(
      [](std::string& text) {
        const bool digits = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
          return c >= '0' && c <= '9';
        });
        return digits ? std::string() : "must be a whole number, 0 or more, not " + text;
      },
      "COUNT");
  return check;
}

void BatchCommandLine::add_options(CLI::App& app, const std::string& input_help,
                                   const std::string& output_help) {
  app.add_option("inputs", inputs, input_help)->type_name("FILE|DIR|-");
  app.add_option("-o,--output", output, output_help)->type_name("FILE|TEMPLATE|-");
  app.add_option("--out-dir", out_dir,
                 "Write the outputs below this directory, mirroring the inputs' paths "
                 "(directories are created)")
      ->type_name("DIR");
  app.add_flag("-r,--recursive", recursive, "Convert the files found in the directories given");
  app.add_option("--from-list", lists,
                 "Read input paths from this file, one per line (- for standard input)")
      ->type_name("FILE");
  app.add_option("-j,--jobs", jobs, "Convert this many files at once (default: the cores)")
      ->type_name("N")
      ->check(CLI::Range(0u, 256u));
  shard_option =
      app.add_option("--shard", shard_text,
                     "Convert only the I-th of N parts of the inputs (1 <= I <= N), chosen by a "
                     "hash of each input's path")
          ->type_name("I/N");
  app.add_flag("--skip-existing", skip_existing,
               "Skip an input whose outputs all exist (resume an interrupted run)");
  app.add_flag("--json", json, "Print one JSON object per file on standard output (JSON Lines)");
  app.add_flag("-n,--dry-run", dry_run,
               "Print each input and its outputs, tab-separated (or JSON with --json), and "
               "convert nothing");
  app.add_flag("-q,--quiet", quiet, "Print errors only");
}

RunOptions BatchCommandLine::run_options(const char* tool) const {
  RunOptions options;
  options.tool = tool;
  options.jobs = jobs == 0 ? default_jobs() : jobs;
  options.quiet = quiet;
  options.json = json;
  options.progress_bar = !quiet && stderr_wants_progress_bar();
  return options;
}

Status plan_tasks(const BatchCommandLine& command, const PlanSettings& settings,
                  std::vector<Task>& tasks) {
  tasks.clear();
  if (command.inputs.empty() && command.lists.empty())
    return usage("no input: give files, directories with -r, or --from-list FILE");
  const auto stdin_uses = std::count(command.inputs.begin(), command.inputs.end(), "-") +
                          std::count(command.lists.begin(), command.lists.end(), "-");
  const bool stdin_input =
      std::find(command.inputs.begin(), command.inputs.end(), "-") != command.inputs.end();
  if (stdin_uses > 1) return usage("standard input (-) can be read only once");
  if (stdin_input && (command.inputs.size() > 1 || !command.lists.empty()))
    return usage("standard input (-) must be the only input");
  if (command.output == "-" && command.json)
    return usage("--json and -o - would both write to standard output");

  Shard shard;
  const bool shard_given = command.shard_option && command.shard_option->count() > 0;
  if (shard_given && !Shard::parse(command.shard_text, shard))
    return usage("--shard " + command.shard_text + ": expected I/N with 1 <= I <= N");

  OutputTemplate name_template;
  const bool output_is_template = !command.output.empty() && command.output != "-";
  if (Status s =
          OutputTemplate::parse(output_is_template ? command.output : settings.default_template,
                                settings.extra_names, name_template);
      !s)
    return s;

  std::vector<Input> inputs;
  InputOptions input_options{command.inputs, command.lists, command.recursive, settings.extensions};
  if (Status s = gather_inputs(input_options, inputs); !s) return s;

  if (command.output == "-" && inputs.size() != 1)
    return usage("-o - takes a single input (" + std::to_string(inputs.size()) + " given)");
  if (output_is_template && !name_template.has_placeholders() && inputs.size() > 1)
    return usage("-o " + command.output + " names one file, but there are " +
                 std::to_string(inputs.size()) +
                 " inputs: use --out-dir DIR, or a template such as -o '{dir}/{stem}" +
                 settings.default_template.substr(settings.default_template.rfind('}') + 1) + "'");

  for (Input& input : inputs) {
    Task task;
    for (const OutputVariant& variant : settings.variants) {
      std::string output;
      if (command.output == "-") {
        output = "-";
      } else if (input.path == "-") {
        if (name_template.has_placeholders() && output_is_template)
          return usage("standard input has no file name for the placeholders of -o " +
                       command.output + ": give a file name or -o -");
        if (!output_is_template && !command.out_dir.empty())
          return usage("standard input has no name to write below --out-dir: give -o FILE");
        output = output_is_template ? command.output : settings.stdin_default_output;
        if (output.empty()) return usage("standard input needs -o FILE or -o -");
        if (output != "-") output = place_output(command.out_dir, output);
      } else {
        output = place_output(command.out_dir, name_template.expand(input.path, variant));
      }
      task.outputs.push_back(output);
    }
    task.input = std::move(input);
    tasks.push_back(std::move(task));
  }
  // On the whole list, before sharding, so that every shard reaches the same verdict.
  mark_output_conflicts(tasks);
  if (shard.count > 1) {
    tasks.erase(std::remove_if(tasks.begin(), tasks.end(),
                               [&shard](const Task& t) { return !shard.contains(t.input.path); }),
                tasks.end());
  }
  return Status::ok();
}

}  // namespace pm::cli
