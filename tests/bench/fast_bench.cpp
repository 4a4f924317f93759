// The one collapse loop (issue 25; the former fast loop, which every input takes) against
// meshopt_simplify, in one process: for each mesh, the surface distance of the levels at 50%,
// 10% and 2% of the faces (the measure of quality_bench: pm::measure_surface_distance, both
// ways), and the time of pm::encode on one thread (the whole .pm, every level) and of the
// collapse sequence alone against meshopt_simplify's time to 1% of the faces, medians of
// --runs runs each. With --metric schroeder, Schroeder's metric (fast_schroeder.md,
// run_fast.sh --metric schroeder). With --fast, the loop without its measured distance
// (fast_unmeasured.md, run_fast.sh --fast). The former default loop's levels are quality.md's
// 3cb92db rows.
//
//   pm_bench_fast MESH_DIR [--out fast.md] [--runs 5] [--metric quadric|schroeder] [--fast]
#include <meshoptimizer.h>
#include <sys/wait.h>

#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <cstdio>
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
#include "sequence_timing.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using pm::bench::median;
using pm::bench::significant;
using pm::bench::with_thousands;

namespace {

constexpr double kTargets[] = {0.5, 0.1, 0.02};
constexpr double kSpeedTarget = 0.01;

double milliseconds_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

struct Distance {
  double hausdorff = 0, rms = 0;  // percent of the diagonal
};

Distance measure(const pm::Mesh& original, const pm::Mesh& lod) {
  pm::SurfaceDistance distance;
  if (pm::Status s = pm::measure_surface_distance(original, lod, pm::DistanceOptions{}, distance);
      !s) {
    std::cerr << "fast_bench: measure failed: " << s.message() << "\n";
    return {-1, -1};
  }
  return {100.0 * distance.hausdorff / distance.diagonal, 100.0 * distance.rms / distance.diagonal};
}

bool encode(const pm::Mesh& mesh, pm::Metric metric, bool fast, pm::ProgressiveMesh& out,
            double& ms) {
  pm::EncodeOptions options;
  options.metric = metric;
  options.fast = fast;
  options.drop_attributes = true;  // geometry only, as meshopt is given
  options.threads = 1;
  const auto start = Clock::now();
  const pm::Status s = pm::encode(mesh, options, out);
  ms = milliseconds_since(start);
  if (!s) std::cerr << "fast_bench: encode failed: " << s.message() << "\n";
  return s.is_ok();
}

// The finest level with at most n faces (as quality_bench's).
pm::Mesh level_at_most(const pm::ProgressiveMesh& progressive, std::size_t n) {
  std::size_t level = pm::level_for_faces(progressive, n);
  if (level > 0 && pm::faces_at_level(progressive, level) > n) --level;
  return pm::extract_level(progressive, level);
}

pm::Mesh meshopt_level(const pm::Mesh& original, std::size_t target_faces, double& ms) {
  std::vector<unsigned int> indices(original.triangles.size());
  const auto start = Clock::now();
  const std::size_t count =
      meshopt_simplify(indices.data(), original.triangles.data(), original.triangles.size(),
                       original.positions.data(), original.vertex_count(), 3 * sizeof(float),
                       3 * target_faces, FLT_MAX, 0, nullptr);
  ms = milliseconds_since(start);
  pm::Mesh lod;
  lod.positions = original.positions;
  lod.triangles.assign(indices.begin(), indices.begin() + count);
  return lod;
}

std::string ratio(double ours, double theirs) {
  return theirs > 0 ? significant(ours / theirs) : "n/a";
}

// Takes --metric NAME out of argv (the other options are bench_report's); false for a name
// that is not a metric.
bool take_metric(int& argc, char** argv, pm::Metric& metric) {
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--metric" && i + 1 < argc) {
      const std::string name = argv[++i];
      if (name != "quadric" && name != "schroeder") return false;
      metric = name == "quadric" ? pm::Metric::kQuadric : pm::Metric::kSchroeder;
    } else {
      argv[kept++] = argv[i];
    }
  }
  argc = kept;
  return true;
}

