// Shared pieces of the benchmarks' reports; see bench_report.h.
#include "bench_report.h"

#include <sys/utsname.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <sstream>
#include <thread>

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

}  // namespace pm::bench
