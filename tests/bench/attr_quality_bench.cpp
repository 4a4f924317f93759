// Geometric quality with attributes kept (issue 25's "Quality with attributes kept" line):
// how far each simplifier's LOD of a textured mesh lies from the original surface when its
// texture coordinates, normals and materials are kept, against meshopt_simplify on the
// seam-split vertex buffer, and what the seams cost (the same loop without attributes).
//
// For each mesh and each target fraction of its faces, one LOD per method:
//   pmenc                           pm::encode, the one collapse loop (since issue 25),
//                                   every attribute kept
//   pmenc --drop-attributes         the same loop on the geometry alone (the seams' cost)
//   pmenc --fast                    the same loop without its measured distance, every
//                                   attribute kept (pmenc's default from a million faces)
//   meshopt_simplify (seam-split)   meshoptimizer 0.18 on the buffer a glTF exporter writes
//                                   (meshopt_seams.h), options 0, no error limit
// pmenc's LOD is the finest level with at most the target's faces (pm::extract_level).
// Every LOD is measured by pm::measure_surface_distance (Metro-style, both ways, as in
// quality.md); the table gives Hausdorff and RMS in percent of the original's diagonal and
// their ratio to meshopt's at the same target. run_attr_quality.sh, attr_quality.md.
#include <meshoptimizer.h>

#include <algorithm>
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
#include "meshopt_seams.h"
#include "pm/encoder.h"
#include "pm/lod.h"
#include "pm/mesh.h"
#include "pm/mesh_io.h"