// Takes `flag` out of argv: true when it was there.
bool take_flag(int& argc, char** argv, const std::string& flag) {
  bool found = false;
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    if (argv[i] == flag)
      found = true;
    else
      argv[kept++] = argv[i];
  }
  argc = kept;
  return found;
}

}  // namespace

int main(int argc, char** argv) {
  // --loop-meshes: MESH_DIR holds run_fast.sh --loop-meshes's meshes made by Loop
  // subdivision, which pmenc encodes without the measured distance (--fast-from): the loop
  // runs so (as --fast) and the table is fast_loop_meshes.md.
  const bool loop_meshes = take_flag(argc, argv, "--loop-meshes");
  const bool fast = take_flag(argc, argv, "--fast") || loop_meshes;
  pm::Metric metric = pm::Metric::kQuadric;
  if (!take_metric(argc, argv, metric)) {
    std::cerr << "pm_bench_fast: --metric is quadric or schroeder\n";
    return 2;
  }
  const bool schroeder = metric == pm::Metric::kSchroeder;
  const char* metric_name = schroeder ? "Schroeder's" : "quadric";
  pm::bench::MeshDirArguments arguments{
      "",
      loop_meshes ? "fast_loop_meshes.md"
      : fast      ? "fast_unmeasured.md"
      : schroeder ? "fast_schroeder.md"
                  : "fast.md",
      5};
  if (!pm::bench::parse_mesh_dir_arguments(argc, argv, "pm_bench_fast", arguments)) return 2;
  const auto& [dir, out_path, runs] = arguments;
  const std::vector<fs::path> paths = pm::bench::mesh_files({dir});

  std::ostringstream quality, speed;
  quality << "| mesh | target | faces | pmenc H % | meshopt H % | pmenc RMS % | meshopt RMS % | "
             "pmenc/meshopt H | pmenc/meshopt RMS |\n"
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  speed << "| mesh | faces | encode ms | loop ms | meshopt to 1% ms | loop / meshopt |\n"
        << "|---|---:|---:|---:|---:|---:|\n";
  // Over the meshes and targets: the ratios' geometric means and largest values.
  double log_h = 0, log_rms = 0, worst_h = 0, worst_rms = 0;
  int points = 0;
  for (const fs::path& path : paths) {
    pm::Mesh original;
    if (!pm::bench::read_listed_mesh(path, "fast_bench", original)) continue;
    const std::string name = path.filename().string();
    pm::ProgressiveMesh progressive;
    std::vector<double> encode_times, loop_times, meshopt_times;
    // The collapse sequence alone, as pm::encode runs it; a mesh that needs a repair is
    // repaired before the timer starts (sequence_timing.h).
    pm::EncodeOptions options;
    options.metric = metric;
    options.fast = fast;
    options.threads = 1;
    options.drop_attributes = true;  // as encode() above, and as meshopt is given
    pm::bench::CollapseSequenceRun sequence_run(original, options);
    for (int r = 0; r < runs; ++r) {
      double encode_ms = 0;
      if (!encode(original, metric, fast, progressive, encode_ms)) return 1;
      encode_times.push_back(encode_ms);
      if (pm::Status s = sequence_run.prepare(); !s) {
        std::cerr << "fast_bench: repair failed: " << s.message() << "\n";
        return 1;
      }
      pm::Simplification sequence;
      const auto start = Clock::now();
      if (pm::Status s = sequence_run.run(sequence); !s) {
        std::cerr << "fast_bench: the collapse sequence failed: " << s.message() << "\n";
        return 1;
      }
      loop_times.push_back(milliseconds_since(start));
      double ms = 0;
      meshopt_level(original, static_cast<std::size_t>(kSpeedTarget * original.face_count()), ms);
      meshopt_times.push_back(ms);
    }
    for (const double target : kTargets) {
      const auto faces = static_cast<std::size_t>(target * original.face_count());
      double ms;
      const Distance p = measure(original, level_at_most(progressive, faces));
      const Distance m = measure(original, meshopt_level(original, faces, ms));
      quality << "| " << name << " | " << significant(100 * target) << "% | "
              << with_thousands(faces) << " | " << significant(p.hausdorff) << " | "
              << significant(m.hausdorff) << " | " << significant(p.rms) << " | "
              << significant(m.rms) << " | " << ratio(p.hausdorff, m.hausdorff) << " | "
              << ratio(p.rms, m.rms) << " |\n";
      if (p.hausdorff > 0 && p.rms > 0 && m.hausdorff > 0 && m.rms > 0) {
        log_h += std::log(p.hausdorff / m.hausdorff);
        log_rms += std::log(p.rms / m.rms);
        worst_h = std::max(worst_h, p.hausdorff / m.hausdorff);
        worst_rms = std::max(worst_rms, p.rms / m.rms);
        ++points;
      }
    }
    const double meshopt_median = median(meshopt_times);
    const double loop_median = median(loop_times);
    speed << "| " << name << " | " << with_thousands(original.face_count()) << " | "
          << significant(median(encode_times)) << " | " << significant(loop_median)
          << (sequence_run.repaired() ? " (repaired first)" : "") << " | "
          << significant(meshopt_median) << " | " << ratio(loop_median, meshopt_median) << " |\n";
  }

  std::ofstream md(out_path);
  md << "# The one collapse loop against meshoptimizer" << (schroeder ? ", Schroeder's metric" : "")
     << (loop_meshes ? " on meshes made by Loop subdivision"
         : fast      ? ", without its measured distance (`--fast`)"
                     : "")
     << "\n\n"
     << "Generated by `tests/bench/run_fast.sh" << (schroeder ? " --metric schroeder" : "")
     << (loop_meshes ? " --loop-meshes"
         : fast      ? " --fast"
                     : "")
     << "` (issue 25; pm_bench_fast, tests/bench/fast_bench.cpp).\n\n"
     << (loop_meshes
             ? "Issue 25's speed line on the 1.6M- and 4.4M-face Loop meshes (nefertiti after "
               "two Loop steps, the bunny after three: `pm_make_big_mesh`, as run_scale.sh "
               "makes them), with the loop pmenc runs on them by default: from a million "
               "faces, without the measured distance (`--fast-from`).\n\n"
             : "")
     << pm::bench::run_description(PM_BENCH_SOURCE_DIR)
     << "- load average at the end: " << pm::bench::command_output("cut -d' ' -f1-3 /proc/loadavg")
     << "\n- peer: meshoptimizer " << MESHOPTIMIZER_VERSION / 1000 << "."
     << MESHOPTIMIZER_VERSION % 1000 / 10 << "\n\n"
     << "Errors: Hausdorff (H) and RMS distance between each level and the input, both ways, by "
        "`pm::measure_surface_distance`, in percent of the bounding-box diagonal. pmenc: "
        "`pm::encode`, the one collapse loop (since issue 25), "
     << (fast ? "without its measured distance (`EncodeOptions::fast`, pmenc `--fast`, and "
                "pmenc's default from a million faces), "
              : "")
     << metric_name
     << " metric, geometry only, levels of at most the target's faces; meshopt: "
        "`meshopt_simplify` to the target, no error limit. The former default loop's levels "
        "(commit 3cb92db) against the same: quality.md's section \"Issue 25\".\n\n"
     << "## Quality\n\n"
     << quality.str() << "\npmenc/meshopt over the " << points
     << " points: Hausdorff geometric mean " << significant(points ? std::exp(log_h / points) : 0)
     << ", largest " << significant(worst_h) << "; RMS geometric mean "
     << significant(points ? std::exp(log_rms / points) : 0) << ", largest "
     << significant(worst_rms) << ".\n\n## Speed\n\n"
     << "One thread. encode: the whole `pm::encode` (repair, the collapse sequence down to "
        "the base mesh, the .pm's streams); loop: the collapse sequence alone, as `pm::encode` "
        "runs it (`simplify_direct` on an input that needs no repair; \"repaired first\": "
        "`simplify` on pmenc's repair of the input, made before the timer starts, "
        "tests/bench/sequence_timing.h); meshopt: "
        "`meshopt_simplify` to 1% of the faces; each a median of "
     << runs << " runs.\n\n"
     << speed.str();
  std::cerr << "wrote " << out_path << "\n";
  return 0;
}
