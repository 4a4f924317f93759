// The texture-coordinate benchmark (issue 4): how far, in UV space, each simplifier's LOD
// puts the texture from where the original has it, at the same face count.
//
// For each mesh with texture coordinates and each target fraction of its faces:
//   pmenc             pm::encode with default options (the one collapse loop, quadric
//                     metric, attributes kept: seams and material borders held, the
//                     attribute error in the cost, Hoppe 1999), then pm::extract_level of the finest
//                     level with at most the target's faces
//   pmenc --fast      the same without the loop's measured distance (pmenc's default on
//                     meshes of a million faces or more, --fast-from)
//   meshopt_simplify  meshoptimizer 0.18 on the seam-split vertex buffer a glTF exporter
//                     writes (meshopt_seams.h), no options, no error limit
// Each LOD is measured by the same code: the UV error (uv_error.h: Metro-style samples of
// the LOD, each with its interpolated UV, against the original's UV at the closest point;
// RMS, 95th percentile and maximum), the faces that mix two UV charts of the original, and
// the geometric distance (pm::measure_surface_distance, as in quality.md). See README.md.
#include <meshoptimizer.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "bench_report.h"
#include "meshopt_seams.h"
#include "pm/encoder.h"
#include "pm/lod.h"
#include "pm/mesh.h"
#include "pm/mesh_io.h"
#include "pm/surface_distance.h"
#include "uv_error.h"

namespace {

namespace fs = std::filesystem;
using pm::bench::significant;
using pm::bench::with_thousands;
using Clock = std::chrono::steady_clock;

// As in quality_bench.cpp: a method that ends more than this fraction above its face target
// has stalled.
constexpr double kStallTolerance = 0.02;

enum class Method { kPmenc, kFast, kMeshopt };
constexpr Method kMethods[] = {Method::kPmenc, Method::kFast, Method::kMeshopt};
constexpr std::size_t kMethodCount = sizeof kMethods / sizeof kMethods[0];
constexpr std::size_t kMeshoptIndex = 2;
const char* method_name(Method method) {
  if (method == Method::kPmenc) return "pmenc";
  if (method == Method::kFast) return "pmenc --fast";
  return "meshopt_simplify (seam-split)";
}
const char* method_slug(Method method) {
  if (method == Method::kPmenc) return "pmenc";
  if (method == Method::kFast) return "pmenc-fast";
  return "meshopt";
}

struct Settings {
  std::vector<std::string> inputs;
  std::vector<double> targets = {0.1, 0.02, 0.01};
  std::string out_path;
  std::string dump_directory;  // --dump: every LOD as OBJ with its UVs (render_spot.sh)
  pm::bench::UvErrorOptions uv;
};

struct Outcome {
  bool available = false;
  std::string note;
  std::size_t faces = 0;
  bool stalled = false;
  pm::bench::UvError uv;
  std::size_t chart_crossing_faces = 0;
  double hausdorff_percent = 0, rms_percent = 0;
  double milliseconds = 0;
};

struct TargetRow {
  double fraction = 0;
  std::size_t target_faces = 0;
  Outcome outcomes[kMethodCount];  // kMethods order
};

struct MeshReport {
  std::string name;
  std::size_t faces = 0, vertices = 0, uvs = 0, charts = 0, seam_vertices = 0;
  double encode_ms = 0, fast_encode_ms = 0;
  std::vector<TargetRow> rows;
};

double milliseconds_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// --- What the original's texture layout is, and whether a LOD tears it. ---

// LOD faces whose corners' UVs belong to two charts of the original (or are not the
// original's values): the texture is smeared across them, a seam not held.
std::size_t chart_crossing_faces(const pm::Mesh& lod, const pm::bench::UvCharts& charts) {
  std::size_t crossing = 0;
  for (std::size_t f = 0; f < lod.face_count(); ++f)
    crossing += charts.chart_of_face_of(lod, f) == pm::bench::UvCharts::kNone;
  return crossing;
}

std::size_t seam_vertex_count(const pm::Mesh& mesh) {
  std::vector<std::vector<std::pair<float, float>>> uvs(mesh.vertex_count());
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const uint32_t id = mesh.uv_indices[i];
    if (id == pm::kNoAttribute) continue;
    auto& list = uvs[mesh.triangles[i]];
    const std::pair<float, float> uv = {mesh.uvs[2 * std::size_t(id)],
                                        mesh.uvs[2 * std::size_t(id) + 1]};
    if (std::find(list.begin(), list.end(), uv) == list.end()) list.push_back(uv);
  }
  return std::count_if(uvs.begin(), uvs.end(), [](const auto& list) { return list.size() > 1; });
}

