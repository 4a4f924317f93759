// What the benchmarks' markdown reports share: number formatting and the lines that say
// where and when a table was made.
#pragma once

#include <cstddef>
#include <string>

namespace pm::bench {

// Three significant digits (or `digits`), never in exponent form: 0.000123, 0.0412, 1.23.
std::string significant(double value, int digits = 3);
// "a / b" with enough significant digits (3 to 7) that unequal values print unequal, so a
// verdict between them shows in the numbers.
std::string distinguishable_pair(double ours, double peer);
// 12,345.
std::string with_thousands(std::size_t n);
// 'text' for a POSIX shell.
std::string shell_quoted(const std::string& text);
// What the command prints on standard output, without the trailing line break ("" when it
// cannot run).
std::string command_output(const std::string& command);
// "- machine: ...\n- date: ...\n- commit: ...\n" for the repository at source_dir; the
// commit says when lib/ or formats/ have uncommitted changes, since the library measured
// is then not that commit's.
std::string run_description(const std::string& source_dir);

}  // namespace pm::bench
