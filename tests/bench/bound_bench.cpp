// How tight the recorded errors are (issue 25): for each mesh, the levels of at most 50%, 10%
// and 2% of the faces, by the one collapse loop (since issue 25) with its measure (its record
// tracks every removed point: tracked_points.h) and without it (EncodeOptions::fast, which
// tracks them too, settling a point within the records so far), the recorded error
// against the exact largest distance of an input vertex to the level's faces (what the
// record bounds: pm::measure_surface_distance from the input's vertices alone). A ratio below
// 1 would be a record that is not a bound. Then the encode's time on one thread, median of
// --runs runs, with the measure.
//
//   pm_bench_bound MESH_DIR [--out bound.md] [--runs 5]
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "bench_report.h"
#include "pm/encoder.h"
#include "pm/lod.h"
#include "pm/mesh.h"
#include "pm/mesh_io.h"
#include "pm/surface_distance.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using pm::bench::median;
using pm::bench::significant;
using pm::bench::with_thousands;

namespace {

constexpr double kTargets[] = {0.5, 0.1, 0.02};

bool encode(const pm::Mesh& mesh, bool fast, pm::ProgressiveMesh& out, double* ms) {
  pm::EncodeOptions options;
  options.drop_attributes = true;
  options.threads = 1;
  options.fast = fast;
  const auto start = Clock::now();
  const pm::Status s = pm::encode(mesh, options, out);
  if (ms) *ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  if (!s) std::cerr << "bound_bench: encode failed: " << s.message() << "\n";
  return s.is_ok();
}

// The input's vertices as point-like faces (those some face uses).
pm::Mesh vertices_of(const pm::Mesh& input) {
  std::vector<bool> used(input.vertex_count(), false);
  for (uint32_t v : input.triangles) used[v] = true;
  pm::Mesh points;
  points.positions = input.positions;
  for (uint32_t v = 0; v < input.vertex_count(); ++v)
    if (used[v]) points.triangles.insert(points.triangles.end(), {v, v, v});
  return points;
}

struct Tightness {
  double recorded = 0, exact = 0;
};

// The finest level with at most n faces (as fast_bench's).
Tightness tightness(const pm::ProgressiveMesh& progressive, const pm::Mesh& points, std::size_t n) {
  std::size_t level = pm::level_for_faces(progressive, n);
  if (level > 0 && pm::faces_at_level(progressive, level) > n) --level;
  pm::DistanceOptions one_sample;
  one_sample.samples_per_face = 1;
  pm::SurfaceDistance d;
  if (pm::Status s = pm::measure_surface_distance(points, pm::extract_level(progressive, level),
                                                  one_sample, d);
      !s)
    std::cerr << "bound_bench: measure failed: " << s.message() << "\n";
  return {pm::error_at_level(progressive, level), d.forward_max};
}

std::string ratio(const Tightness& t) {
  if (!(t.exact > 0)) return "n/a";
  const double r = t.recorded / t.exact;
  return significant(r) + (r < 1 ? " (below!)" : "");
}

}  // namespace

int main(int argc, char** argv) {
  pm::bench::MeshDirArguments arguments{"", "bound.md", 5};
  if (!pm::bench::parse_mesh_dir_arguments(argc, argv, "pm_bench_bound", arguments)) return 2;
  const auto& [dir, out_path, runs] = arguments;
  const std::vector<fs::path> paths = pm::bench::mesh_files({dir});

  std::ostringstream table, speed;
  table << "| mesh | target | recorded | exact | recorded/exact | --fast: recorded | exact | "
           "recorded/exact |\n"
           "|---|---:|---:|---:|---:|---:|---:|---:|\n";
  speed << "| mesh | faces | encode ms |\n|---|---:|---:|\n";
  for (const fs::path& path : paths) {
    pm::Mesh original;
    if (!pm::bench::read_listed_mesh(path, "bound_bench", original)) continue;
    const std::string name = path.filename().string();
    pm::ProgressiveMesh progressive, fast;
    std::vector<double> times;
    for (int r = 0; r < runs; ++r) {
      double ms = 0;
      if (!encode(original, false, progressive, &ms)) return 1;
      times.push_back(ms);
    }
    if (!encode(original, true, fast, nullptr)) return 1;
    const pm::Mesh points = vertices_of(original);
    const double diagonal = pm::bounding_box_diagonal(original.positions) / 100;  // percent
    for (const double target : kTargets) {
      const auto faces = static_cast<std::size_t>(target * original.face_count());
      const Tightness t = tightness(progressive, points, faces);
      const Tightness f = tightness(fast, points, faces);
      table << "| " << name << " | " << significant(100 * target) << "% | "
            << significant(t.recorded / diagonal) << " | " << significant(t.exact / diagonal)
            << " | " << ratio(t) << " | " << significant(f.recorded / diagonal) << " | "
            << significant(f.exact / diagonal) << " | " << ratio(f) << " |\n";
    }
    speed << "| " << name << " | " << with_thousands(original.face_count()) << " | "
          << significant(median(times)) << " |\n";
  }

  std::ofstream md(out_path);
  md << "# Recorded errors against the distances they bound\n\n"
     << "Generated by `tests/bench/run_bound.sh` (issue 25; pm_bench_bound, "
        "tests/bench/bound_bench.cpp).\n\n"
     << pm::bench::run_description(PM_BENCH_SOURCE_DIR)
     << "- load average at the end: " << pm::bench::command_output("cut -d' ' -f1-3 /proc/loadavg")
     << "\n\n"
     << "Each level of at most the target's faces: its recorded error (`pm::error_at_level`, "
        "what `pmdec --error --estimate` selects by) and the exact largest distance of an input "
        "vertex to its faces (`pm::measure_surface_distance` from the input's vertices), both in "
        "percent of the bounding-box diagonal. The record must be at least the distance "
        "(recorded/exact >= 1); the nearer 1, the tighter. `pm::encode`, the one collapse loop "
        "(since issue 25), geometry only: with its measured distance (pmenc's default below a "
        "million faces) and without it (`EncodeOptions::fast`, pmenc `--fast`; its levels "
        "differ), both tracking every removed point on a face of the level for the record "
        "(lib/src/simplify/tracked_points.h). With the measure a point that moves goes to its "
        "nearest face unless it is within the kept points' distance of the one it was on; "
        "without it, unless it is within the largest record so far.\n\n"
     << "## Tightness\n\n"
     << table.str() << "\n## Time\n\n"
     << "The whole `pm::encode` with the measure on one thread, median of " << runs
     << " runs.\n\n"
     << speed.str();
  std::cerr << "wrote " << out_path << "\n";
  return 0;
}