// --- One mesh ---

// "010" for 10%, "002" for 2%, "0.5" for 0.5%: the file names of --dump and the images.
std::string percent_tag(double fraction) {
  const double percent = 100 * fraction;
  if (std::fabs(percent - std::round(percent)) < 1e-9) {
    char text[16];
    std::snprintf(text, sizeof text, "%03ld", std::lround(percent));
    return text;
  }
  return significant(percent);
}

Outcome measure(const pm::Mesh& original, const pm::Mesh& lod, std::size_t target_faces,
                const pm::bench::UvCharts& charts, const Settings& settings) {
  Outcome outcome;
  outcome.faces = lod.face_count();
  outcome.stalled = double(outcome.faces) > double(target_faces) * (1 + kStallTolerance);
  std::string message;
  if (!pm::bench::measure_uv_error(original, lod, settings.uv, outcome.uv, &message)) {
    outcome.note = message;
    return outcome;
  }
  outcome.chart_crossing_faces = chart_crossing_faces(lod, charts);
  outcome.available = pm::bench::distance_percent(original, lod, outcome.hausdorff_percent,
                                                  outcome.rms_percent, outcome.note);
  return outcome;
}

void dump(const Settings& settings, const fs::path& mesh_path, double fraction, Method method,
          const pm::Mesh& lod) {
  const fs::path path =
      fs::path(settings.dump_directory) / (mesh_path.stem().string() + "_" + percent_tag(fraction) +
                                           "_" + method_slug(method) + ".obj");
  std::string bytes;
  if (pm::Status s = pm::write_mesh_to_memory(lod, pm::MeshFormat::kObj, bytes); !s) {
    std::cerr << "pm_bench_uv: cannot write " << path.string() << ": " << s.message() << "\n";
    return;
  }
  std::ofstream(path, std::ios::binary) << bytes;
}

// The report of one mesh; none when it cannot be read or encoded, or has no UVs (no_uvs).
std::optional<MeshReport> run_mesh(const fs::path& path, const Settings& settings, bool& no_uvs) {
  no_uvs = false;
  pm::Mesh original;
  if (pm::Status s = pm::read_mesh(path.string(), original); !s) {
    std::cerr << "pm_bench_uv: " << path.string() << ": " << s.message() << " (skipped)\n";
    return std::nullopt;
  }
  if (!original.has_uvs()) {
    no_uvs = true;
    std::cerr << "[uv] " << path.filename().string() << ": no texture coordinates (skipped)\n";
    return std::nullopt;
  }
  MeshReport report;
  report.name = path.filename().string();
  report.faces = original.face_count();
  report.vertices = original.vertex_count();
  report.uvs = original.uv_count();
  report.seam_vertices = seam_vertex_count(original);
  const pm::bench::UvCharts charts = pm::bench::uv_charts(original);
  report.charts = charts.count;
  std::cerr << "[uv] " << report.name << ": " << report.faces << " faces, " << report.charts
            << " UV charts\n";

  pm::ProgressiveMesh progressive, fast;
  for (bool with_fast : {false, true}) {
    pm::EncodeOptions options;
    options.fast = with_fast;
    const auto start = Clock::now();
    if (pm::Status s = pm::encode(original, options, with_fast ? fast : progressive); !s) {
      std::cerr << "pm_bench_uv: " << report.name << ": encode" << (with_fast ? " --fast" : "")
                << " failed: " << s.message() << "\n";
      return std::nullopt;
    }
    (with_fast ? report.fast_encode_ms : report.encode_ms) = milliseconds_since(start);
  }

  for (double fraction : settings.targets) {
    TargetRow row;
    row.fraction = fraction;
    row.target_faces =
        std::max<std::size_t>(1, std::size_t(std::llround(fraction * double(report.faces))));
    for (std::size_t m = 0; m < kMethodCount; ++m) {
      const Method method = kMethods[m];
      pm::Mesh lod;
      double milliseconds = 0;
      if (method != Method::kMeshopt) {
        const pm::ProgressiveMesh& from = method == Method::kFast ? fast : progressive;
        lod = pm::extract_level(from, pm::bench::level_at_most_faces(from, row.target_faces));
        milliseconds = method == Method::kFast ? report.fast_encode_ms : report.encode_ms;
      } else {
        pm::bench::MeshoptLod meshopt =
            pm::bench::meshopt_seam_split_lod(original, row.target_faces);
        lod = std::move(meshopt.lod);
        milliseconds = meshopt.milliseconds;
      }
      Outcome& outcome = row.outcomes[m];
      outcome = measure(original, lod, row.target_faces, charts, settings);
      outcome.milliseconds = milliseconds;
      if (!settings.dump_directory.empty()) dump(settings, path, fraction, method, lod);
      std::cerr << "[uv]   " << report.name << " " << row.target_faces
                << " faces: " << method_name(method) << " -> " << outcome.faces
                << " faces, UV same chart RMS " << outcome.uv.same_chart.rms << " p95 "
                << outcome.uv.same_chart.p95 << " max " << outcome.uv.same_chart.max
                << "; nearest RMS " << outcome.uv.nearest.rms << " p95 " << outcome.uv.nearest.p95
                << ", crossing " << outcome.chart_crossing_faces << ", seam band "
                << outcome.uv.seam_band << "/" << outcome.uv.samples << ", ties "
                << outcome.uv.ties_resolved << ", chartless " << outcome.uv.chartless << ", H "
                << outcome.hausdorff_percent << "%"
                << (outcome.note.empty() ? "" : " (" + outcome.note + ")") << "\n";
    }
    report.rows.push_back(std::move(row));
  }
  return report;
}

