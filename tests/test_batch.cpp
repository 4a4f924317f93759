// pmenc and pmdec on many files, as asset pipelines and schedulers run them: inputs from
// arguments, directories and lists; output names; -j; JSON Lines; failures that do not stop
// the batch; resuming after SIGKILL; shards; pipes; the progress bar on a terminal.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <random>
#include <set>
#include <thread>

#include "pm/lod.h"
#include "pm/mesh_io.h"
#include "pm/pm_codec.h"
#include "test_util.h"

extern char** environ;

namespace pm {
namespace {

namespace fs = std::filesystem;
using test::CommandResult;
using test::TempDir;

constexpr const char kAssimpInvalidDir[] = "/usr/share/assimp/models/invalid";

// Runs a tool with the working directory `dir`, so that inputs can be named relatively, as
// users do (sh's exec keeps the process id: a kill reaches the tool itself).
std::vector<std::string> in_dir(const std::string& dir, const char* tool,
                                const std::vector<std::string>& args) {
  std::vector<std::string> argv = {"/bin/sh", "-c", "cd \"$0\" && exec \"$@\"", dir, tool};
  argv.insert(argv.end(), args.begin(), args.end());
  return argv;
}
CommandResult pmenc_in(const std::string& dir, const std::vector<std::string>& args,
                       const std::string& stdin_data = "") {
  return test::run_command(in_dir(dir, PMENC_PATH, args), stdin_data);
}
CommandResult pmdec_in(const std::string& dir, const std::vector<std::string>& args,
                       const std::string& stdin_data = "") {
  return test::run_command(in_dir(dir, PMDEC_PATH, args), stdin_data);
}

void copy_into(const std::string& source, const std::string& destination) {
  fs::create_directories(fs::path(destination).parent_path());
  fs::copy_file(source, destination, fs::copy_options::overwrite_existing);
}

// Every regular file below root, by path relative to root, with its bytes.
std::map<std::string, std::string> tree(const std::string& root) {
  std::map<std::string, std::string> files;
  if (!fs::exists(root)) return files;
  for (const auto& entry : fs::recursive_directory_iterator(root))
    if (entry.is_regular_file())
      files[fs::relative(entry.path(), root).string()] = test::read_file(entry.path().string());
  return files;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t begin = 0;
  while (begin < text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    lines.push_back(text.substr(begin, end - begin));
    begin = end + 1;
  }
  return lines;
}

bool has_line(const std::string& text, const std::string& line) {
  const std::vector<std::string> all = lines_of(text);
  return std::find(all.begin(), all.end(), line) != all.end();
}

bool has_line_starting(const std::string& text, const std::string& prefix) {
  for (const std::string& line : lines_of(text))
    if (line.rfind(prefix, 0) == 0) return true;
  return false;
}

// ---------------------------------------------------------------------------------------
// A small JSON reader, strict enough to reject what is not JSON: the tools' JSON Lines are
// read with it, so a malformed line fails the test.

struct Json {
  enum class Kind { kNull, kBool, kNumber, kString, kArray, kObject } kind = Kind::kNull;
  std::string text;  // string value, or the number / literal as written
  std::vector<Json> items;
  std::map<std::string, Json> members;

  const Json& operator[](const std::string& key) const {
    static const Json missing;
    const auto it = members.find(key);
    return it == members.end() ? missing : it->second;
  }
  bool has(const std::string& key) const { return members.count(key) > 0; }
  bool is_null() const { return kind == Kind::kNull; }
  long long integer() const { return kind == Kind::kNumber ? std::stoll(text) : -1; }
};

class JsonParser {
 public:
  explicit JsonParser(const std::string& text) : text_(text) {}
  bool parse(Json& value) {
    if (!parse_value(value)) return false;
    skip_blanks();
    return at_ == text_.size();
  }

 private:
  void skip_blanks() {
    while (at_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[at_]))) ++at_;
  }
  bool literal(const char* word) {
    const std::size_t n = std::strlen(word);
    if (text_.compare(at_, n, word) != 0) return false;
    at_ += n;
    return true;
  }
  bool parse_string(std::string& out) {
    if (at_ >= text_.size() || text_[at_] != '"') return false;
    ++at_;
    while (at_ < text_.size() && text_[at_] != '"') {
      const char c = text_[at_++];
      if (static_cast<unsigned char>(c) < 0x20) return false;
      if (c != '\\') {
        out += c;
        continue;
      }
      if (at_ >= text_.size()) return false;
      const char e = text_[at_++];
      const std::string simple = "\"\\/bfnrt";
      const std::string meaning = "\"\\/\b\f\n\r\t";
      if (const std::size_t k = simple.find(e); k != std::string::npos) {
        out += meaning[k];
      } else if (e == 'u' && at_ + 4 <= text_.size()) {
        const unsigned code = std::stoul(text_.substr(at_, 4), nullptr, 16);
        at_ += 4;
        if (code >= 0x80) return false;  // the tools escape control characters only
        out += static_cast<char>(code);
      } else {
        return false;
      }
    }
    if (at_ >= text_.size()) return false;
    ++at_;
    return true;
  }
  bool parse_value(Json& value) {
    skip_blanks();
    if (at_ >= text_.size()) return false;
    const char c = text_[at_];
    if (c == '{') {
      value.kind = Json::Kind::kObject;
      ++at_;
      skip_blanks();
      if (at_ < text_.size() && text_[at_] == '}') return ++at_, true;
      for (;;) {
        skip_blanks();
        std::string key;
        if (!parse_string(key)) return false;
        skip_blanks();
        if (at_ >= text_.size() || text_[at_++] != ':') return false;
        Json member;
        if (!parse_value(member)) return false;
        if (!value.members.emplace(key, member).second) return false;  // duplicate key
        skip_blanks();
        if (at_ < text_.size() && text_[at_] == ',') {
          ++at_;
          continue;
        }
        return at_ < text_.size() && text_[at_++] == '}';
      }
    }
    if (c == '[') {
      value.kind = Json::Kind::kArray;
      ++at_;
      skip_blanks();
      if (at_ < text_.size() && text_[at_] == ']') return ++at_, true;
      for (;;) {
        Json item;
        if (!parse_value(item)) return false;
        value.items.push_back(item);
        skip_blanks();
        if (at_ < text_.size() && text_[at_] == ',') {
          ++at_;
          continue;
        }
        return at_ < text_.size() && text_[at_++] == ']';
      }
    }
    if (c == '"') {
      value.kind = Json::Kind::kString;
      return parse_string(value.text);
    }
    if (literal("null")) return value.kind = Json::Kind::kNull, true;
    if (literal("true") || literal("false")) return value.kind = Json::Kind::kBool, true;
    const std::size_t start = at_;
    while (at_ < text_.size() && text_[at_] != '\0' && std::strchr("+-0123456789.eE", text_[at_]))
      ++at_;
    if (at_ == start) return false;
    value.kind = Json::Kind::kNumber;
    value.text = text_.substr(start, at_ - start);
    char* end = nullptr;
    std::strtod(value.text.c_str(), &end);
    return *end == '\0';
  }

