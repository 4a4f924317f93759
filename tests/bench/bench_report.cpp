// Shared pieces of the benchmarks' reports; see bench_report.h.
#include "bench_report.h"

#include <sys/utsname.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>

#include "pm/lod.h"
#include "pm/mesh_io.h"
#include "pm/surface_distance.h"

namespace pm::bench {

std::string significant(double value, int digits) {
  if (value == 0) return "0";
  const int magnitude = static_cast<int>(std::floor(std::log10(std::fabs(value))));
  const int decimals = std::max(0, digits - 1 - magnitude);
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return text;
}

std::string distinguishable_pair(double ours, double peer) {
  int digits = 3;
  while (digits < 7 && ours != peer && significant(ours, digits) == significant(peer, digits))
    ++digits;
  return significant(ours, digits) + " / " + significant(peer, digits);
}

std::string with_thousands(std::size_t n) {
  std::string digits = std::to_string(n), text;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) text += ',';
    text += digits[i];
  }
  return text;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

std::string shell_quoted(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

std::string command_output(const std::string& command) {
  std::string text;
  if (FILE* pipe = popen(command.c_str(), "r")) {
    std::array<char, 256> buffer;
    while (std::fgets(buffer.data(), buffer.size(), pipe)) text += buffer.data();
    pclose(pipe);
  }
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  return text;
}

std::string run_description(const std::string& source_dir) {
  std::ostringstream text;
  utsname names{};
  uname(&names);
  std::string cpu = "unknown CPU";
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);) {
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  }
  const std::time_t now = std::time(nullptr);
  char date[64];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  const std::string repo = shell_quoted(source_dir);
  std::string commit = command_output("git -C " + repo + " rev-parse --short HEAD 2>/dev/null");
  if (commit.empty())
    commit = "unknown";
  else if (!command_output("git -C " + repo + " status --porcelain -- lib formats 2>/dev/null")
                .empty())
    commit += " with uncommitted changes in lib/ or formats/";
  text << "- machine: " << names.machine << ", " << cpu << ", "
       << std::thread::hardware_concurrency() << " hardware threads (" << names.sysname << " "
       << names.release << ")\n"
       << "- date: " << date << "\n"
       << "- commit: " << commit << "\n";
  return text.str();
}

std::vector<std::filesystem::path> mesh_files(const std::vector<std::string>& inputs) {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  for (const std::string& input : inputs) {
    std::error_code error;
    if (fs::is_directory(input, error)) {
      std::vector<fs::path> found;
      for (const auto& entry : fs::directory_iterator(input, error))
        if (entry.is_regular_file() &&
            pm::mesh_format_from_path(entry.path().string()) != pm::MeshFormat::kUnknown)
          found.push_back(entry.path());
      std::sort(found.begin(), found.end());
      files.insert(files.end(), found.begin(), found.end());
    } else if (fs::exists(input, error)) {
      files.emplace_back(input);
    } else {
      std::cerr << "\n*** NOTE: " << input << " does not exist: skipped.\n\n";
    }
  }
  return files;
}

bool read_listed_mesh(const std::filesystem::path& path, const char* program, pm::Mesh& mesh) {
  if (pm::Status status = pm::read_mesh(path.string(), mesh); !status) {
    std::cerr << program << ": " << path.string() << ": " << status.message() << " (skipped)\n";
    return false;
  }
  std::cerr << "[" << program << "] " << path.filename().string() << "\n";
  return true;
}

std::size_t level_at_most_faces(const pm::ProgressiveMesh& progressive, std::size_t n) {
  std::size_t level = pm::level_for_faces(progressive, n);
  if (level > 0 && pm::faces_at_level(progressive, level) > n) --level;
  return level;
}

bool distance_percent(const pm::Mesh& original, const pm::Mesh& lod, double& hausdorff_percent,
                      double& rms_percent, std::string& note) {
  pm::SurfaceDistance distance;
  if (pm::Status s = pm::measure_surface_distance(original, lod, pm::DistanceOptions{}, distance);
      !s) {
    note = "distance: " + s.message();
    return false;
  }
  hausdorff_percent = 100 * distance.hausdorff / distance.diagonal;
  rms_percent = 100 * distance.rms / distance.diagonal;
  return true;
}

bool parse_targets(const std::string& text, std::vector<double>& targets) {
  targets.clear();
  std::stringstream list(text);
  for (std::string item; std::getline(list, item, ',');) {
    char* end = nullptr;
    const double value = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !(value > 0 && value <= 1)) return false;
    targets.push_back(value);
  }
  return !targets.empty();
}

bool parse_mesh_dir_arguments(int argc, char** argv, const char* program, MeshDirArguments& arguments) {
  bool ok = argc >= 2 && argv[1][0] != '-';
  if (ok) arguments.dir = argv[1];
  for (int i = 2; ok && i < argc; i += 2) {
    const std::string flag = argv[i];
    if (i + 1 >= argc) {
      ok = false;
    } else if (flag == "--out") {
      arguments.out_path = argv[i + 1];
    } else if (flag == "--runs") {
      char* end = nullptr;
      const long runs = std::strtol(argv[i + 1], &end, 10);
      ok = *end == '\0' && runs >= 1 && runs <= 1000;
      arguments.runs = static_cast<int>(runs);
    } else {
      ok = false;
    }
  }
  if (!ok) std::cerr << "usage: " << program << " MESH_DIR [--out FILE] [--runs N (1 to 1000)]\n";
  return ok;
}

}  // namespace pm::bench