// --- The report ---

// A setting as written on the command line: 10, 1e-06, 0.05.
std::string shortest(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

// One verdict: pmenc's RMS and p95 no larger than meshopt's.
struct Verdict {
  bool counted = false, holds = false;
  std::string cell;
};

Verdict compare(const Outcome& ours, const Outcome& peer,
                pm::bench::UvStatistics pm::bench::UvError::*measure) {
  Verdict verdict;
  if (!ours.available || !peer.available) {
    verdict.cell = "n/a";
    return verdict;
  }
  if (peer.stalled) {
    verdict.cell = "meshopt stalled at " + with_thousands(peer.faces);
    return verdict;
  }
  const pm::bench::UvStatistics& a = ours.uv.*measure;
  const pm::bench::UvStatistics& b = peer.uv.*measure;
  verdict.counted = true;
  verdict.holds = !ours.stalled && a.rms <= b.rms && a.p95 <= b.p95;
  verdict.cell = std::string(verdict.holds ? "yes" : "**no**") + ": RMS " +
                 pm::bench::distinguishable_pair(a.rms, b.rms) + ", p95 " +
                 pm::bench::distinguishable_pair(a.p95, b.p95);
  return verdict;
}

std::string render(const std::vector<MeshReport>& reports, const Settings& settings,
                   const std::vector<std::string>& skipped) {
  std::ostringstream md;
  md << "# Texture-coordinate benchmark\n\n"
     << "Generated by `bash tests/bench/run_uv.sh` (also run by `tests/bench/run_quality.sh`); "
        "pmenc's rows are the one collapse loop's (since issue 25), **pmenc --fast** the same "
        "loop without its measured distance (pmenc's default from a million faces); "
     << "see tests/bench/README.md, \"Texture coordinates\", for what is measured and why.\n\n"
     << pm::bench::run_description(PM_BENCH_SOURCE_DIR) << "- peer: meshoptimizer "
     << MESHOPTIMIZER_VERSION / 1000 << "." << MESHOPTIMIZER_VERSION % 1000 / 10
     << ", `meshopt_simplify` on the seam-split vertex buffer (one vertex per position, UV "
        "and normal), one primitive for the whole mesh, options 0, no error limit (0.18 has no "
        "`meshopt_simplifyWithAttributes`)\n\n"
     << "**UV error**, in UV units (the texture is 1 x 1): the LOD is sampled Metro-style "
        "(every vertex once per UV it shows, and "
     << shortest(settings.uv.samples_per_original_face)
     << " points per face of the original in all, shared among the LOD's faces by area); each "
        "sample's UV, interpolated on the LOD, is compared with the original's UV at the "
        "closest point of the original surface. RMS, 95th percentile (p95) and maximum over "
        "the samples. Two rules for that closest point, the same for every method:\n\n"
     << "- **same chart**: the closest point among the original's faces of the sample's own "
        "UV chart (the chart its face's UVs come from; a face that mixes charts is measured "
        "as by *nearest*). It compares what the texture shows, and a seam that moves in 3D "
        "still counts.\n"
     << "- **nearest**: the closest point on any face; among faces tied with the nearest "
        "(within "
     << shortest(settings.uv.tie_tolerance)
     << " of the diagonal: a seam edge is as near to both charts) the one whose UV is closest. "
        "A sample a little off the surface near a seam can still find the other chart, and "
        "counts the whole distance between the charts: **seam band** counts these samples "
        "(error at least "
     << shortest(settings.uv.seam_band_threshold)
     << " on a face at a seam). They are few but dominate this RMS.\n\n"
     << "**charts crossed**: LOD faces whose corners' UVs come from two charts of the original "
        "(a seam not held: the texture is smeared across the face). **Hausdorff %, RMS %**: the "
        "geometric distance, both ways, as in quality.md. **time ms**: pmenc's is one "
        "`pm::encode` for every LOD; meshopt's is its calls for one LOD.\n\n"
     << "Pictures of spot's LODs with a checker texture: [images/](images/) (regenerated by "
        "`bash tests/bench/render_spot.sh`).\n\n";

  for (const MeshReport& report : reports) {
    md << "## " << report.name << "\n\n"
       << with_thousands(report.faces) << " faces, " << with_thousands(report.vertices)
       << " vertices, " << with_thousands(report.uvs) << " texture coordinates in " << report.charts
       << " charts, " << with_thousands(report.seam_vertices)
       << " seam vertices. pmenc encode: " << std::lround(report.encode_ms) << " ms; --fast "
       << std::lround(report.fast_encode_ms) << " ms.\n\n"
       << "| target faces | method | faces reached | UV RMS, same chart | UV p95, same chart | "
          "UV max, same chart | UV RMS, nearest | UV p95, nearest | seam band | charts "
          "crossed | Hausdorff % | RMS % | time ms |\n"
       << "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const TargetRow& row : report.rows) {
      for (std::size_t m = 0; m < kMethodCount; ++m) {
        const Outcome& o = row.outcomes[m];
        md << "| " << with_thousands(row.target_faces) << " (" << significant(100 * row.fraction)
           << "%) | " << method_name(kMethods[m]) << " | ";
        if (!o.available) {
          md << "n/a: " << o.note << " | | | | | | | | | | |\n";
          continue;
        }
        char time[32];
        std::snprintf(time, sizeof time, "%.1f", o.milliseconds);
        md << (o.stalled ? "**stalled at " + with_thousands(o.faces) + "**"
                         : with_thousands(o.faces))
           << " | " << significant(o.uv.same_chart.rms) << " | " << significant(o.uv.same_chart.p95)
           << " | " << significant(o.uv.same_chart.max) << " | " << significant(o.uv.nearest.rms)
           << " | " << significant(o.uv.nearest.p95) << " | " << with_thousands(o.uv.seam_band)
           << " of " << with_thousands(o.uv.samples) << " | "
           << with_thousands(o.chart_crossing_faces) << " | " << significant(o.hausdorff_percent)
           << " | " << significant(o.rms_percent) << " | " << time
           << (kMethods[m] != Method::kMeshopt ? " (all LODs)" : "") << " |\n";
      }
    }
    md << "\n";
  }

  // Issue 4's acceptance: pmenc's UV error no larger than meshopt's, RMS and p95.
  md << "## Summary\n\n"
     << "Is pmenc's UV error no larger than meshopt_simplify's at the same target, on both RMS "
        "and p95? Cells read \"RMS pm / meshopt, p95 pm / meshopt\". Where meshopt stalls above "
        "the target there is no comparison at the same face count.\n\n"
     << "| mesh | target faces | same chart: pmenc <= meshopt | nearest: pmenc <= meshopt | "
        "same chart: --fast <= meshopt | nearest: --fast <= meshopt |\n"
     << "|---|---:|---|---|---|---|\n";
  // [0], [1]: the default loop, same chart and nearest; [2], [3]: --fast.
  int held[4] = {}, counted[4] = {};
  for (const MeshReport& report : reports) {
    for (const TargetRow& row : report.rows) {
      const Outcome& peer = row.outcomes[kMeshoptIndex];
      const Verdict verdicts[4] = {
          compare(row.outcomes[0], peer, &pm::bench::UvError::same_chart),
          compare(row.outcomes[0], peer, &pm::bench::UvError::nearest),
          compare(row.outcomes[1], peer, &pm::bench::UvError::same_chart),
          compare(row.outcomes[1], peer, &pm::bench::UvError::nearest)};
      md << "| " << report.name << " | " << with_thousands(row.target_faces) << " ("
         << significant(100 * row.fraction) << "%)";
      for (int k = 0; k < 4; ++k) {
        md << " | " << verdicts[k].cell;
        held[k] += verdicts[k].holds;
        counted[k] += verdicts[k].counted;
      }
      md << " |\n";
    }
  }
  md << "\n**Same chart: " << held[0] << " of " << counted[0] << " hold. Nearest: " << held[1]
     << " of " << counted[1] << " hold.** With --fast: same chart " << held[2] << " of "
     << counted[2] << ", nearest " << held[3] << " of " << counted[3] << ".\n";
  if (!skipped.empty()) {
    md << "\nMeshes without texture coordinates, not measured:";
    for (const std::string& name : skipped) md << " " << name;
    md << ".\n";
  }
  return md.str();
}

