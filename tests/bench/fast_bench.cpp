// The fast collapse loop against the default loop and meshopt_simplify (issue 25), in one
// process: for each mesh, the surface distance of the levels at 50%, 10% and 2% of the faces
// (the measure of quality_bench: pm::measure_surface_distance, both ways), and the time of
// pm::encode with the fast loop on one thread (the whole .pm, every level) against
// meshopt_simplify's time to 1% of the faces, medians of --runs runs each. With --metric
// schroeder, both loops run Schroeder's metric (fast_schroeder.md, run_fast.sh --metric
// schroeder), and the default loop's encode is timed as often as the fast loop's.
//
//   pm_bench_fast MESH_DIR [--out fast.md] [--runs 5] [--metric quadric|schroeder]
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
#include "simplify/fast_simplifier.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using pm::bench::significant;
using pm::bench::with_thousands;

namespace {

constexpr double kTargets[] = {0.5, 0.1, 0.02};
constexpr double kSpeedTarget = 0.01;

double milliseconds_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
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

}  // namespace

int main(int argc, char** argv) {
  pm::Metric metric = pm::Metric::kQuadric;
  if (!take_metric(argc, argv, metric)) {
    std::cerr << "pm_bench_fast: --metric is quadric or schroeder\n";
    return 2;
  }
  const bool schroeder = metric == pm::Metric::kSchroeder;
  const char* metric_name = schroeder ? "Schroeder's" : "quadric";
  pm::bench::MeshDirArguments arguments{"", schroeder ? "fast_schroeder.md" : "fast.md", 5};
  if (!pm::bench::parse_mesh_dir_arguments(argc, argv, "pm_bench_fast", arguments)) return 2;
  const auto& [dir, out_path, runs] = arguments;
  const std::vector<fs::path> paths = pm::bench::mesh_files({dir});

  std::ostringstream quality, speed;
  quality << "| mesh | target | faces | default H % | fast H % | meshopt H % | default RMS % | "
             "fast RMS % | meshopt RMS % | fast/default H | fast/default RMS | fast/meshopt H | "
             "fast/meshopt RMS |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  speed << "| mesh | faces | default encode ms" << (schroeder ? "" : " (1 run)")
        << " | fast encode ms | fast loop ms | meshopt to 1% ms | fast loop / meshopt |"
        << (schroeder ? " fast/default encode |\n" : "\n")
        << "|---|---:|---:|---:|---:|---:|---:|" << (schroeder ? "---:|\n" : "\n");
  // Over the meshes and targets: the ratios' geometric means and largest values.
  double log_h = 0, log_rms = 0, worst_h = 0, worst_rms = 0;
  int points = 0;
  for (const fs::path& path : paths) {
    pm::Mesh original;
    if (!pm::bench::read_listed_mesh(path, "fast_bench", original)) continue;
    const std::string name = path.filename().string();
    pm::ProgressiveMesh slow, fast;
    double slow_ms = 0, fast_ms = 0;
    if (!encode(original, metric, false, slow, slow_ms)) continue;
    std::vector<double> slow_times{slow_ms}, fast_times, meshopt_times;
    std::vector<double> loop_times;
    for (int r = 0; r < runs; ++r) {
      if (!encode(original, metric, true, fast, fast_ms)) return 1;
      fast_times.push_back(fast_ms);
      if (schroeder && r > 0) {
        if (!encode(original, metric, false, slow, slow_ms)) return 1;
        slow_times.push_back(slow_ms);
      }
      // The collapse sequence alone, on a manifold input that needs no repair.
      pm::EncodeOptions options;
      options.metric = metric;
      options.threads = 1;
      pm::FastSimplification sequence;
      const auto start = Clock::now();
      if (pm::simplify_fast_direct(original, options, sequence))
        loop_times.push_back(milliseconds_since(start));
      double ms = 0;
      meshopt_level(original, static_cast<std::size_t>(kSpeedTarget * original.face_count()), ms);
      meshopt_times.push_back(ms);
    }
    for (const double target : kTargets) {
      const auto faces = static_cast<std::size_t>(target * original.face_count());
      double ms;
      const Distance d = measure(original, level_at_most(slow, faces));
      const Distance f = measure(original, level_at_most(fast, faces));
      const Distance m = measure(original, meshopt_level(original, faces, ms));
      quality << "| " << name << " | " << significant(100 * target) << "% | "
              << with_thousands(faces) << " | " << significant(d.hausdorff) << " | "
              << significant(f.hausdorff) << " | " << significant(m.hausdorff) << " | "
              << significant(d.rms) << " | " << significant(f.rms) << " | " << significant(m.rms)
              << " | " << ratio(f.hausdorff, d.hausdorff) << " | " << ratio(f.rms, d.rms) << " | "
              << ratio(f.hausdorff, m.hausdorff) << " | " << ratio(f.rms, m.rms) << " |\n";
      if (d.hausdorff > 0 && d.rms > 0 && f.hausdorff > 0 && f.rms > 0) {
        log_h += std::log(f.hausdorff / d.hausdorff);
        log_rms += std::log(f.rms / d.rms);
        worst_h = std::max(worst_h, f.hausdorff / d.hausdorff);
        worst_rms = std::max(worst_rms, f.rms / d.rms);
        ++points;
      }
    }
    const double fast_median = median(fast_times), meshopt_median = median(meshopt_times);
    const double loop_median = loop_times.empty() ? 0 : median(loop_times);
    const double slow_median = median(slow_times);
    speed << "| " << name << " | " << with_thousands(original.face_count()) << " | "
          << significant(slow_median) << " | " << significant(fast_median) << " | "
          << (loop_times.empty() ? "n/a (repaired first)" : significant(loop_median)) << " | "
          << significant(meshopt_median) << " | "
          << (loop_times.empty() ? "n/a" : ratio(loop_median, meshopt_median)) << " |";
    if (schroeder) speed << " " << ratio(fast_median, slow_median) << " |";
    speed << "\n";
  }

  std::ofstream md(out_path);
  md << "# The fast loop against the default loop and meshoptimizer"
     << (schroeder ? ", Schroeder's metric" : "") << "\n\n"
     << "Generated by `tests/bench/run_fast.sh" << (schroeder ? " --metric schroeder" : "")
     << "` (issue 25; pm_bench_fast, tests/bench/fast_bench.cpp).\n\n"
     << pm::bench::run_description(PM_BENCH_SOURCE_DIR)
     << "- load average at the end: " << pm::bench::command_output("cut -d' ' -f1-3 /proc/loadavg")
     << "\n- peer: meshoptimizer " << MESHOPTIMIZER_VERSION / 1000 << "."
     << MESHOPTIMIZER_VERSION % 1000 / 10 << "\n\n"
     << "Errors: Hausdorff (H) and RMS distance between each level and the input, both ways, by "
        "`pm::measure_surface_distance`, in percent of the bounding-box diagonal. default: "
        "`pm::encode` with the default loop ("
     << metric_name << " metric, measured error); fast: `pm::encode` with "
        "`EncodeOptions::fast` ("
     << metric_name << " metric); both geometry only, levels of at most the target's faces; "
        "meshopt: `meshopt_simplify` to the target, no error limit.\n\n"
     << "## Quality\n\n"
     << quality.str() << "\nfast/default over the " << points
     << " points: Hausdorff geometric mean "
     << significant(points ? std::exp(log_h / points) : 0) << ", largest "
     << significant(worst_h) << "; RMS geometric mean "
     << significant(points ? std::exp(log_rms / points) : 0) << ", largest "
     << significant(worst_rms) << ".\n\n## Speed\n\n"
     << "One thread. fast encode: the whole `pm::encode` (repair, the collapse sequence down to "
        "the base mesh, the .pm's streams), median of "
     << runs << " runs; fast loop: the collapse sequence alone (`simplify_fast_direct`, on an "
        "input that needs no repair), median of " << runs << " runs; meshopt: `meshopt_simplify` to 1% of the faces, median of " << runs
     << " runs; the default loop's encode "
     << (schroeder ? "a median of as many runs" : "once, for scale") << ".\n\n"
     << speed.str();
  std::cerr << "wrote " << out_path << "\n";
  return 0;
}
