// Planning a batch (batch.h): the inputs (arguments, -r, --from-list), their output names
// (-o templates, --out-dir), --shard, and the plan itself (conflicting outputs, --dry-run).
#include "batch.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include "cli_common.h"

namespace pm::cli {
namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------
// Inputs

namespace {

std::string lower_case(std::string_view text) {
  std::string lower(text);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower;
}

bool has_wanted_extension(const std::string& file_name,
                          const std::vector<std::string>& extensions) {
  const std::size_t dot = file_name.rfind('.');
  if (dot == std::string::npos || dot == 0) return false;
  const std::string extension = lower_case(std::string_view(file_name).substr(dot + 1));
  return std::find(extensions.begin(), extensions.end(), extension) != extensions.end();
}

std::string join(const std::string& directory, const std::string& name) {
  return !directory.empty() && directory.back() == '/' ? directory + name : directory + "/" + name;
}

// Files with a wanted extension below directory, depth first, each directory's entries
// sorted by name. Symbolic links to files are followed, links to directories are not (as
// find(1) does), so that a link cannot make the walk loop.
void walk(const std::string& directory, const std::vector<std::string>& extensions,
          std::vector<Input>& inputs) {
  std::error_code error;
  fs::directory_iterator it(directory, error);
  if (error) {
    inputs.push_back(
        {directory, 0, Status(ErrorCode::kIoError, "cannot read directory: " + error.message())});
    return;
  }
  std::vector<std::string> names;
  for (; it != fs::directory_iterator(); it.increment(error)) {
    if (error) break;
    names.push_back(it->path().filename().string());
  }
  if (error) {
    inputs.push_back(
        {directory, 0, Status(ErrorCode::kIoError, "cannot read directory: " + error.message())});
    return;
  }
  std::sort(names.begin(), names.end());
  for (const std::string& name : names) {
    const std::string path = join(directory, name);
    struct stat link_info {};
    if (lstat(path.c_str(), &link_info) != 0) continue;  // gone since the listing
    if (S_ISDIR(link_info.st_mode)) {
      walk(path, extensions, inputs);
      continue;
    }
    struct stat info {};
    if (stat(path.c_str(), &info) != 0 || !S_ISREG(info.st_mode)) continue;
    if (has_wanted_extension(name, extensions))
      inputs.push_back({path, static_cast<uint64_t>(info.st_size), Status::ok()});
  }
}

void add_named(const std::string& path, const InputOptions& options, std::vector<Input>& inputs) {
  if (path == "-") {
    inputs.push_back({path, 0, Status::ok()});
    return;
  }
  struct stat info {};
  if (stat(path.c_str(), &info) != 0) {
    inputs.push_back({path, 0, Status::ok()});  // the conversion reports why it cannot open it
    return;
  }
  if (S_ISDIR(info.st_mode)) {
    if (options.recursive) {
      walk(path, options.extensions, inputs);
    } else {
      inputs.push_back(
          {path, 0,
           Status(ErrorCode::kIoError, "is a directory (use -r to convert the files in it)")});
    }
    return;
  }
  inputs.push_back({path, static_cast<uint64_t>(info.st_size), Status::ok()});
}

}  // namespace

Status gather_inputs(const InputOptions& options, std::vector<Input>& inputs) {
  inputs.clear();
  // A file named twice (in a list and by a directory, say) is converted once.
  std::set<std::string> seen;
  const auto already_seen = [&seen](const Input& input) {
    return !seen.insert(fs::path(input.path).lexically_normal().string()).second;
  };
  for (const std::string& argument : options.arguments) add_named(argument, options, inputs);
  for (const std::string& list_file : options.list_files) {
    std::string text;
    if (Status s = read_whole_input(list_file, text); !s)
      return Status(s.code(), error_line("--from-list", list_file, s.message()));
    std::size_t begin = 0;
    while (begin < text.size()) {
      std::size_t end = text.find('\n', begin);
      if (end == std::string::npos) end = text.size();
      std::string line = text.substr(begin, end - begin);
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (!line.empty()) add_named(line, options, inputs);
      begin = end + 1;
    }
  }
  inputs.erase(std::remove_if(inputs.begin(), inputs.end(), already_seen), inputs.end());
  return Status::ok();
}

// ---------------------------------------------------------------------------------------
// Output names

Status OutputTemplate::parse(const std::string& text, const std::vector<std::string>& extra_names,
                             OutputTemplate& result) {
  std::vector<std::string> known = {"stem", "ext", "name", "dir"};
  known.insert(known.end(), extra_names.begin(), extra_names.end());
  auto known_list = [&known] {
    std::string list;
    for (const std::string& name : known) list += (list.empty() ? "{" : ", {") + name + "}";
    return list;
  };
  result.pieces_.clear();
  std::string literal;
  for (std::size_t i = 0; i < text.size(); ++i) {
    // "{{" and "}}" are literal braces.
    if ((text[i] == '{' || text[i] == '}') && i + 1 < text.size() && text[i + 1] == text[i]) {
      literal += text[i++];
      continue;
    }
    if (text[i] == '}')
      return Status(ErrorCode::kInvalidArgument,
                    "-o " + text + ": unmatched } (write }} for a brace)");
    if (text[i] != '{') {
      literal += text[i];
      continue;
    }
    const std::size_t close = text.find('}', i);
    if (close == std::string::npos)
      return Status(ErrorCode::kInvalidArgument,
                    "-o " + text + ": unmatched { (write {{ for a brace)");
    const std::string name = text.substr(i + 1, close - i - 1);
    if (std::find(known.begin(), known.end(), name) == known.end())
      return Status(ErrorCode::kInvalidArgument, "-o " + text + ": unknown placeholder {" + name +
                                                     "} (known: " + known_list() + ")");
    if (!literal.empty()) result.pieces_.push_back({false, literal});
    literal.clear();
    result.pieces_.push_back({true, name});
    i = close;
  }
  if (!literal.empty()) result.pieces_.push_back({false, literal});
  return Status::ok();
}

bool OutputTemplate::has_placeholder(std::string_view name) const {
  return std::any_of(pieces_.begin(), pieces_.end(),
                     [name](const Piece& p) { return p.placeholder && p.text == name; });
}

bool OutputTemplate::has_placeholders() const {
  return std::any_of(pieces_.begin(), pieces_.end(), [](const Piece& p) { return p.placeholder; });
}

std::string OutputTemplate::expand(
    const std::string& input, const std::vector<std::pair<std::string, std::string>>& extra) const {
  const std::size_t slash = input.rfind('/');
  const std::string name = slash == std::string::npos ? input : input.substr(slash + 1);
  const std::string dir = slash == std::string::npos ? "."
                          : slash == 0               ? "/"
                                                     : input.substr(0, slash);
  const std::size_t dot = name.rfind('.');
  const bool has_extension = dot != std::string::npos && dot > 0;
  const std::string stem = has_extension ? name.substr(0, dot) : name;
  const std::string ext = has_extension ? name.substr(dot + 1) : "";
  std::string out;
  for (const Piece& piece : pieces_) {
    if (!piece.placeholder) {
      out += piece.text;
    } else if (piece.text == "stem") {
      out += stem;
    } else if (piece.text == "ext") {
      out += ext;
    } else if (piece.text == "name") {
      out += name;
    } else if (piece.text == "dir") {
      out += dir;
    } else {
      for (const auto& [key, value] : extra)
        if (key == piece.text) out += value;
    }
  }
  return out;
}

std::string place_output(const std::string& out_dir, const std::string& expanded) {
  const fs::path normal = fs::path(expanded).lexically_normal();
  if (out_dir.empty()) return normal.string();
  fs::path relative;
  bool leading = true;
  for (const fs::path& part : normal.relative_path()) {
    if (leading && part == "..") continue;
    leading = false;
    relative /= part;
  }
  return (fs::path(out_dir) / relative).lexically_normal().string();
}

// ---------------------------------------------------------------------------------------
// Shards

bool Shard::parse(std::string_view text, Shard& shard) {
  const std::size_t slash = text.find('/');
  if (slash == std::string_view::npos) return false;
  auto number = [](std::string_view digits, uint32_t& value) {
    if (digits.empty() || digits.size() > 9) return false;
    value = 0;
    for (char c : digits) {
      if (!std::isdigit(static_cast<unsigned char>(c))) return false;
      value = value * 10 + static_cast<uint32_t>(c - '0');
    }
    return true;
  };
  Shard parsed;
  if (!number(text.substr(0, slash), parsed.index) || !number(text.substr(slash + 1), parsed.count))
    return false;
  if (parsed.count < 1 || parsed.index < 1 || parsed.index > parsed.count) return false;
  shard = parsed;
  return true;
}

bool Shard::contains(const std::string& input_path) const {
  // FNV-1a over the normalized path ("./a//b.obj" and "a/b.obj" are one file), then the
  // splitmix64 finalizer, whose low bits are well mixed for the modulo.
  const std::string key = fs::path(input_path).lexically_normal().generic_string();
  uint64_t hash = 0xcbf29ce484222325ull;
  for (unsigned char c : key) hash = (hash ^ c) * 0x100000001b3ull;
  hash ^= hash >> 30;
  hash *= 0xbf58476d1ce4e5b9ull;
  hash ^= hash >> 27;
  hash *= 0x94d049bb133111ebull;
  hash ^= hash >> 31;
  return hash % count == index - 1;
}

// ---------------------------------------------------------------------------------------
// Running

void mark_output_conflicts(std::vector<Task>& tasks) {
  const auto without_extension = [](const std::string& path) {
    const std::size_t dot = path.rfind('.');
    return dot == std::string::npos || path.find('/', dot) != std::string::npos
               ? path
               : path.substr(0, dot);
  };
  std::map<std::string, std::size_t> writer_of;  // output -> index of the first task
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    Task& task = tasks[i];
    for (const std::string& output : task.outputs) {
      if (output == "-") continue;
      const auto [it, inserted] = writer_of.emplace(output, i);
      if (inserted || it->second == i || !task.conflict) continue;
      const std::string& other = tasks[it->second].input.path;
      const bool same_stem = without_extension(other) == without_extension(task.input.path);
      task.conflict = Status(ErrorCode::kInvalidArgument,
                             output + " is also the output of " + other +
                                 ", given earlier (name the outputs apart, e.g. with " +
                                 (same_stem ? "{ext}" : "{dir}") + " in -o)");
    }
  }
}

bool all_outputs_exist(const Task& task) {
  if (task.outputs.empty()) return false;
  for (const std::string& output : task.outputs) {
    struct stat info {};
    if (output == "-" || stat(output.c_str(), &info) != 0) return false;
  }
  return true;
}

void print_plan(const std::vector<Task>& tasks, bool json, bool outputs_as_array,
                bool skip_existing) {
  for (const Task& task : tasks) {
    if (skip_existing && all_outputs_exist(task)) continue;
    std::string line;
    if (json) {
      line = "{\"input\":" + json_string(task.input.path);
      if (outputs_as_array) {
        line += ",\"outputs\":[";
        for (std::size_t i = 0; i < task.outputs.size(); ++i)
          line += (i ? "," : "") + json_string(task.outputs[i]);
        line += "]";
      } else {
        line += ",\"output\":" + (task.outputs.empty() ? "null" : json_string(task.outputs[0]));
      }
      line += "}";
    } else {
      line = task.input.path;
      for (const std::string& output : task.outputs) line += "\t" + output;
    }
    line += "\n";
    std::fwrite(line.data(), 1, line.size(), stdout);
  }
  std::fflush(stdout);
}

}  // namespace pm::cli
