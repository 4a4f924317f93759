// pmenc: mesh in, progressive mesh (.pm) out. Parse, call the library, report.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <map>

#include "cli_common.h"
#include "pm/encoder.h"
#include "pm/mesh_io.h"
#include "pm/pm_codec.h"

namespace {

constexpr const char* kTool = "pmenc";

std::string default_output_for(const std::string& input) {
  if (input == "-") return "-";
  const auto slash = input.find_last_of('/');
  const auto dot = input.find_last_of('.');
  const bool has_extension =
      dot != std::string::npos && (slash == std::string::npos || dot > slash);
  return (has_extension ? input.substr(0, dot) : input) + ".pm";
}

void report_repairs(const std::string& input, const pm::RepairReport& r) {
  if (!r.any()) return;
  std::cerr << kTool << ": " << input << ": repaired for simplification (undone at full detail):";
  const char* separator = " ";
  auto item = [&](std::size_t n, const char* what) {
    if (!n) return;
    std::cerr << separator << n << ' ' << what;
    separator = ", ";
  };
  item(r.complex_edges, "non-manifold edges cut");
  item(r.vertices_duplicated, "vertices duplicated at non-manifold spots (kept, never removed)");
  item(r.carried_faces, "faces with a repeated vertex carried as-is");
  item(r.loose_vertices, "unreferenced vertices kept for full detail");
  std::cerr << '\n';
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "pmenc: encode a triangle mesh as a progressive mesh (.pm).\n"
      "Reads OBJ, PLY, OFF or STL; writes the base mesh and the vertex splits that\n"
      "restore the input exactly. Decode any level of detail with pmdec."};
  app.set_version_flag("--version", std::string("pmenc ") + PM_VERSION_STRING);
  std::string input, output;
  pm::EncodeOptions options;
  bool quiet = false;
  std::string input_format;
  int zstd_level = pm::WriteOptions{}.zstd_level;
  app.add_option("input", input, "Input mesh (.obj .ply .off .stl), or - for standard input")
      ->required();
  app.add_option("-o,--output", output,
                 "Output .pm file, or - for standard output "
                 "(default: the input's name with .pm)");
  app.add_option("--format", input_format,
                 "Input format when it cannot be told from the name "
                 "(obj, ply, off, stl); needed for standard input");
  app.add_option("--metric", options.metric,
                 "Collapse cost: schroeder (distance to plane or feature line, Schroeder 1992) "
                 "or quadric (Garland and Heckbert 1997)")
      ->transform(CLI::CheckedTransformer(
          std::map<std::string, pm::Metric>{{"schroeder", pm::Metric::kSchroeder},
                                            {"quadric", pm::Metric::kQuadric}},
          CLI::ignore_case))
      ->default_str("quadric");
  app.add_option("--feature-angle", options.feature_angle_deg,
                 "Edges whose faces meet at more than this angle (degrees) are sharp features "
                 "(default: 30 for schroeder, 180 for quadric, which holds boundaries only)")
      ->check(CLI::Range(0.0, 180.0));
  app.add_option("--max-normal-flip", options.max_normal_flip_deg,
                 "Reject collapses that turn a face normal by more than this (degrees)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 180.0));
  app.add_flag("--keep-corners", options.keep_corners,
               "Never remove corner vertices (Schroeder 1992's rule; simplification may stall)");
  app.add_option("--min-faces", options.min_faces, "Stop simplifying at this many faces");
  app.add_option("--min-vertices", options.min_vertices, "Stop simplifying at this many vertices");
  app.add_option("--zstd-level", zstd_level, "zstd compression level")
      ->capture_default_str()
      ->check(CLI::Range(1, 22));
  app.add_flag("-q,--quiet", quiet, "Print errors only");
  app.footer(
      "Exit codes: 0 ok, 1 internal error, 2 usage, 3 cannot read input, 4 invalid input,\n"
      "5 cannot write output, 6 unsupported format or version, 7 input too large.");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? pm::cli::kExitOk : pm::cli::kExitUsage;
  }
  if (output.empty()) output = default_output_for(input);
  pm::cli::install_cleanup_handlers();
  const auto start = std::chrono::steady_clock::now();

  pm::MeshFormat format = input_format.empty() ? pm::mesh_format_from_path(input)
                                               : pm::mesh_format_from_path("." + input_format);
  if (format == pm::MeshFormat::kUnknown) {
    return pm::cli::fail(
        kTool, input,
        pm::Status(pm::ErrorCode::kUnsupportedFormat,
                   input == "-" ? "standard input needs --format obj|ply|off|stl"
                                : "unknown mesh format (use .obj .ply .off .stl or --format)"));
  }
  std::string bytes;
  if (pm::Status s = pm::cli::read_whole_input(input, bytes); !s)
    return pm::cli::fail(kTool, input, s);
  pm::Mesh mesh;
  pm::ReadReport read_report;
  if (pm::Status s = pm::read_mesh_from_memory(bytes, format, mesh, &read_report); !s)
    return pm::cli::fail(kTool, input, s);
  bytes = std::string();
  if (read_report.polygons_triangulated && !quiet)
    std::cerr << kTool << ": " << input << ": " << read_report.polygons_triangulated
              << " polygons split into triangles\n";

  if (!quiet && isatty(2)) {
    options.progress = [](double fraction) {
      std::fprintf(stderr, "\rpmenc: simplifying %3d%%", static_cast<int>(fraction * 100));
      if (fraction >= 1.0) std::fprintf(stderr, "\r%24s\r", "");
    };
  }
  pm::ProgressiveMesh progressive;
  pm::EncodeStats stats;
  if (pm::Status s = pm::encode(mesh, options, progressive, &stats); !s)
    return pm::cli::fail(kTool, input, s);
  if (!quiet) report_repairs(input, stats.repair);

  std::string encoded;
  pm::WriteOptions write_options;
  write_options.zstd_level = zstd_level;
  if (pm::Status s = pm::write_pm(progressive, write_options, encoded); !s)
    return pm::cli::fail(kTool, input, s);
  if (pm::Status s = pm::cli::write_output_atomically(output, encoded, /*binary=*/true); !s) {
    pm::cli::fail(kTool, output, s);
    return s.code() == pm::ErrorCode::kInvalidArgument ? pm::cli::kExitUsage
                                                       : pm::cli::kExitCannotWrite;
  }
  if (!quiet) {
    std::fprintf(
        stderr,
        "pmenc: %s: %zu faces, base mesh %zu faces / %zu vertices, %zu splits, %s in %.2f s\n",
        input.c_str(), stats.input_faces, stats.base_faces, stats.base_vertices, stats.collapses,
        pm::cli::human_bytes(encoded.size()).c_str(), pm::cli::seconds_since(start));
  }
  return pm::cli::kExitOk;
}