namespace {

namespace fs = std::filesystem;
using pm::bench::significant;
using pm::bench::with_thousands;
using Clock = std::chrono::steady_clock;

enum class Method { kKept, kDropped, kFast, kMeshopt };
constexpr Method kMethods[] = {Method::kKept, Method::kDropped, Method::kFast, Method::kMeshopt};
constexpr std::size_t kMethodCount = sizeof kMethods / sizeof kMethods[0];
constexpr std::size_t kMeshoptIndex = 3;

const char* method_name(Method method) {
  switch (method) {
    case Method::kKept: return "pmenc, attributes kept";
    case Method::kDropped: return "pmenc --drop-attributes";
    case Method::kFast: return "pmenc --fast, attributes kept";
    case Method::kMeshopt: return "meshopt_simplify (seam-split)";
  }
  return "";
}

struct Settings {
  std::vector<std::string> inputs;
  std::vector<double> targets = {0.5, 0.1, 0.02};
  std::string out_path;
};

struct Outcome {
  bool available = false;
  std::string note;  // why not available
  std::size_t faces = 0;
  double hausdorff_percent = 0, rms_percent = 0;
};

struct TargetRow {
  double fraction = 0;
  std::size_t target_faces = 0;
  Outcome outcomes[kMethodCount];  // kMethods order
};

struct MeshReport {
  std::string name;
  std::size_t faces = 0, vertices = 0, uvs = 0, normals = 0, materials = 0;
  double encode_seconds[kMethodCount] = {};  // one pm::encode for every LOD; meshopt: all targets
  std::vector<TargetRow> rows;
};

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

Outcome measure(const pm::Mesh& original, const pm::Mesh& lod) {
  Outcome outcome;
  outcome.faces = lod.face_count();
  outcome.available = pm::bench::distance_percent(original, lod, outcome.hausdorff_percent,
                                                  outcome.rms_percent, outcome.note);
  return outcome;
}

bool run_mesh(const fs::path& path, const Settings& settings, MeshReport& report) {
  pm::Mesh original;
  if (!pm::bench::read_listed_mesh(path, "pm_bench_attr_quality", original)) return false;
  report.name = path.filename().string();
  report.faces = original.face_count();
  report.vertices = original.vertex_count();
  report.uvs = original.uv_count();
  report.normals = original.normal_count();
  report.materials = original.material_names.size();
  for (double fraction : settings.targets) {
    TargetRow row;
    row.fraction = fraction;
    row.target_faces =
        std::max<std::size_t>(1, std::size_t(std::llround(fraction * double(report.faces))));
    report.rows.push_back(row);
  }
  for (std::size_t m = 0; m < kMethodCount; ++m) {
    const Method method = kMethods[m];
    if (method == Method::kMeshopt) {
      for (TargetRow& row : report.rows) {
        pm::bench::MeshoptLod meshopt = pm::bench::meshopt_seam_split_lod(original, row.target_faces);
        report.encode_seconds[m] += meshopt.milliseconds / 1000;
        row.outcomes[m] = measure(original, meshopt.lod);
      }
      continue;
    }
    pm::EncodeOptions options;
    options.drop_attributes = method == Method::kDropped;
    options.fast = method == Method::kFast;
    pm::ProgressiveMesh progressive;
    const auto start = Clock::now();
    if (pm::Status s = pm::encode(original, options, progressive); !s) {
      std::cerr << "pm_bench_attr_quality: " << report.name << ": " << method_name(method)
                << ": encode failed: " << s.message() << "\n";
      return false;
    }
    report.encode_seconds[m] = seconds_since(start);
    for (TargetRow& row : report.rows) {
      const pm::Mesh lod =
          pm::extract_level(progressive, pm::bench::level_at_most_faces(progressive, row.target_faces));
      row.outcomes[m] = measure(original, lod);
    }
  }
  for (const TargetRow& row : report.rows)
    for (std::size_t m = 0; m < kMethodCount; ++m) {
      const Outcome& o = row.outcomes[m];
      std::cerr << "[attr]   " << report.name << " " << row.target_faces
                << " faces: " << method_name(kMethods[m]) << " -> " << o.faces << " faces, H "
                << o.hausdorff_percent << "% RMS " << o.rms_percent << "%"
                << (o.note.empty() ? "" : " (" + o.note + ")") << "\n";
    }
  return true;
}

// "0.93×", bold when above 1 (worse than meshopt).
std::string ratio_cell(double ours, double peer) {
  if (!(peer > 0)) return "n/a";
  const double ratio = ours / peer;
  char text[32];
  std::snprintf(text, sizeof text, "%.2f×", ratio);
  return ratio > 1 ? "**" + std::string(text) + "**" : std::string(text);
}

std::string render(const std::vector<MeshReport>& reports, const std::string& load_at_start,
                   double total_seconds) {
  std::ostringstream md;
  md << "# Geometric error with attributes kept\n\n"
     << "Issue 25's \"Quality with attributes kept\" line. Generated by `bash "
        "tests/bench/run_attr_quality.sh`; see tests/bench/README.md, \"Geometric error with "
        "attributes kept\".\n\n"
     << pm::bench::run_description(PM_BENCH_SOURCE_DIR)
     << "- load average (1, 5, 15 min) at the start: " << load_at_start
     << ", at the end: " << pm::bench::command_output("cut -d' ' -f1-3 /proc/loadavg")
     << " (a shared machine); the whole run took " << std::lround(total_seconds) << " s\n"
     << "- peer: meshoptimizer " << MESHOPTIMIZER_VERSION / 1000 << "."
     << MESHOPTIMIZER_VERSION % 1000 / 10
     << ", `meshopt_simplify` on the seam-split vertex buffer (one vertex per position, UV and "
        "normal, as a glTF exporter writes it), one primitive, options 0, no error limit\n\n"
     << "Rows: **pmenc** (the one collapse loop, since issue 25) keeps texture coordinates, "
        "normals and materials; **--drop-attributes** is the same loop on the geometry alone, "
        "so the difference between the two is what the seams cost; **--fast** keeps the attributes "
        "but leaves out the measured distance (pmenc's default on meshes of a million faces or "
        "more, `--fast-from`). pmenc's LOD is the finest level with at most the target's faces. **Hausdorff %, RMS "
        "%**: `pm::measure_surface_distance` (Metro-style, 10 samples per face and every vertex, "
        "both ways, as in quality.md), in percent of the original's bounding-box diagonal. **/ "
        "meshopt**: the ratio to meshopt's at the same target, in bold when above 1.\n\n";
  for (const MeshReport& report : reports) {
    md << "## " << report.name << "\n\n"
       << with_thousands(report.faces) << " faces, " << with_thousands(report.vertices)
       << " vertices, " << with_thousands(report.uvs) << " texture coordinates, "
       << with_thousands(report.normals) << " normals, " << report.materials
       << " materials. Time for every LOD (s):";
    for (std::size_t m = 0; m < kMethodCount; ++m) {
      if (report.encode_seconds[m] <= 0) continue;
      char text[32];
      std::snprintf(text, sizeof text, "%.2f", report.encode_seconds[m]);
      md << (m ? ", " : " ") << method_name(kMethods[m]) << " " << text;
    }
    md << " (meshopt: its calls for the " << report.rows.size() << " targets).\n\n"
       << "| target faces | method | faces reached | Hausdorff % | RMS % | Hausdorff / meshopt "
          "| RMS / meshopt |\n"
       << "|---:|---|---:|---:|---:|---:|---:|\n";
    for (const TargetRow& row : report.rows) {
      const Outcome& peer = row.outcomes[kMeshoptIndex];
      for (std::size_t m = 0; m < kMethodCount; ++m) {
        const Outcome& o = row.outcomes[m];
        md << "| " << with_thousands(row.target_faces) << " (" << significant(100 * row.fraction)
           << "%) | " << method_name(kMethods[m]) << " | ";
        if (!o.available) {
          md << o.note << " | | | | |\n";
          continue;
        }
        md << with_thousands(o.faces) << " | " << significant(o.hausdorff_percent) << " | "
           << significant(o.rms_percent) << " | ";
        if (m == kMeshoptIndex || !peer.available)
          md << "1 | 1 |\n";
        else
          md << ratio_cell(o.hausdorff_percent, peer.hausdorff_percent) << " | "
             << ratio_cell(o.rms_percent, peer.rms_percent) << " |\n";
      }
    }
    md << "\n";
  }
  md << "## Summary\n\n"
     << "pmenc against meshopt_simplify on the seam-split buffer, \"Hausdorff ratio, RMS "
        "ratio\"; the acceptance wants both at most 1 with attributes kept. Without attributes: "
        "the same loop with --drop-attributes (against the same meshopt LOD). --fast: the same loop "
        "without its measured distance, attributes kept; its \"holds\" counts apart.\n\n"
     << "| mesh | target faces | attributes kept | holds | without attributes | --fast, attributes kept | --fast holds |\n"
     << "|---|---:|---|---|---|---|---|\n";
  int held = 0, counted = 0, fast_held = 0, fast_counted = 0;
  for (const MeshReport& report : reports)
    for (const TargetRow& row : report.rows) {
      const Outcome& peer = row.outcomes[kMeshoptIndex];
      const Outcome& kept = row.outcomes[0];
      const Outcome& dropped = row.outcomes[1];
      const Outcome& fast = row.outcomes[2];
      md << "| " << report.name << " | " << with_thousands(row.target_faces) << " ("
         << significant(100 * row.fraction) << "%) | ";
      if (!peer.available || !kept.available) {
        md << "n/a | n/a | | | |\n";
        continue;
      }
      const bool holds = kept.hausdorff_percent <= peer.hausdorff_percent &&
                         kept.rms_percent <= peer.rms_percent;
      ++counted;
      held += holds;
      md << ratio_cell(kept.hausdorff_percent, peer.hausdorff_percent) << ", "
         << ratio_cell(kept.rms_percent, peer.rms_percent) << " | " << (holds ? "yes" : "**no**")
         << " | ";
      if (dropped.available)
        md << ratio_cell(dropped.hausdorff_percent, peer.hausdorff_percent) << ", "
           << ratio_cell(dropped.rms_percent, peer.rms_percent);
      md << " | ";
      if (fast.available) {
        const bool fast_holds = fast.hausdorff_percent <= peer.hausdorff_percent &&
                                fast.rms_percent <= peer.rms_percent;
        ++fast_counted;
        fast_held += fast_holds;
        md << ratio_cell(fast.hausdorff_percent, peer.hausdorff_percent) << ", "
           << ratio_cell(fast.rms_percent, peer.rms_percent) << " | "
           << (fast_holds ? "yes" : "**no**");
      } else {
        md << " | ";
      }
      md << " |\n";
    }
  md << "\n**" << held << " of " << counted << " hold** (the default loop); with --fast, "
     << fast_held << " of " << fast_counted << ".\n";
  return md.str();
}

const char kUsage[] =
    "usage: pm_bench_attr_quality MESH... [--targets 0.5,0.1,0.02] [--out FILE]\n"
    "Simplifies each mesh to each target fraction of its faces with pmenc (attributes kept,\n"
    "and dropped) and meshopt_simplify on the seam-split vertex buffer, measures each LOD's geometric distance\n"
    "to the original both ways, and prints a markdown report (also to FILE with --out).\n"
    "Progress: stderr.\n";

// Every option takes a value; anything else is a mesh.
bool parse_arguments(int argc, char** argv, Settings& settings) {
  for (int i = 1; i < argc; ++i) {
    const std::string name = argv[i];
    if (name == "--help" || name == "-h") {
      std::cout << kUsage;
      std::exit(0);
    }
    if (name.rfind("-", 0) != 0) {
      settings.inputs.push_back(name);
      continue;
    }
    const char* value = i + 1 < argc ? argv[++i] : nullptr;
    bool understood = value != nullptr;
    if (!understood) {
    } else if (name == "--targets") {
      understood = pm::bench::parse_targets(value, settings.targets);
    } else if (name == "--out") {
      settings.out_path = value;
    } else {
      understood = false;
    }
    if (!understood) {
      std::cerr << "pm_bench_attr_quality: unknown option, or a missing or bad value: " << name
                << "\n" << kUsage;
      return false;
    }
  }
  if (settings.inputs.empty()) std::cerr << kUsage;
  return !settings.inputs.empty();
}

}  // namespace

int main(int argc, char** argv) {
  Settings settings;
  if (!parse_arguments(argc, argv, settings)) return 2;
  const auto start = Clock::now();
  const std::string load_at_start = pm::bench::command_output("cut -d' ' -f1-3 /proc/loadavg");
  std::vector<MeshReport> reports;
  bool failed = false;
  for (const fs::path& file : pm::bench::mesh_files(settings.inputs)) {
    MeshReport report;
    if (run_mesh(file, settings, report))
      reports.push_back(std::move(report));
    else
      failed = true;
  }
  if (reports.empty()) {
    std::cerr << "pm_bench_attr_quality: no mesh measured\n";
    return 3;
  }
  const std::string markdown = render(reports, load_at_start, seconds_since(start));
  std::cout << markdown;
  if (!settings.out_path.empty()) {
    std::ofstream out(settings.out_path, std::ios::binary);
    out << markdown;
    if (!out) {
      std::cerr << "pm_bench_attr_quality: cannot write " << settings.out_path << "\n";
      return 5;
    }
  }
  return failed ? 1 : 0;
}
