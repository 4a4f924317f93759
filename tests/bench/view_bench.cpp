// pm_bench_view: the view-dependent refinement benchmark of issue 7. A camera orbits the
// ~1M-face mesh (the Stanford bunny after two steps of Loop subdivision, as run_runtime.sh
// makes it) in --frames steps; at each frame it times
//
//   - the incremental update, pm::SelectiveRefinement::update_view (Hoppe 1997, "View-
//     dependent refinement of progressive meshes", §5: the previous frame's mesh adapted to
//     the new viewpoint), and
//   - the rebuild from the base mesh, pm::SelectiveRefinement::set_view (the same criteria
//     applied top-down from the base mesh),
//
// and checks that both give the same mesh: the same set of applied splits, so the same faces.
// The orbit is run --runs times; each run gives a mean and a 99th percentile per frame, and
// the table shows the median over runs. Markdown on stdout (and --out FILE), progress on
// stderr. See README.md here, "View-dependent refinement".
//
//   pm_bench_view --pm FILE [--frames N] [--runs N] [--pixel-error P] [--out FILE]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bench_report.h"
#include "pm/pm_codec.h"
#include "pm/selective_refinement.h"

namespace {

using Clock = std::chrono::steady_clock;
using pm::bench::median;
using pm::bench::significant;
using pm::bench::with_thousands;

constexpr double kPi = 3.14159265358979323846;

[[noreturn]] void die(const std::string& message) {
  std::fprintf(stderr, "pm_bench_view: %s\n", message.c_str());
  std::exit(1);
}

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Nearest rank: the smallest value with at least fraction p of the values at or below it.
double percentile(std::vector<double> values, double p) {
  std::sort(values.begin(), values.end());
  const std::size_t rank = static_cast<std::size_t>(std::ceil(p * values.size()));
  return values[std::min(values.size() - 1, rank == 0 ? 0 : rank - 1)];
}

// The load average over 1, 5 and 15 minutes ("?" where /proc/loadavg cannot be read).
std::string load_average() {
  std::ifstream file("/proc/loadavg");
  std::string a, b, c;
  if (!(file >> a >> b >> c)) return "?";
  return a + " " + b + " " + c;
}

double mean(const std::vector<double>& values) {
  double sum = 0;
  for (double v : values) sum += v;
  return values.empty() ? 0 : sum / values.size();
}

struct Settings {
  std::string pm_path, out;
  int frames = 200, runs = 3;
  double pixel_error = 1;
};

// Per run: what each frame cost, and what it did.
struct Run {
  std::vector<double> incremental_ms, rebuild_ms;
  double first_update_ms = 0;
  std::size_t equal_frames = 0;
  std::vector<double> faces, operations, evaluations;
};

}  // namespace

