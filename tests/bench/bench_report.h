// What the benchmarks' markdown reports share: number formatting and the lines that say
// where and when a table was made.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "pm/mesh.h"
#include "pm/progressive_mesh.h"

namespace pm::bench {

// Three significant digits (or `digits`), never in exponent form: 0.000123, 0.0412, 1.23.
std::string significant(double value, int digits = 3);
// "a / b" with enough significant digits (3 to 7) that unequal values print unequal, so a
// verdict between them shows in the numbers.
std::string distinguishable_pair(double ours, double peer);
// 12,345.
std::string with_thousands(std::size_t n);
// The middle value, or the mean of the two middle ones for an even count; 0 for none.
double median(std::vector<double> values);
// 'text' for a POSIX shell.
std::string shell_quoted(const std::string& text);
// What the command prints on standard output, without the trailing line break ("" when it
// cannot run).
std::string command_output(const std::string& command);
// "- machine: ...\n- date: ...\n- commit: ...\n" for the repository at source_dir; the
// commit says when lib/ or formats/ have uncommitted changes, since the library measured
// is then not that commit's.
std::string run_description(const std::string& source_dir);

// The mesh files among `inputs`: a file as named, a directory's meshes (the formats pm reads)
// sorted by name. A name that does not exist is noted on standard error and skipped.
std::vector<std::filesystem::path> mesh_files(const std::vector<std::string>& inputs);

// Reads one of mesh_files()'s meshes for `program`'s table, its name on standard error as
// progress; false, saying why it is skipped, when it cannot be read.
bool read_listed_mesh(const std::filesystem::path& path, const char* program, pm::Mesh& mesh);

// The finest level with at most n faces. pm::level_for_faces gives the coarsest with at
// least n; a split adds one or two faces, so that level may be one face over, and the level
// before it is then under.
std::size_t level_at_most_faces(const pm::ProgressiveMesh& progressive, std::size_t n);

// The geometric distance between `original` and `lod` as quality.md measures it
// (pm::measure_surface_distance, both ways, default options), in percent of the original's
// bounding-box diagonal; false, with the reason in `note`, when it cannot be measured.
bool distance_percent(const pm::Mesh& original, const pm::Mesh& lod, double& hausdorff_percent,
                      double& rms_percent, std::string& note);

// "0.5,0.1,0.02": fractions in (0, 1]; false for an empty list or any other item.
bool parse_targets(const std::string& text, std::vector<double>& targets);

// The command line of the benchmarks that take one folder of meshes:
//   PROGRAM MESH_DIR [--out FILE] [--runs N]
struct MeshDirArguments {
  std::string dir;
  std::string out_path;  // the caller's default until --out
  int runs = 5;          // at least 1
};
// False, with the usage on standard error, for a missing folder or an unknown or incomplete
// option (the caller exits with 2).
bool parse_mesh_dir_arguments(int argc, char** argv, const char* program, MeshDirArguments& arguments);

}  // namespace pm::bench