// --- Command line ---

const char kUsage[] =
    "usage: pm_bench_uv [MESH_OR_DIRECTORY...] [--targets 0.1,0.02,0.01] [--out FILE]\n"
    "                   [--dump DIRECTORY] [--tie-tolerance T] [--samples-per-face N]\n"
    "Simplifies each mesh with texture coordinates (default: ../shared/meshes and\n"
    "samples/textured.obj) to each target fraction of its faces with pmenc and with\n"
    "meshopt_simplify on the seam-split vertex buffer, measures the UV error of every LOD\n"
    "with the same code, and prints a markdown report (also written to FILE with --out).\n"
    "--dump writes every LOD to DIRECTORY as OBJ (MESH_PCT_METHOD.obj). Progress: stderr.\n";

bool parse_positive(const char* text, double& value) {
  char* end = nullptr;
  value = std::strtod(text, &end);
  return *text != '\0' && *end == '\0' && value > 0 && std::isfinite(value);
}

bool parse_arguments(int argc, char** argv, Settings& settings) {
  for (int i = 1; i < argc; ++i) {
    const std::string argument = argv[i];
    const bool has_value = i + 1 < argc;
    if (argument == "--help" || argument == "-h") {
      std::cout << kUsage;
      std::exit(0);
    } else if (argument == "--targets" && has_value) {
      if (!pm::bench::parse_targets(argv[++i], settings.targets)) {
        std::cerr << "pm_bench_uv: --targets wants fractions in (0, 1], e.g. 0.1,0.02\n";
        return false;
      }
    } else if (argument == "--out" && has_value) {
      settings.out_path = argv[++i];
    } else if (argument == "--dump" && has_value) {
      settings.dump_directory = argv[++i];
      fs::create_directories(settings.dump_directory);
    } else if (argument == "--tie-tolerance" && has_value) {
      if (!parse_positive(argv[++i], settings.uv.tie_tolerance)) {
        std::cerr << "pm_bench_uv: --tie-tolerance wants a positive number\n";
        return false;
      }
    } else if (argument == "--samples-per-face" && has_value) {
      if (!parse_positive(argv[++i], settings.uv.samples_per_original_face)) {
        std::cerr << "pm_bench_uv: --samples-per-face wants a positive number\n";
        return false;
      }
    } else if (!argument.empty() && argument[0] == '-') {
      std::cerr << "pm_bench_uv: unknown or incomplete option " << argument << "\n" << kUsage;
      return false;
    } else {
      settings.inputs.push_back(argument);
    }
  }
  if (settings.inputs.empty()) {
    settings.inputs.push_back(std::string(PM_BENCH_SOURCE_DIR) + "/../shared/meshes");
    settings.inputs.push_back(std::string(PM_BENCH_SOURCE_DIR) + "/samples/textured.obj");
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Settings settings;
  if (!parse_arguments(argc, argv, settings)) return 2;
  const std::vector<fs::path> files = pm::bench::mesh_files(settings.inputs);
  std::vector<MeshReport> reports;
  std::vector<std::string> skipped;  // no texture coordinates
  bool failed = false;
  for (const fs::path& file : files) {
    bool no_uvs = false;
    if (auto report = run_mesh(file, settings, no_uvs))
      reports.push_back(std::move(*report));
    else if (no_uvs)
      skipped.push_back(file.filename().string());
    else
      failed = true;
  }
  if (reports.empty()) {
    std::cerr << "\n*** NOTE: no mesh with texture coordinates to benchmark. Nothing measured.\n\n";
    return 3;
  }
  const std::string markdown = render(reports, settings, skipped);
  std::cout << markdown;
  if (!settings.out_path.empty()) {
    std::ofstream out(settings.out_path, std::ios::binary);
    out << markdown;
    if (!out) {
      std::cerr << "pm_bench_uv: cannot write " << settings.out_path << "\n";
      return 5;
    }
  }
  return failed ? 1 : 0;
}
