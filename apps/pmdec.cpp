// pmdec: progressive mesh (.pm) in, one level of detail out. Parse, call, report.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "cli_common.h"
#include "pm/lod.h"
#include "pm/measured_level.h"
#include "pm/mesh_io.h"
#include "pm/pm_codec.h"
#include "pm/surface_distance.h"

namespace {

constexpr const char* kTool = "pmdec";

// "0.5" and "0.5%" are a percentage of the bounding-box diagonal; with --absolute, "0.5" is
// in model units.
bool parse_error_bound(std::string text, bool absolute, const pm::ProgressiveMesh& pm,
                       double& bound) {
  const bool percent_sign = !text.empty() && text.back() == '%';
  if (percent_sign) text.pop_back();
  if (percent_sign && absolute) return false;
  try {
    std::size_t used = 0;
    bound = std::stod(text, &used);
    if (used != text.size() || !(bound >= 0) || !std::isfinite(bound)) return false;
  } catch (const std::exception&) {
    return false;
  }
  if (!absolute) bound *= pm::bounding_box_diagonal(pm.positions) / 100.0;
  return true;
}

int print_info(const std::string& input, std::string_view bytes) {
  pm::PmInfo info;
  if (pm::Status s = pm::read_pm_info(bytes, info); !s) return pm::cli::fail(kTool, input, s);
  std::printf("file:             %s (%zu bytes)\n", input.c_str(), bytes.size());
  std::printf("format version:   %u.%u\n", info.major, info.minor);
  std::printf("flags:            0x%08x\n", info.flags);
  std::printf("base mesh:        %u vertices, %u faces\n", info.base_vertex_count,
              info.base_face_count);
  std::printf("vertex splits:    %u\n", info.split_count);
  std::printf("full detail:      %llu vertices, %llu faces\n",
              static_cast<unsigned long long>(info.full_vertex_count),
              static_cast<unsigned long long>(info.full_face_count));
  std::printf(
      "repairs carried:  %u welded vertices, %u faces with a repeated vertex, %u unreferenced "
      "vertices\n",
      info.weld_count, info.carried_face_count, info.loose_vertex_count);
  std::printf("error range:      0 (full detail) to %.9g (base mesh), model units\n",
              info.max_error);
  return pm::cli::kExitOk;
}

// --compare: one line for people, or one JSON object for scripts (--json). A percentage of
// a zero diagonal (a flat point) has no value: "n/a", or null in JSON.
void print_comparison(const pm::SurfaceDistance& d, const pm::Mesh& lod, std::size_t level,
                      double seconds, bool json) {
  const bool has_diagonal = d.diagonal > 0;
  const double hausdorff_percent = has_diagonal ? 100 * d.hausdorff / d.diagonal : 0;
  const double rms_percent = has_diagonal ? 100 * d.rms / d.diagonal : 0;
  if (!json) {
    char percents[2][32] = {"n/a", "n/a"};
    if (has_diagonal) {
      std::snprintf(percents[0], sizeof percents[0], "%.3g%%", hausdorff_percent);
      std::snprintf(percents[1], sizeof percents[1], "%.3g%%", rms_percent);
    }
    std::printf("hausdorff %.6g (%s of diagonal) rms %.6g (%s) faces %zu samples %zu\n",
                d.hausdorff, percents[0], d.rms, percents[1], lod.face_count(), d.samples);
    return;
  }
  char percents[2][32] = {"null", "null"};
  if (has_diagonal) {
    std::snprintf(percents[0], sizeof percents[0], "%.17g", hausdorff_percent);
    std::snprintf(percents[1], sizeof percents[1], "%.17g", rms_percent);
  }
  std::printf(
      "{\"faces\":%zu,\"vertices\":%zu,\"level\":%zu,\"hausdorff\":%.17g,\"rms\":%.17g,"
      "\"hausdorff_percent\":%s,\"rms_percent\":%s,\"diagonal\":%.17g,\"samples\":%zu,"
      "\"seconds\":%.3f}\n",
      lod.face_count(), lod.vertex_count(), level, d.hausdorff, d.rms, percents[0], percents[1],
      d.diagonal, d.samples, seconds);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "pmdec: decode a level of detail from a progressive mesh (.pm).\n"
      "Without a level option, writes full detail: the input mesh, exactly."};
  app.set_version_flag("--version", std::string("pmdec ") + PM_VERSION_STRING);
  std::string input, output, error_text, output_format, compare_path;
  std::size_t vertices = 0, faces = 0;
  double ratio = 1.0;
  bool quiet = false, info = false, json = false, absolute = false, estimate = false;
  app.add_option("input", input, "Input .pm file, or - for standard input")->required();
  app.add_option(
      "-o,--output", output,
      "Output mesh; the extension picks OBJ, PLY, OFF or STL; - writes OBJ to standard output");
  app.add_option("--format", output_format,
                 "Output format, overriding the extension (obj, ply, off, stl)");
  auto* by_vertices =
      app.add_option("--vertices", vertices, "Level with at least this many vertices");
  auto* by_faces = app.add_option("--faces", faces,
                                  "Level with this many faces (one more where a split adds two)");
  auto* by_ratio = app.add_option("--ratio", ratio, "Level with this fraction of the full faces")
                       ->check(CLI::Range(0.0, 1.0));
  auto* by_error = app.add_option(
      "--error", error_text,
      "Coarsest level whose measured Hausdorff distance to full detail is at most E percent "
      "of the bounding-box diagonal (E or E%); see --absolute and --estimate");
  app.add_flag("--absolute", absolute, "With --error: E is in model units")->needs(by_error);
  app.add_flag("--estimate", estimate,
               "With --error: select by the errors recorded in the file, without measuring "
               "(instant, but not a guarantee)")
      ->needs(by_error);
  by_vertices->excludes(by_faces)->excludes(by_ratio)->excludes(by_error);
  by_faces->excludes(by_ratio)->excludes(by_error);
  by_ratio->excludes(by_error);
  auto* compare = app.add_option("--compare", compare_path,
                                 "Measure the level's distance (Hausdorff, RMS) to this original "
                                 "mesh and print it on standard output; -o becomes optional");
  app.add_flag("--json", json, "With --compare: print one JSON object instead")->needs(compare);
  app.add_flag("--info", info, "Print the header, counts and error range, and exit");
  app.add_flag("-q,--quiet", quiet, "Print errors only");
  app.footer(
      "Exit codes: 0 ok, 1 internal error, 2 usage, 3 cannot read input, 4 invalid or\n"
      "truncated .pm, 5 cannot write output, 6 unsupported format or version, 7 too large.");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? pm::cli::kExitOk : pm::cli::kExitUsage;
  }
  pm::cli::install_cleanup_handlers();
  const auto start = std::chrono::steady_clock::now();

  std::string bytes;
  if (pm::Status s = pm::cli::read_whole_input(input, bytes); !s)
    return pm::cli::fail(kTool, input, s);
  if (info) return print_info(input, bytes);
  if (output.empty() && compare_path.empty()) {
    std::cerr << kTool << ": no output given (use -o FILE, or -o - for OBJ on standard output)\n";
    return pm::cli::kExitUsage;
  }
  if (output == "-" && !compare_path.empty()) {
    std::cerr << kTool << ": --compare prints on standard output: write the mesh to a file\n";
    return pm::cli::kExitUsage;
  }
  pm::MeshFormat format = output_format.empty() ? pm::mesh_format_from_path(output)
                                                : pm::mesh_format_from_path("." + output_format);
  if (output == "-" && output_format.empty()) format = pm::MeshFormat::kObj;
  if (!output.empty() && format == pm::MeshFormat::kUnknown)
    return pm::cli::fail(kTool, output,
                         pm::Status(pm::ErrorCode::kUnsupportedFormat,
                                    "unknown output format (use .obj .ply .off .stl or --format)"));

  // Read before any work is done or any file written, so that a bad ORIGINAL costs nothing.
  pm::Mesh original;
  if (!compare_path.empty()) {
    if (pm::Status s = pm::read_mesh(compare_path, original); !s)
      return pm::cli::fail(kTool, compare_path, s);
  }

  pm::ProgressiveMesh progressive;
  if (pm::Status s = pm::read_pm(bytes, progressive); !s) return pm::cli::fail(kTool, input, s);
  bytes = std::string();

  const std::size_t full_faces = pm::faces_at_level(progressive, progressive.splits.size());
  std::size_t level = progressive.splits.size();
  if (*by_vertices) {
    level = pm::level_for_vertices(progressive, vertices);
  } else if (*by_faces || *by_ratio) {
    const std::size_t wanted =
        *by_faces ? faces : static_cast<std::size_t>(std::llround(ratio * full_faces));
    level = pm::level_for_faces(progressive, wanted);
    if (!quiet && wanted < pm::faces_at_level(progressive, 0))
      std::cerr << kTool << ": " << input << ": " << wanted
                << " faces requested; the base mesh has " << pm::faces_at_level(progressive, 0)
                << "\n";
  } else if (*by_error) {
    double bound = 0;
    if (!parse_error_bound(error_text, absolute, progressive, bound)) {
      std::cerr << kTool << ": --error: not a non-negative number"
                << (absolute ? " (no % with --absolute)" : " or percentage") << ": "
                << error_text << "\n";
      return pm::cli::kExitUsage;
    }
    if (estimate) {
      level = pm::level_for_error(progressive, bound);
    } else {
      const auto search_start = std::chrono::steady_clock::now();
      pm::MeasuredLevel found;
      if (pm::Status s = pm::level_for_measured_error(progressive, bound, {}, found); !s)
        return pm::cli::fail(kTool, input, s);
      level = found.level;
      if (!quiet) {
        const double diagonal = found.distance.diagonal;
        std::fprintf(stderr,
                     "pmdec: %s: measured Hausdorff %.6g (%.4g%% of diagonal) <= %.6g, "
                     "%zu levels measured, %.2f s\n",
                     input.c_str(), found.distance.hausdorff,
                     diagonal > 0 ? 100 * found.distance.hausdorff / diagonal : 0.0, bound,
                     found.measurements, pm::cli::seconds_since(search_start));
      }
    }
  }

  const pm::Mesh mesh = pm::extract_level(progressive, level);
  if (!output.empty()) {
    std::string encoded;
    if (pm::Status s = pm::write_mesh_to_memory(mesh, format, encoded); !s)
      return pm::cli::fail(kTool, output, s);
    const bool binary = format == pm::MeshFormat::kPly || format == pm::MeshFormat::kStl;
    if (pm::Status s = pm::cli::write_output_atomically(output, encoded, binary); !s) {
      pm::cli::fail(kTool, output, s);
      return s.code() == pm::ErrorCode::kInvalidArgument ? pm::cli::kExitUsage
                                                         : pm::cli::kExitCannotWrite;
    }
  }
  if (!compare_path.empty()) {
    const auto compare_start = std::chrono::steady_clock::now();
    pm::SurfaceDistance distance;
    if (pm::Status s = pm::measure_surface_distance(original, mesh, {}, distance); !s)
      return pm::cli::fail(kTool, compare_path, s);
    print_comparison(distance, mesh, level, pm::cli::seconds_since(compare_start), json);
  }
  if (!quiet) {
    std::fprintf(
        stderr, "pmdec: %s: level %zu of %zu: %zu faces, %zu vertices, recorded error %.6g, %.2f s\n",
        input.c_str(), level, progressive.splits.size(), mesh.face_count(), mesh.vertex_count(),
        double(pm::error_at_level(progressive, level)), pm::cli::seconds_since(start));
  }
  return pm::cli::kExitOk;
}