int main(int argc, char** argv) {
  Settings settings;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--pm" && has_value)
      settings.pm_path = argv[++i];
    else if (arg == "--frames" && has_value)
      settings.frames = std::atoi(argv[++i]);
    else if (arg == "--runs" && has_value)
      settings.runs = std::atoi(argv[++i]);
    else if (arg == "--pixel-error" && has_value)
      settings.pixel_error = std::atof(argv[++i]);
    else if (arg == "--out" && has_value)
      settings.out = argv[++i];
    else
      die("usage: pm_bench_view --pm FILE [--frames N] [--runs N] [--pixel-error P] [--out FILE]");
  }
  if (settings.pm_path.empty() || settings.frames < 2 || settings.runs < 1 ||
      !(settings.pixel_error > 0))
    die("usage: pm_bench_view --pm FILE [--frames N >= 2] [--runs N >= 1] [--pixel-error P > 0] "
        "[--out FILE]");

  std::ifstream file(settings.pm_path, std::ios::binary);
  if (!file) die("cannot read " + settings.pm_path);
  const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  pm::ProgressiveMesh pm;
  if (pm::Status s = pm::read_pm(bytes, pm); !s) die(settings.pm_path + ": " + s.message());

  auto start = Clock::now();
  pm::SelectiveRefinement incremental(pm);
  const double construction_ms = ms_since(start);
  pm::SelectiveRefinement rebuild(pm);
  std::fprintf(stderr, "%zu splits; hierarchy built in %.0f ms\n", pm.split_count(), construction_ms);

  // The orbit: around the model's box centre at twice its bounding radius, a little above it,
  // looking at the centre, so that the model fills most of a 1920 x 1080 view.
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (std::size_t i = 0; i < pm.positions.size(); ++i) {
    lo[i % 3] = std::min(lo[i % 3], double(pm.positions[i]));
    hi[i % 3] = std::max(hi[i % 3], double(pm.positions[i]));
  }
  const double c[3] = {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  const double radius = 0.5 * std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) +
                                        (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                        (hi[2] - lo[2]) * (hi[2] - lo[2]));
  auto camera_at = [&](int frame) {
    const double angle = 2 * kPi * frame / settings.frames;
    pm::ViewCamera camera;
    camera.eye = {c[0] + 2 * radius * std::cos(angle), c[1] + 0.5 * radius,
                  c[2] + 2 * radius * std::sin(angle)};
    camera.target = {c[0], c[1], c[2]};
    camera.up = {0, 1, 0};
    camera.fov_degrees = 60;
    camera.viewport_height = 1080;
    camera.viewport_width = 1920;
    return camera;
  };
  pm::ViewOptions options;
  options.pixel_error = settings.pixel_error;

  const std::string load_before = load_average();
  std::vector<Run> runs(settings.runs);
  for (int r = 0; r < settings.runs; ++r) {
    Run& run = runs[r];
    incremental.reset();
    start = Clock::now();
    if (!incremental.update_view(camera_at(0), options).ok()) die("update_view failed");
    run.first_update_ms = ms_since(start);
    // Frames 1 .. frames: a whole orbit, back to the first camera.
    for (int f = 1; f <= settings.frames; ++f) {
      const pm::ViewCamera camera = camera_at(f);
      pm::UpdateStats stats;
      start = Clock::now();
      const pm::Status updated = incremental.update_view(camera, options, {}, &stats);
      run.incremental_ms.push_back(ms_since(start));
      start = Clock::now();
      const pm::Status rebuilt = rebuild.set_view(camera, options);
      run.rebuild_ms.push_back(ms_since(start));
      if (!updated || !rebuilt) die("update_view or set_view failed");
      run.equal_frames += incremental.applied_splits() == rebuild.applied_splits() &&
                          incremental.face_count() == rebuild.face_count();
      run.faces.push_back(double(incremental.face_count()));
      run.operations.push_back(double(stats.splits + stats.collapses));
      run.evaluations.push_back(double(stats.evaluations));
    }
    std::fprintf(stderr, "run %d: incremental mean %.3f ms, rebuild mean %.3f ms, %zu/%d frames equal\n",
                 r + 1, mean(run.incremental_ms), mean(run.rebuild_ms), run.equal_frames,
                 settings.frames);
  }

  auto over_runs = [&](auto statistic) {
    std::vector<double> values;
    for (const Run& run : runs) values.push_back(statistic(run));
    return median(values);
  };
  const double inc_mean = over_runs([](const Run& r) { return mean(r.incremental_ms); });
  const double inc_p99 = over_runs([](const Run& r) { return percentile(r.incremental_ms, 0.99); });
  const double inc_median = over_runs([](const Run& r) { return median(r.incremental_ms); });
  const double inc_max = over_runs([](const Run& r) {
    return *std::max_element(r.incremental_ms.begin(), r.incremental_ms.end());
  });
  const double re_mean = over_runs([](const Run& r) { return mean(r.rebuild_ms); });
  const double re_p99 = over_runs([](const Run& r) { return percentile(r.rebuild_ms, 0.99); });
  const double re_median = over_runs([](const Run& r) { return median(r.rebuild_ms); });
  const double re_max = over_runs([](const Run& r) {
    return *std::max_element(r.rebuild_ms.begin(), r.rebuild_ms.end());
  });
  std::size_t equal = 0, total = 0;
  for (const Run& run : runs) equal += run.equal_frames, total += settings.frames;
  const Run& first = runs.front();
  const double faces_min = *std::min_element(first.faces.begin(), first.faces.end());
  const double faces_max = *std::max_element(first.faces.begin(), first.faces.end());

  const std::string load_after = load_average();
  std::ostringstream md;
  md << "# View-dependent refinement: incremental update against rebuilding (issue 7)\n\n"
     << pm::bench::run_description(PM_BENCH_SOURCE_DIR)
     << "- load average (1, 5, 15 min): " << load_before << " before the orbits, " << load_after
     << " after (a shared machine: other work is in every time; the two are timed in turn, "
        "frame by frame, so it weighs on both)\n\n"
     << "Input: `" << settings.pm_path.substr(settings.pm_path.find_last_of('/') + 1) << "`, "
     << with_thousands(pm.split_count()) << " vertex splits, "
     << with_thousands(pm.base_face_count() + pm.splits.size() * 2 -
                       std::count_if(pm.splits.begin(), pm.splits.end(),
                                     [](const pm::VertexSplit& s) { return s.new_face_count() == 1; }))
     << " faces at full detail. Camera: " << settings.frames
     << " frames of one orbit around the model at twice its bounding radius, 1920 x 1080 "
        "pixels, 60 degrees vertical field of view, tolerance "
     << significant(settings.pixel_error) << " pixel; frustum and back-face culling on. "
     << "Median over " << settings.runs << " orbits of each orbit's statistic.\n\n"
     << "| per frame | mean | p99 | median | max |\n|---|---:|---:|---:|---:|\n"
     << "| incremental: `update_view` | " << significant(inc_mean) << " ms | "
     << significant(inc_p99) << " ms | " << significant(inc_median) << " ms | "
     << significant(inc_max) << " ms |\n"
     << "| rebuild from the base mesh: `set_view` | " << significant(re_mean) << " ms | "
     << significant(re_p99) << " ms | " << significant(re_median) << " ms | "
     << significant(re_max) << " ms |\n"
     << "| rebuild / incremental | " << significant(re_mean / inc_mean) << "x | "
     << significant(re_p99 / inc_p99) << "x | " << significant(re_median / inc_median)
     << "x | |\n\n"
     << "- Same mesh: " << equal << " of " << total
     << " frames give the same applied splits (hence the same faces) incrementally and from "
        "the base mesh.\n"
     << "- Active mesh: " << with_thousands(std::size_t(mean(first.faces))) << " faces on average ("
     << with_thousands(std::size_t(faces_min)) << " to " << with_thousands(std::size_t(faces_max))
     << "); " << significant(mean(first.operations))
     << " splits and collapses per frame, forced ones included; "
     << significant(mean(first.evaluations)) << " criteria evaluated per frame.\n"
     << "- First update (the whole boundary of the wanted set evaluated, the mesh built): "
     << significant(over_runs([](const Run& r) { return r.first_update_ms; })) << " ms. "
     << "Hierarchy, dependencies and bounds from the `.pm`: " << significant(construction_ms)
     << " ms; the object holds " << significant(incremental.memory_bytes() / 1048576.0)
     << " MB.\n";
  const std::string report = md.str();
  std::fputs(report.c_str(), stdout);
  if (!settings.out.empty()) {
    std::ofstream out(settings.out);
    out << report;
    if (!out) die("cannot write " + settings.out);
  }
  return equal == total ? 0 : 1;
}