  const std::string& text_;
  std::size_t at_ = 0;
};

// One object per line, each keyed by its "input".
std::map<std::string, Json> json_lines_by_input(const std::string& out) {
  std::map<std::string, Json> by_input;
  for (const std::string& line : lines_of(out)) {
    Json value;
    EXPECT_TRUE(JsonParser(line).parse(value)) << "not JSON: " << line;
    EXPECT_EQ(value.kind, Json::Kind::kObject) << line;
    const std::string input = value["input"].text;
    EXPECT_TRUE(by_input.emplace(input, value).second) << "input reported twice: " << input;
  }
  return by_input;
}

// ---------------------------------------------------------------------------------------
// Corpora

struct Corpus {
  std::vector<std::string> valid;    // relative to the test directory
  std::vector<std::string> invalid;  // relative too; given through --from-list
};

// 45 valid meshes in nested folders below `corpus/` (copies of the samples, format
// variants, and the smaller shared meshes when ../shared/meshes is there), and the invalid
// models of Debian's assimp-testmodels below `invalid/`.
Corpus make_corpus(const TempDir& dir) {
  Corpus corpus;
  auto add = [&](const std::string& source, const std::string& relative) {
    copy_into(source, dir.file(relative));
    corpus.valid.push_back(relative);
  };
  // Format variants of a small sample: its full detail written as PLY, OFF and STL.
  CommandResult r = test::run_command(
      {PMENC_PATH, test::sample_mesh_path("nonmanifold.obj"), "-o", dir.file("variant.pm"), "-q"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  for (const char* ext : {"ply", "off", "stl"}) {
    r = test::run_command(
        {PMDEC_PATH, dir.file("variant.pm"), "-o", dir.file(std::string("variant.") + ext), "-q"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    for (int i = 0; i < 3; ++i)
      add(dir.file(std::string("variant.") + ext),
          "corpus/formats/" + std::string(ext) + "/" + std::to_string(i) + "/nonmanifold." + ext);
  }
  const bool shared = test::shared_meshes_available();
  if (!shared) test::warn_no_shared_meshes();
  for (int i = 0; i < 2; ++i) {
    const std::string folder = "corpus/models/set" + std::to_string(i) + "/";
    add(test::sample_mesh_path("sphere.obj"), folder + "sphere.obj");
    add(test::sample_mesh_path("terrain_holes.obj"), folder + "terrain/terrain_holes.obj");
    add(test::sample_mesh_path("block_features.obj"), folder + "block_features.obj");
    add(test::sample_mesh_path("block_features.obj"), folder + "deeper/still/block.OBJ");
    add(shared ? test::shared_mesh_path("cow.obj") : test::sample_mesh_path("block_features.obj"),
        folder + "cow.obj");
    add(shared ? test::shared_mesh_path("spot.obj") : test::sample_mesh_path("sphere.obj"),
        folder + "spot.obj");
  }
  for (int i = 0; static_cast<int>(corpus.valid.size()) < 45; ++i) {
    const std::string folder = "corpus/small/" + std::to_string(i % 4) + "/" + std::to_string(i);
    add(test::sample_mesh_path(i % 2 ? "polygons.obj" : "nonmanifold.obj"),
        folder + (i % 2 ? "/polygons.obj" : "/nonmanifold.obj"));
  }
  if (fs::is_directory(kAssimpInvalidDir)) {
    for (const auto& entry : fs::directory_iterator(kAssimpInvalidDir)) {
      const std::string relative = "invalid/assimp/" + entry.path().filename().string();
      copy_into(entry.path().string(), dir.file(relative));
      corpus.invalid.push_back(relative);
    }
  } else {
    std::cerr << kAssimpInvalidDir << " not found (Debian package assimp-testmodels): "
              << "the corpus has no invalid models\n";
  }
  std::sort(corpus.invalid.begin(), corpus.invalid.end());
  return corpus;
}

std::string pm_name_for(const std::string& input) {
  return "out/" + input.substr(0, input.rfind('.')) + ".pm";
}

Mesh read_or_fail(const std::string& path) {
  Mesh mesh;
  const Status s = read_mesh(path, mesh);
  EXPECT_TRUE(s.is_ok()) << path << ": " << s.message();
  return mesh;
}

// The full detail of a .pm file, decoded in-process.
Mesh decode_full_detail(const std::string& path) {
  ProgressiveMesh progressive;
  const Status s = read_pm(test::read_file(path), progressive);
  EXPECT_TRUE(s.is_ok()) << path << ": " << s.message();
  return extract_level(progressive, progressive.splits.size());
}

// ---------------------------------------------------------------------------------------
// The acceptance corpus

TEST(Batch, CorpusConvertsEveryValidFileReportsEveryInvalidOneAndResumes) {
  TempDir dir;
  const Corpus corpus = make_corpus(dir);
  if (corpus.invalid.empty()) std::cerr << "warning: running the corpus without invalid models\n";
  std::string list;
  for (const std::string& path : corpus.invalid) list += path + "\n";
  test::write_file(dir.file("invalid.txt"), list);
  const std::vector<std::string> args = {"-r",  "corpus", "--from-list", "invalid.txt", "--out-dir",
                                         "out", "-j",     "2",           "--json"};

  const CommandResult first = pmenc_in(dir.path(), args);
  EXPECT_EQ(first.exit_code, corpus.invalid.empty() ? 0 : 8) << first.err;
  std::map<std::string, Json> results = json_lines_by_input(first.out);
  EXPECT_EQ(results.size(), corpus.valid.size() + corpus.invalid.size());
  std::set<std::string> expected_outputs;
  for (const std::string& input : corpus.valid) {
    SCOPED_TRACE(input);
    const Json& r = results[input];
    EXPECT_EQ(r["status"].text, "ok");
    EXPECT_TRUE(r["error"].is_null());
    EXPECT_EQ(r["exit_code"].integer(), 0);
    EXPECT_EQ(r["output"].text, pm_name_for(input));
    expected_outputs.insert(pm_name_for(input).substr(4));
    const Mesh original = read_or_fail(dir.file(input));
    EXPECT_EQ(r["input_faces"].integer(), static_cast<long long>(original.face_count()));
    EXPECT_EQ(r["pm_bytes"].integer(),
              static_cast<long long>(fs::file_size(dir.file(pm_name_for(input)))));
    EXPECT_TRUE(test::same_faces(original, decode_full_detail(dir.file(pm_name_for(input)))));
    EXPECT_TRUE(has_line_starting(
        first.err,
        "pmenc: " + input + ": " + std::to_string(original.face_count()) + " faces, base mesh "))
        << "no summary line for it in\n"
        << first.err;
  }
  for (const std::string& input : corpus.invalid) {
    SCOPED_TRACE(input);
    const Json& r = results[input];
    EXPECT_EQ(r["status"].text, "failed");
    EXPECT_EQ(r["error"].kind, Json::Kind::kString);
    EXPECT_FALSE(r["error"].text.empty());
    EXPECT_EQ(r["error_code"].kind, Json::Kind::kString);
    const long long code = r["exit_code"].integer();
    EXPECT_TRUE(code == 3 || code == 4 || code == 6 || code == 7) << code;
    EXPECT_TRUE(r["input_faces"].is_null());
    // The same message on stderr, one line naming the file.
    EXPECT_TRUE(has_line(first.err, "pmenc: " + input + ": " + r["error"].text)) << first.err;
  }
  EXPECT_TRUE(has_line_starting(first.err, "pmenc: " + std::to_string(results.size()) +
                                               " files: " + std::to_string(corpus.valid.size()) +
                                               " converted, 0 skipped, " +
                                               std::to_string(corpus.invalid.size()) + " failed, "))
      << first.err;
  // Exactly one .pm per valid input: none for the invalid ones, no temporary file.
  std::map<std::string, std::string> outputs = tree(dir.file("out"));
  std::set<std::string> names;
  for (const auto& [name, bytes] : outputs) names.insert(name);
  EXPECT_EQ(names, expected_outputs);

  // The rerun converts nothing, reports the invalid files again, and changes no byte.
  const std::vector<std::string> rerun_args = [&] {
    std::vector<std::string> a = args;
    a.push_back("--skip-existing");
    return a;
  }();
  const CommandResult rerun = pmenc_in(dir.path(), rerun_args);
  EXPECT_EQ(rerun.exit_code, corpus.invalid.empty() ? 0 : 8) << rerun.err;
  results = json_lines_by_input(rerun.out);
  EXPECT_EQ(results.size(), corpus.valid.size() + corpus.invalid.size());
  for (const std::string& input : corpus.valid) EXPECT_EQ(results[input]["status"].text, "skipped");
  for (const std::string& input : corpus.invalid)
    EXPECT_EQ(results[input]["status"].text, "failed");
  EXPECT_TRUE(tree(dir.file("out")) == outputs);
}

// ---------------------------------------------------------------------------------------
// Interrupted runs

// Starts argv with stdout and stderr on /dev/null; returns its process id.
pid_t spawn_quietly(const std::vector<std::string>& argv) {
  std::vector<char*> args;
  for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    const int null = open("/dev/null", O_RDWR);
    dup2(null, 0);
    dup2(null, 1);
    dup2(null, 2);
    execv(args[0], args.data());
    _exit(127);
  }
  return pid;
}

std::vector<std::string> temporaries_below(const std::string& root) {
  std::vector<std::string> found;
  for (const auto& [name, bytes] : tree(root))
    if (name.find(".pm.tmp.") != std::string::npos) found.push_back(name);
  return found;
}

TEST(Batch, RerunAfterSigkillGivesTheSameBytesAsAnUninterruptedRun) {
  TempDir dir;
  for (int i = 0; i < 3; ++i) {
    const std::string folder = "in/" + std::to_string(i) + "/";
    copy_into(test::sample_mesh_path("sphere.obj"), dir.file(folder + "sphere.obj"));
    copy_into(test::sample_mesh_path("terrain_holes.obj"), dir.file(folder + "sub/terrain.obj"));
    copy_into(test::sample_mesh_path("block_features.obj"), dir.file(folder + "block.obj"));
  }
  const auto start = std::chrono::steady_clock::now();
  CommandResult r = pmenc_in(dir.path(), {"-r", "in", "--out-dir", "reference", "-j", "2", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::map<std::string, std::string> reference = tree(dir.file("reference"));
  ASSERT_EQ(reference.size(), 9u);

  std::random_device seed;
  std::mt19937 random(seed());
  for (int round = 0; round < 2; ++round) {
    // Anywhere in the run: before the first output, between outputs, during a write.
    const int delay_ms =
        std::uniform_int_distribution<int>(0, static_cast<int>(seconds * 900))(random);
    SCOPED_TRACE("round " + std::to_string(round) + ": SIGKILL after " + std::to_string(delay_ms) +
                 " ms");
    const pid_t pid = spawn_quietly(
        in_dir(dir.path(), PMENC_PATH,
               {"-r", "in", "--out-dir", "killed", "-j", "2", "-q", "--skip-existing"}));
    ASSERT_GT(pid, 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    // What the killed run left is complete: every .pm present is the reference's.
    for (const auto& [name, bytes] : tree(dir.file("killed"))) {
      if (name.find(".pm.tmp.") != std::string::npos) continue;
      ASSERT_TRUE(reference.count(name)) << name;
      EXPECT_TRUE(bytes == reference.at(name)) << name << " is partial";
    }
  }
  // What is left to do, as --dry-run lists it, is what the resumed run converts.
  const CommandResult left =
      pmenc_in(dir.path(), {"-r", "in", "--out-dir", "killed", "--skip-existing", "--dry-run"});
  ASSERT_EQ(left.exit_code, 0) << left.err;
  std::size_t missing = 0;
  for (const auto& [name, bytes] : reference)
    missing += test::file_exists(dir.file("killed/" + name)) ? 0 : 1;
  EXPECT_EQ(lines_of(left.out).size(), missing) << left.out;
  r = pmenc_in(dir.path(),
               {"-r", "in", "--out-dir", "killed", "-j", "2", "--skip-existing", "--json", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::size_t converted = 0;
  for (const auto& [input, result] : json_lines_by_input(r.out))
    converted += result["status"].text == "ok";
  EXPECT_EQ(converted, missing);
  const std::map<std::string, std::string> resumed = tree(dir.file("killed"));
  EXPECT_EQ(temporaries_below(dir.file("killed")), std::vector<std::string>{});
  ASSERT_EQ(resumed.size(), reference.size());
  for (const auto& [name, bytes] : reference) {
    ASSERT_TRUE(resumed.count(name)) << name;
    EXPECT_TRUE(resumed.at(name) == bytes) << name << " differs";
  }
}

// SIGTERM, SIGINT (Ctrl-C) and SIGHUP are caught: the temporaries being written are removed
// at once, without a rerun, and what was renamed into place is complete.
TEST(Batch, CaughtSignalsLeaveNoTemporaryAndNoPartialFile) {
  TempDir dir;
  for (int i = 0; i < 3; ++i) {
    copy_into(test::sample_mesh_path("sphere.obj"),
              dir.file("in/" + std::to_string(i) + "/sphere.obj"));
    copy_into(test::sample_mesh_path("terrain_holes.obj"),
              dir.file("in/" + std::to_string(i) + "/terrain.obj"));
  }
  CommandResult r = pmenc_in(dir.path(), {"-r", "in", "--out-dir", "reference", "-j", "2", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::map<std::string, std::string> reference = tree(dir.file("reference"));
  std::random_device seed;
  std::mt19937 random(seed());
  int round = 0;
  for (int signal_number : {SIGTERM, SIGINT, SIGHUP}) {
    const std::string out = "out" + std::to_string(round++);
    const int delay_ms = std::uniform_int_distribution<int>(0, 1200)(random);
    SCOPED_TRACE("signal " + std::to_string(signal_number) + " " + std::to_string(delay_ms) +
                 " ms after the output folder appeared");
    const pid_t pid = spawn_quietly(
        in_dir(dir.path(), PMENC_PATH, {"-r", "in", "--out-dir", out, "-j", "2", "-q"}));
    ASSERT_GT(pid, 0);
    // The signal is sent once pmenc writes (it makes the output folder then), not after a fixed
    // time: a loaded or instrumented machine may not have reached main() after 100 ms, and a
    // signal before pmenc installs its handling kills it with nothing to clean up.
    int status = 0;
    bool exited = false;
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (!fs::exists(dir.file(out)) && std::chrono::steady_clock::now() < give_up) {
      if (waitpid(pid, &status, WNOHANG) == pid) {
        exited = true;
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    ASSERT_FALSE(exited) << "pmenc ended before writing anything";
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    kill(pid, signal_number);
    waitpid(pid, &status, 0);
    // Killed by the signal, the handler exits 128 + its number (or the run had finished).
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_TRUE(WEXITSTATUS(status) == 128 + signal_number || WEXITSTATUS(status) == 0)
        << WEXITSTATUS(status);
    EXPECT_EQ(temporaries_below(dir.file(out)), std::vector<std::string>{});
    for (const auto& [name, bytes] : tree(dir.file(out))) {
      ASSERT_TRUE(reference.count(name)) << name;
      EXPECT_TRUE(bytes == reference.at(name)) << name << " is partial";
    }
  }
}

TEST(Batch, RerunRemovesOnlyItsOwnOutputsTemporaries) {
  TempDir dir;
  copy_into(test::sample_mesh_path("polygons.obj"), dir.file("in/a.obj"));
  fs::create_directories(dir.file("out/in"));
  // What kill -9 leaves while writing out/in/a.pm, and files that are not its temporaries.
  for (const char* name :
       {"a.pm.tmp.Ab3xYz", "a.pm.tmp.keep", "other.pm.tmp.Ab3xYz", "a.pm.tmpl.Ab3xYz"})
    test::write_file(dir.file(std::string("out/in/") + name), "partial");
  for (const char* skip : {"--skip-existing", "-q"}) {
    // Both a conversion and a skip clean up (the second run skips a.pm).
    const CommandResult r = pmenc_in(dir.path(), {"in/a.obj", "--out-dir", "out", skip, "-q"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    test::write_file(dir.file("out/in/a.pm.tmp.Q1w2E3"), "partial");
  }
  fs::remove(dir.file("out/in/a.pm.tmp.Q1w2E3"));
  CommandResult r = pmenc_in(dir.path(), {"in/a.obj", "--out-dir", "out", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::set<std::string> names;
  for (const auto& [name, bytes] : tree(dir.file("out/in"))) names.insert(name);
  EXPECT_EQ(names, (std::set<std::string>{"a.pm", "a.pm.tmp.keep", "other.pm.tmp.Ab3xYz",
                                          "a.pm.tmpl.Ab3xYz"}));
}

// ---------------------------------------------------------------------------------------
// Shards and idempotence

std::vector<std::string> planned_inputs(const CommandResult& r) {
  std::vector<std::string> inputs;
  for (const std::string& line : lines_of(r.out)) inputs.push_back(line.substr(0, line.find('\t')));
  return inputs;
}

std::string normalized(const std::string& path) {
  return fs::path(path).lexically_normal().string();
}

TEST(Batch, FourShardsAreDisjointCoverTheListAndIgnoreItsOrder) {
  TempDir dir;
  // Names only: --dry-run plans without reading, so the files need not exist.
  std::vector<std::string> paths;
  for (int i = 0; i < 200; ++i)
    paths.push_back("d" + std::to_string(i % 7) + "/s" + std::to_string(i % 3) + "/m" +
                    std::to_string(i) + ".obj");
  std::string list;
  for (const std::string& p : paths) list += p + "\n";
  // The same files listed in another order and spelled differently.
  std::vector<std::string> shuffled = paths;
  std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(7));
  std::string other_list;
  for (const std::string& p : shuffled)
    other_list += "./" + p.substr(0, p.find('/')) + "//" + p.substr(p.find('/') + 1) + "\r\n";
  test::write_file(dir.file("list.txt"), list);
  test::write_file(dir.file("other.txt"), other_list);

  const CommandResult all =
      pmenc_in(dir.path(), {"--from-list", "list.txt", "--out-dir", "o", "--dry-run"});
  ASSERT_EQ(all.exit_code, 0) << all.err;
  EXPECT_EQ(planned_inputs(all), paths);
  std::multiset<std::string> union_of_shards;
  for (int i = 1; i <= 4; ++i) {
    const std::string shard = std::to_string(i) + "/4";
    const CommandResult part = pmenc_in(
        dir.path(), {"--from-list", "list.txt", "--out-dir", "o", "--dry-run", "--shard", shard});
    ASSERT_EQ(part.exit_code, 0) << part.err;
    const std::vector<std::string> inputs = planned_inputs(part);
    EXPECT_GE(inputs.size(), 25u) << shard << " is far from a quarter";
    union_of_shards.insert(inputs.begin(), inputs.end());
    const CommandResult reordered = pmenc_in(
        dir.path(), {"--from-list", "other.txt", "--out-dir", "o", "--dry-run", "--shard", shard});
    ASSERT_EQ(reordered.exit_code, 0) << reordered.err;
    std::set<std::string> a, b;
    for (const std::string& p : inputs) a.insert(normalized(p));
    for (const std::string& p : planned_inputs(reordered)) b.insert(normalized(p));
    EXPECT_EQ(a, b) << shard;
  }
  // Disjoint and covering: every path exactly once.
  EXPECT_EQ(union_of_shards, std::multiset<std::string>(paths.begin(), paths.end()));

  for (const char* bad : {"0/4", "5/4", "1/0", "a/4", "3", "1/4/2", ""}) {
    const CommandResult r =
        pmenc_in(dir.path(), {"--from-list", "list.txt", "--dry-run", "--shard", bad});
    EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.err;
  }
}

TEST(Batch, ShardedParallelRunsWriteTheBytesOfASerialRun) {
  TempDir dir;
  int n = 0;
  for (const char* sample : {"polygons.obj", "nonmanifold.obj", "block_features.obj"})
    for (int i = 0; i < 3; ++i)
      copy_into(test::sample_mesh_path(sample),
                dir.file("in/" + std::to_string(n++) + "/" + sample));
  CommandResult r = pmenc_in(dir.path(), {"-r", "in", "--out-dir", "serial", "-j", "1", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (int i = 1; i <= 4; ++i) {
    r = pmenc_in(dir.path(), {"-r", "in", "--out-dir", "sharded", "-j", "2", "-q", "--shard",
                              std::to_string(i) + "/4"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  const auto serial = tree(dir.file("serial"));
  EXPECT_EQ(serial.size(), 9u);
  EXPECT_TRUE(serial == tree(dir.file("sharded")));
  // And a single-file run of one of them: same bytes again.
  r = pmenc_in(dir.path(), {"in/8/block_features.obj", "-o", "single.pm", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(test::read_file(dir.file("single.pm")) == serial.at("in/8/block_features.pm"));
}

// ---------------------------------------------------------------------------------------
// Inputs and output names

TEST(Batch, TemplatesNameOutputsAndOutDirMirrorsTheInputs) {
  TempDir dir;
  copy_into(test::sample_mesh_path("polygons.obj"), dir.file("m/a.obj"));
  copy_into(test::sample_mesh_path("polygons.obj"), dir.file("m/n/b.obj"));
  CommandResult r = pmenc_in(dir.path(), {"m/a.obj", "m/n/b.obj", "--out-dir", "o", "-o",
                                          "{name}-{stem}-{ext}{{x}}.pm", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(test::file_exists(dir.file("o/a.obj-a-obj{x}.pm")));
  EXPECT_TRUE(test::file_exists(dir.file("o/b.obj-b-obj{x}.pm")));
  // Default: beside the input; with --out-dir: the input's path below it.
  r = pmenc_in(dir.path(), {"m/a.obj", "m/n/b.obj", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(test::file_exists(dir.file("m/a.pm")));
  EXPECT_TRUE(test::file_exists(dir.file("m/n/b.pm")));
  r = pmenc_in(dir.path(), {"./m//a.obj", "m/n/b.obj", "--out-dir", "mirror", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(test::file_exists(dir.file("mirror/m/a.pm")));
  EXPECT_TRUE(test::file_exists(dir.file("mirror/m/n/b.pm")));
  // An absolute path and one above the working directory stay below --out-dir.
  r = pmenc_in(dir.file("m/n"),
               {dir.file("m/a.obj"), "../../m/n/b.obj", "--out-dir", "up", "--json", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto results = json_lines_by_input(r.out);
  EXPECT_EQ(results[dir.file("m/a.obj")]["output"].text, "up" + dir.file("m/a.pm"));
  EXPECT_EQ(results["../../m/n/b.obj"]["output"].text, "up/m/n/b.pm");
  EXPECT_TRUE(test::file_exists(dir.file("m/n/up/m/n/b.pm")));
  EXPECT_TRUE(test::file_exists(dir.file("m/n/up" + dir.file("m/a.pm"))));
}

TEST(Batch, ConflictingOrBadOutputNamesAreUsageErrorsBeforeAnyWork) {
  TempDir dir;
  copy_into(test::sample_mesh_path("polygons.obj"), dir.file("a/x.obj"));
  copy_into(test::sample_mesh_path("polygons.obj"), dir.file("b/x.obj"));
  CommandResult r = pmenc_in(dir.path(), {"a/x.obj", "b/x.obj", "-o", "one.pm"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("names one file, but there are 2 inputs"), std::string::npos) << r.err;
  r = pmenc_in(dir.path(), {"a/x.obj", "-o", "{base}.pm"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown placeholder {base}"), std::string::npos) << r.err;
  EXPECT_EQ(pmenc_in(dir.path(), {"a/x.obj", "-o", "{stem.pm"}).exit_code, 2);
  EXPECT_EQ(pmenc_in(dir.path(), {"a/x.obj", "b/x.obj", "-o", "-"}).exit_code, 2);
  EXPECT_EQ(pmenc_in(dir.path(), {"a/x.obj", "-o", "-", "--json"}).exit_code, 2);
  EXPECT_EQ(pmenc_in(dir.path(), {"-", "a/x.obj"}).exit_code, 2);
  EXPECT_EQ(pmenc_in(dir.path(), {}).exit_code, 2);
  EXPECT_FALSE(test::file_exists(dir.file("one.pm")));
  EXPECT_FALSE(test::file_exists(dir.file("a/x.pm")));
}

TEST(Batch, InputsWithTheSameOutputFailButTheFirstAndTheInvalid) {
  TempDir dir;
  copy_into(test::sample_mesh_path("polygons.obj"), dir.file("a/x.obj"));
  copy_into(test::sample_mesh_path("nonmanifold.obj"), dir.file("b/x.obj"));
  copy_into(test::sample_mesh_path("polygons.obj"), dir.file("a/x.off"));
  test::write_file(dir.file("a/x.ply"), "ply\nnonsense\n");
  ASSERT_EQ(pmenc_in(dir.path(), {"a/x.obj", "-o", "alone.pm", "-q"}).exit_code, 0);
  // The first input in list order keeps the name, whatever -j or the shard; a later valid
  // one fails (with exit code 2 of its own); a later invalid one reports its own problem.
  std::map<std::string, int> reports;
  for (const char* shard : {"1/1", "1/2", "2/2"}) {
    SCOPED_TRACE(shard);
    TempDir out;
    const CommandResult r =
        pmenc_in(dir.path(), {"a/x.obj", "b/x.obj", "a/x.ply", "--out-dir", out.path(), "-o",
                              "{stem}.pm", "--json", "-j", "2", "--shard", shard});
    auto results = json_lines_by_input(r.out);
    if (results.count("a/x.obj")) {
      EXPECT_EQ(results["a/x.obj"]["status"].text, "ok");
      EXPECT_TRUE(test::read_file(out.file("x.pm")) == test::read_file(dir.file("alone.pm")));
    }
    if (results.count("b/x.obj")) {
      EXPECT_EQ(results["b/x.obj"]["exit_code"].integer(), 2);
      EXPECT_TRUE(has_line(r.err, "pmenc: b/x.obj: " + out.file("x.pm") +
                                      " is also the output of a/x.obj, given earlier (name the "
                                      "outputs apart, e.g. with {dir} in -o)"))
          << r.err;
    }
    if (results.count("a/x.ply")) {
      EXPECT_EQ(results["a/x.ply"]["exit_code"].integer(), 4);
    }
    for (const auto& [input, result] : results) ++reports[input];
  }
  // Each input once in the full run and once in one of the halves.
  EXPECT_EQ(reports, (std::map<std::string, int>{{"a/x.obj", 2}, {"b/x.obj", 2}, {"a/x.ply", 2}}));
  const CommandResult r =
      pmenc_in(dir.path(), {"a/x.obj", "a/x.off", "b/x.obj", "-o", "{dir}/{stem}.pm"});
  EXPECT_EQ(r.exit_code, 8);
  EXPECT_TRUE(has_line(r.err, "pmenc: a/x.off: line 6: not an off file (no OFF header)")) << r.err;
  // Two valid inputs that differ by their extension only: told apart by {ext}.
  ASSERT_EQ(pmdec_in(dir.path(), {"alone.pm", "-o", "a/x.stl", "-q"}).exit_code, 0);
  const CommandResult same_stem = pmenc_in(dir.path(), {"a/x.obj", "a/x.stl"});
  EXPECT_EQ(same_stem.exit_code, 8);
  EXPECT_TRUE(has_line(same_stem.err,
                       "pmenc: a/x.stl: a/x.pm is also the output of a/x.obj, given earlier (name "
                       "the outputs apart, e.g. with {ext} in -o)"))
      << same_stem.err;
  // The same file twice is converted once.
  const CommandResult twice = pmenc_in(dir.path(), {"a/x.obj", "./a//x.obj", "--json", "-q"});
  EXPECT_EQ(twice.exit_code, 0) << twice.err;
  EXPECT_EQ(lines_of(twice.out).size(), 1u);
}

TEST(Batch, ListsRecursionAndFailuresThatDoNotStopTheBatch) {
  TempDir dir;
  copy_into(test::sample_mesh_path("polygons.obj"), dir.file("tree/p.obj"));
  copy_into(test::sample_mesh_path("nonmanifold.obj"), dir.file("tree/deep/er/n.OBJ"));
  test::write_file(dir.file("tree/readme.txt"), "not a mesh");        // ignored by -r
  test::write_file(dir.file("tree/bad.off"), "OFF\n3 1 0\n0 0 0\n");  // picked up, fails
  // -r: mesh extensions only, any case.
  CommandResult r = pmenc_in(dir.path(), {"-r", "tree", "--out-dir", "o", "--dry-run"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out,
            "tree/bad.off\to/tree/bad.pm\ntree/deep/er/n.OBJ\to/tree/deep/er/n.pm\ntree/p.obj\to/"
            "tree/p.pm\n");
  r = pmenc_in(dir.path(), {"-r", "tree", "--out-dir", "o", "--json"});
  EXPECT_EQ(r.exit_code, 8) << r.err;
  auto results = json_lines_by_input(r.out);
  EXPECT_EQ(results["tree/p.obj"]["status"].text, "ok");
  EXPECT_EQ(results["tree/deep/er/n.OBJ"]["status"].text, "ok");
  EXPECT_EQ(results["tree/bad.off"]["status"].text, "failed");
  EXPECT_EQ(results["tree/bad.off"]["exit_code"].integer(), 4);
  EXPECT_TRUE(test::file_exists(dir.file("o/tree/p.pm")));
  EXPECT_FALSE(test::file_exists(dir.file("o/tree/bad.pm")));

  // A directory without -r, a missing file: reported, the rest converted.
  r = pmenc_in(dir.path(), {"tree", "nope.obj", "tree/p.obj", "--out-dir", "o2", "--json"});
  EXPECT_EQ(r.exit_code, 8) << r.err;
  EXPECT_TRUE(has_line(r.err, "pmenc: tree: is a directory (use -r to convert the files in it)"))
      << r.err;
  results = json_lines_by_input(r.out);
  EXPECT_EQ(results["tree"]["exit_code"].integer(), 3);
  EXPECT_EQ(results["nope.obj"]["exit_code"].integer(), 3);
  EXPECT_EQ(results["tree/p.obj"]["status"].text, "ok");
  // Alone, a directory keeps the single-file exit code.
  EXPECT_EQ(pmenc_in(dir.path(), {"tree", "-o", "x.pm"}).exit_code, 3);

  // --from-list FILE (CRLF, blank lines) and --from-list - (standard input).
  test::write_file(dir.file("list.txt"), "tree/p.obj\r\n\r\n\ntree/deep/er/n.OBJ\r\n");
  r = pmenc_in(dir.path(), {"--from-list", "list.txt", "--out-dir", "o3", "-q"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(test::file_exists(dir.file("o3/tree/deep/er/n.pm")));
  r = pmenc_in(dir.path(), {"--from-list", "-", "--out-dir", "o4", "-q"}, "tree/p.obj\n");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(test::file_exists(dir.file("o4/tree/p.pm")));
  r = pmenc_in(dir.path(), {"--from-list", "missing.txt", "--out-dir", "o5"});
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_EQ(r.err.rfind("pmenc: --from-list: missing.txt: cannot open", 0), 0u) << r.err;
}

TEST(Batch, OneLinePerFileOnAPipeAndNothingWithQuiet) {
  TempDir dir;
  copy_into(test::sample_mesh_path("block_features.obj"), dir.file("in/a.obj"));
  copy_into(test::sample_mesh_path("block_features.obj"), dir.file("in/b.obj"));
  CommandResult r = pmenc_in(dir.path(), {"-r", "in", "--out-dir", "o", "-j", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> lines = lines_of(r.err);
  ASSERT_EQ(lines.size(), 3u) << r.err;
  std::vector<std::string> per_file = {
      lines[0].substr(0, lines[0].find(": 2944 faces, base mesh ")),
      lines[1].substr(0, lines[1].find(": 2944 faces, base mesh "))};
  std::sort(per_file.begin(), per_file.end());
  EXPECT_EQ(per_file, (std::vector<std::string>{"pmenc: in/a.obj", "pmenc: in/b.obj"}));
  EXPECT_EQ(lines[2].rfind("pmenc: 2 files: 2 converted, 0 skipped, 0 failed, 5888 faces in ", 0),
            0u)
      << lines[2];
  r = pmenc_in(dir.path(), {"-r", "in", "--out-dir", "o", "-q"});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.err, "");
  EXPECT_EQ(r.out, "");
}

// ---------------------------------------------------------------------------------------
// Terminals

struct TerminalRun {
  int exit_code = -1;
  std::string terminal;  // what the program wrote to the terminal
};

// Runs argv with stderr (and stdout, if asked) on a new pseudo-terminal, TERM=xterm.
TerminalRun run_on_terminal(const std::vector<std::string>& argv, bool stdout_too) {
  TerminalRun result;
  const int master = posix_openpt(O_RDWR | O_NOCTTY);
  if (master < 0 || grantpt(master) != 0 || unlockpt(master) != 0) return result;
  const std::string slave_name = ptsname(master);
  std::vector<char*> args;
  for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  std::vector<std::string> environment = {"TERM=xterm"};
  for (char** e = environ; *e; ++e)
    if (std::strncmp(*e, "TERM=", 5) != 0) environment.push_back(*e);
  std::vector<char*> envp;
  for (std::string& e : environment) envp.push_back(e.data());
  envp.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    setsid();
    const int slave = open(slave_name.c_str(), O_RDWR);
    const int null = open("/dev/null", O_RDWR);
    dup2(null, 0);
    dup2(stdout_too ? slave : null, 1);
    dup2(slave, 2);
    close(master);
    execve(args[0], args.data(), envp.data());
    _exit(127);
  }
  char buffer[4096];
  for (;;) {
    const ssize_t n = read(master, buffer, sizeof buffer);
    if (n > 0) {
      result.terminal.append(buffer, static_cast<std::size_t>(n));
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    break;  // EIO: the program and its terminal are gone
  }
  int status = 0;
  waitpid(pid, &status, 0);
  close(master);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return result;
}

TEST(Batch, ProgressBarOnATerminalAndNothingWithQuiet) {
  TempDir dir;
  for (int i = 0; i < 3; ++i)
    copy_into(test::sample_mesh_path("sphere.obj"), dir.file("in/" + std::to_string(i) + ".obj"));
  copy_into(test::sample_mesh_path("polygons.obj"), dir.file("in/bad.obj"));
  test::write_file(dir.file("in/bad.obj"), "f 1 2 3\n");
  TerminalRun run = run_on_terminal(
      in_dir(dir.path(), PMENC_PATH, {"-r", "in", "--out-dir", "o", "-j", "2"}), false);
  EXPECT_EQ(run.exit_code, 8);
  // The bar is redrawn in place ("\r"), with files done, faces per second and the ETA; the
  // failure and the totals are lines of their own.
  EXPECT_NE(run.terminal.find("\rpmenc 0/4 files ["), std::string::npos) << run.terminal;
  EXPECT_NE(run.terminal.find("faces/s  ETA "), std::string::npos) << run.terminal;
  EXPECT_NE(run.terminal.find("\rpmenc 4/4 files [####################] 100%"), std::string::npos)
      << run.terminal;
  EXPECT_NE(run.terminal.find("pmenc: in/bad.obj: "), std::string::npos) << run.terminal;
  EXPECT_NE(run.terminal.find("pmenc: 4 files: 3 converted, 0 skipped, 1 failed, "),
            std::string::npos)
      << run.terminal;
  // No per-file line: the bar counts them.
  EXPECT_EQ(run.terminal.find("pmenc: in/0.obj: "), std::string::npos) << run.terminal;

  run =
      run_on_terminal(in_dir(dir.path(), PMENC_PATH, {"-r", "in", "--out-dir", "q", "-q"}), false);
  EXPECT_EQ(run.exit_code, 8);
  EXPECT_EQ(run.terminal.find("files ["), std::string::npos) << run.terminal;
  // Errors only: the one line of the failure.
  EXPECT_EQ(std::count(run.terminal.begin(), run.terminal.end(), '\n'), 1) << run.terminal;
}

TEST(Batch, BinaryOutputToATerminalIsRefused) {
  TempDir dir;
  const TerminalRun run =
      run_on_terminal({PMENC_PATH, test::sample_mesh_path("polygons.obj"), "-o", "-"}, true);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.terminal.find("refusing to write binary data to a terminal"), std::string::npos)
      << run.terminal;
  EXPECT_EQ(run.terminal.find("PM"), std::string::npos);
}

// ---------------------------------------------------------------------------------------
// Pipes

TEST(Batch, PipesFromPmencThroughPmdec) {
  TempDir dir;
  const std::string obj = test::read_file(test::sample_mesh_path("sphere.obj"));
  // Standard input's format is recognized by its content.
  const CommandResult encoded = test::run_command({PMENC_PATH, "-", "-o", "-", "-q"}, obj);
  ASSERT_EQ(encoded.exit_code, 0) << encoded.err;
  ASSERT_EQ(test::run_command(
                {PMENC_PATH, test::sample_mesh_path("sphere.obj"), "-o", dir.file("s.pm"), "-q"})
                .exit_code,
            0);
  EXPECT_TRUE(encoded.out == test::read_file(dir.file("s.pm")));
  const CommandResult decoded =
      test::run_command({PMDEC_PATH, "-", "--ratio", "0.1", "-o", "-", "-q"}, encoded.out);
  ASSERT_EQ(decoded.exit_code, 0) << decoded.err;
  ASSERT_EQ(test::run_command(
                {PMDEC_PATH, dir.file("s.pm"), "--ratio", "0.1", "-o", dir.file("s10.obj"), "-q"})
                .exit_code,
            0);
  EXPECT_EQ(decoded.out, test::read_file(dir.file("s10.obj")));
  // And as a shell pipeline.
  const CommandResult shell = test::run_command(
      {"/bin/bash", "-c",
       "set -o pipefail; cat \"$1\" | \"$2\" - -o - | \"$3\" - --ratio 0.1 -o - > \"$4\"", "sh",
       test::sample_mesh_path("sphere.obj"), PMENC_PATH, PMDEC_PATH, dir.file("a10.obj")});
  ASSERT_EQ(shell.exit_code, 0) << shell.err;
  EXPECT_EQ(test::read_file(dir.file("a10.obj")), test::read_file(dir.file("s10.obj")));
  // Each format is recognized on standard input; text that is none of them is refused.
  for (const char* ext : {"ply", "off", "stl"}) {
    ASSERT_EQ(test::run_command(
                  {PMDEC_PATH, dir.file("s.pm"), "-o", dir.file(std::string("s.") + ext), "-q"})
                  .exit_code,
              0);
    const CommandResult r = test::run_command({PMENC_PATH, "-", "-o", "-", "-q"},
                                              test::read_file(dir.file(std::string("s.") + ext)));
    EXPECT_EQ(r.exit_code, 0) << ext << ": " << r.err;
  }
  const CommandResult unknown = test::run_command({PMENC_PATH, "-", "-o", "-"}, "hello world\n");
  EXPECT_EQ(unknown.exit_code, 6);
  EXPECT_EQ(unknown.err,
            "pmenc: (stdin): cannot tell the mesh format of standard input: use --format "
            "obj|ply|off|stl|gltf|glb\n");
}

// ---------------------------------------------------------------------------------------
// pmdec on many files

TEST(Batch, PmdecWritesEveryLevelOfEveryInputFromTemplates) {
  TempDir dir;
  copy_into(test::sample_mesh_path("sphere.obj"), dir.file("a.obj"));
  copy_into(test::sample_mesh_path("terrain_holes.obj"), dir.file("b.obj"));
  ASSERT_EQ(pmenc_in(dir.path(), {"a.obj", "b.obj", "-q"}).exit_code, 0);
  CommandResult r = pmdec_in(dir.path(), {"a.pm", "b.pm", "--lods", "100%,25%,5%,1%,300",
                                          "--out-dir", "out", "-o", "{stem}_{lod}.obj", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto results = json_lines_by_input(r.out);
  ASSERT_EQ(results.size(), 2u);
  for (const char* stem : {"a", "b"}) {
    const Json& result = results[std::string(stem) + ".pm"];
    EXPECT_EQ(result["status"].text, "ok");
    ASSERT_EQ(result["outputs"].items.size(), 5u);
    const std::vector<std::pair<std::string, std::vector<std::string>>> levels = {
        {"100", {"--ratio", "1"}},
        {"25", {"--ratio", "0.25"}},
        {"5", {"--ratio", "0.05"}},
        {"1", {"--ratio", "0.01"}},
        {"300", {"--faces", "300"}}};
    for (std::size_t i = 0; i < levels.size(); ++i) {
      const auto& [label, option] = levels[i];
      SCOPED_TRACE(std::string(stem) + " " + label);
      const std::string name = "out/" + std::string(stem) + "_" + label + ".obj";
      const Json& level = result["outputs"].items[i];
      EXPECT_EQ(level["output"].text, name);
      EXPECT_EQ(level["lod"].text, label);
      // Byte for byte what a single-level run writes.
      std::vector<std::string> single = {std::string(stem) + ".pm", "-o", "single.obj", "-q"};
      single.insert(single.end(), option.begin(), option.end());
      ASSERT_EQ(pmdec_in(dir.path(), single).exit_code, 0);
      EXPECT_EQ(test::read_file(dir.file(name)), test::read_file(dir.file("single.obj")));
      EXPECT_EQ(level["faces"].integer(),
                static_cast<long long>(read_or_fail(dir.file(name)).face_count()));
    }
  }
  // The default name with --out-dir mirrors the input and appends _{lod}.
  r = pmdec_in(dir.path(), {"a.pm", "--lods", "50%", "--out-dir", "d", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(test::file_exists(dir.file("d/a_50.obj")));
  // --skip-existing: every output there, nothing to do.
  r = pmdec_in(dir.path(), {"a.pm", "b.pm", "--lods", "100%,25%,5%,1%,300", "--out-dir", "out",
                            "-o", "{stem}_{lod}.obj", "--json", "--skip-existing"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const auto& [input, result] : json_lines_by_input(r.out))
    EXPECT_EQ(result["status"].text, "skipped") << input;
}

TEST(Batch, PmdecUsageErrorsAndFailuresThatDoNotStopTheBatch) {
  TempDir dir;
  copy_into(test::sample_mesh_path("polygons.obj"), dir.file("a.obj"));
  ASSERT_EQ(pmenc_in(dir.path(), {"a.obj", "-q"}).exit_code, 0);
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
           {"a.pm", "--lods", "100%,25%", "-o", "x.obj"},         // levels not named apart
           {"a.pm", "--ratio", "0.5", "-o", "{stem}_{lod}.obj"},  // {lod} without --lods
           {"a.pm", "--lods", "abc", "--out-dir", "o"},
           {"a.pm", "--lods", "0%", "--out-dir", "o"},
           {"a.pm", "--lods", "101%", "--out-dir", "o"},
           {"a.pm", "--lods", "50%,,5%", "--out-dir", "o"},
           {"a.pm", "--lods", "50%,5%", "-o", "-"},
           {"a.pm", "--lods", "50%", "--faces", "10", "--out-dir", "o"},
           {"a.pm", "--lods", "25%,25", "--out-dir", "o"},  // two levels named 25
       }) {
    const CommandResult r = pmdec_in(dir.path(), args);
    EXPECT_EQ(r.exit_code, 2) << testing::PrintToString(args) << r.err;
  }
  EXPECT_FALSE(test::file_exists(dir.file("o")));
  EXPECT_FALSE(test::file_exists(dir.file("x.obj")));

  test::write_file(dir.file("bad.pm"), test::read_file(dir.file("a.pm")).substr(0, 40));
  const CommandResult r = pmdec_in(dir.path(), {"a.pm", "bad.pm", "--out-dir", "o", "--json"});
  EXPECT_EQ(r.exit_code, 8);
  auto results = json_lines_by_input(r.out);
  EXPECT_EQ(results["a.pm"]["status"].text, "ok");
  EXPECT_EQ(results["bad.pm"]["exit_code"].integer(), 4);
  EXPECT_TRUE(has_line(r.err, "pmdec: bad.pm: " + results["bad.pm"]["error"].text)) << r.err;
  EXPECT_TRUE(test::file_exists(dir.file("o/a.obj")));
  EXPECT_FALSE(test::file_exists(dir.file("o/bad.obj")));
  // --info on several files: one block each.
  fs::copy_file(dir.file("a.pm"), dir.file("b.pm"));
  const CommandResult info = pmdec_in(dir.path(), {"a.pm", "b.pm", "--info"});
  EXPECT_EQ(info.exit_code, 0) << info.err;
  EXPECT_EQ(lines_of(info.out).size(),
            2 * lines_of(pmdec_in(dir.path(), {"a.pm", "--info"}).out).size() + 1);
}

}  // namespace
}  // namespace pm
