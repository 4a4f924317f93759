// pmenc: meshes in, progressive meshes (.pm) out. Parse, plan, call the library per file,
// report.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <utility>

#include "batch_options.h"
#include "cli_common.h"
#include "pm/advanced/pm_stream.h"
#include "pm/encoder.h"
#include "pm/gltf.h"
#include "pm/mesh_io.h"
#include "pm/pm_codec.h"

namespace {

constexpr const char* kTool = "pmenc";

struct Settings {
  // --fast-from: meshes of a million faces or more leave out the measured distance.
  pm::EncodeOptions encode = [] {
    pm::EncodeOptions options;
    options.fast_from = pm::kDefaultFastFrom;
    return options;
  }();
  pm::WriteOptions write;
  std::string input_format;  // --format, or empty
  bool skip_existing = false;
  bool create_directories = false;  // --out-dir: the mirrored tree is made as needed
  bool layered = false;             // --layered
  int error_bits = -1;              // --error-bits; -1: kQuantizedErrorBits with --quantize, else 0
};

std::string repairs_note(const std::string& input, const pm::RepairReport& r) {
  std::string line = input + ": repaired for simplification (undone at full detail):";
  const char* separator = " ";
  auto item = [&](std::size_t n, const char* what) {
    if (!n) return;
    line += separator + std::to_string(n) + ' ' + what;
    separator = ", ";
  };
  item(r.complex_edges, "non-manifold edges cut");
  item(r.vertices_duplicated, "vertices duplicated at non-manifold spots (kept, never removed)");
  item(r.carried_faces, "faces with a repeated vertex carried as-is");
  item(r.loose_vertices, "unreferenced vertices kept for full detail");
  return line;
}

// The JSON members of one file; counts are null unless it was converted.
std::string json_members(const std::string& output, const pm::EncodeStats* stats,
                         std::size_t pm_bytes) {
  std::string json = "\"output\":" + pm::cli::json_string(output);
  auto member = [&](const char* key, std::size_t value) {
    json += std::string(",\"") + key + "\":" + (stats ? std::to_string(value) : "null");
  };
  member("input_faces", stats ? stats->input_faces : 0);
  member("base_faces", stats ? stats->base_faces : 0);
  member("base_vertices", stats ? stats->base_vertices : 0);
  member("splits", stats ? stats->collapses : 0);
  member("pm_bytes", pm_bytes);
  // How the collapse loop ran: "fast" without its measured distance (--fast, --fast-from),
  // "default" with it (the names of the two loops before issue 25 made them one).
  json += std::string(",\"loop\":") + (stats ? (stats->fast ? "\"fast\"" : "\"default\"") : "null");
  return json;
}

pm::cli::Outcome encode_file(const pm::cli::Task& task, pm::cli::JobProgress& progress,
                             const Settings& settings) {
  const auto start = std::chrono::steady_clock::now();
  const std::string& input = task.input.path;
  const std::string& output = task.outputs.front();
  pm::cli::Outcome outcome;
  outcome.json = json_members(output, nullptr, 0);
  auto failed = [&outcome](const pm::Status& status) { return outcome.failed_with(status); };
  if (!task.input.problem) return failed(task.input.problem);
  if (settings.skip_existing && pm::cli::all_outputs_exist(task)) {
    outcome.skipped = true;
    outcome.summary = input + ": skipped, " + output + " exists";
    return outcome;
  }

  pm::MeshFormat format = settings.input_format.empty()
                              ? pm::mesh_format_from_path(input)
                              : pm::mesh_format_from_path("." + settings.input_format);
  if (format == pm::MeshFormat::kUnknown && input != "-")
    return failed(pm::Status(pm::ErrorCode::kUnsupportedFormat,
                             "unknown mesh format (use .obj .ply .off .stl .gltf .glb or --format)"));
  std::string bytes;
  if (pm::Status s = pm::cli::read_whole_input(input, bytes); !s) return failed(s);
  if (format == pm::MeshFormat::kUnknown) format = pm::cli::sniff_mesh_format(bytes);
  if (format == pm::MeshFormat::kUnknown)
    return failed(pm::Status(pm::ErrorCode::kUnsupportedFormat,
                             "cannot tell the mesh format of standard input: use --format "
                             "obj|ply|off|stl|gltf|glb"));
  pm::Mesh mesh;
  pm::ReadReport read_report;
  if (format == pm::MeshFormat::kGltf || format == pm::MeshFormat::kGlb) {
    // A .gltf's buffers may be files beside it (standard input has no directory).
    pm::GltfReadOptions gltf;
    if (input != "-") {
      const std::string directory = std::filesystem::path(input).parent_path().string();
      gltf.base_directory = directory.empty() ? "." : directory;
    }
    if (pm::Status s = pm::read_gltf(bytes, gltf, mesh, &read_report); !s) return failed(s);
  } else if (pm::Status s = pm::read_mesh_from_memory(bytes, format, mesh, &read_report); !s) {
    return failed(s);
  }
  std::string().swap(bytes);  // frees the buffer (assigning an empty string keeps it)
  if (!task.conflict) return failed(task.conflict);
  progress.set_faces(mesh.face_count());
  if (read_report.polygons_triangulated)
    progress.note(input + ": " + std::to_string(read_report.polygons_triangulated) +
                  " polygons split into triangles");
  // What the file holds that a mesh cannot (glTF: skins, tangents, other scenes, ...).
  for (const std::string& dropped : read_report.ignored_properties)
    progress.note(input + ": not kept: " + dropped);

  pm::EncodeOptions options = settings.encode;
  // --layered: whole chunks. The windows of layered splits stay inside the stream's chunks
  // (--chunk-splits), those of the options the stream is written with.
  if (settings.layered) options.layer_window = std::numeric_limits<double>::infinity();
  options.progress = [&progress](double fraction) { progress.set_fraction(fraction); };
  pm::ProgressiveMesh progressive;
  pm::EncodeStats stats;
  // The mesh is given away: encode() lets its arrays go once the collapse loop has its own.
  if (pm::Status s = pm::encode(std::move(mesh), options, settings.write, progressive, &stats); !s)
    return failed(s);
  if (stats.repair.any()) progress.note(repairs_note(input, stats.repair));
  if (stats.fast && !settings.encode.fast)  // large meshes leave out the measure (--fast-from)
    progress.note(input + ": " + std::to_string(stats.input_faces) + " faces, at least --fast-from " +
                  std::to_string(settings.encode.fast_from) +
                  ": --fast, without the measured distance (--fast-from 0 to measure)");

  std::string encoded;
  if (pm::Status s = pm::write_pm(progressive, settings.write, encoded); !s) return failed(s);
  pm::Status written =
      settings.create_directories ? pm::cli::make_parent_directories(output) : pm::Status::ok();
  if (written) written = pm::cli::write_output_atomically(output, encoded, /*binary=*/true);
  if (!written) {
    outcome.status = written;
    outcome.exit_code = pm::cli::exit_code_for_write(written);
    outcome.error_file = output;
    return outcome;
  }
  outcome.faces = stats.input_faces;
  outcome.json = json_members(output, &stats, encoded.size());
  char summary[256];
  std::snprintf(summary, sizeof summary,
                ": %zu faces, base mesh %zu faces / %zu vertices, %zu splits, %s in %.2f s",
                stats.input_faces, stats.base_faces, stats.base_vertices, stats.collapses,
                pm::cli::human_bytes(encoded.size()).c_str(), pm::cli::seconds_since(start));
  outcome.summary = (input == "-" ? std::string("(stdin)") : input) + summary;
  return outcome;
}

}  // namespace

int main(int argc, char** argv) {
  pm::cli::return_large_blocks_when_freed();
  CLI::App app{
      "pmenc: encode triangle meshes as progressive meshes (.pm).\n"
      "Reads OBJ, PLY, OFF, STL or glTF; writes the base mesh and the vertex splits that\n"
      "restore the input exactly. Decode any level of detail with pmdec.\n"
      "Many inputs are converted at once (-j); a failure does not stop the others."};
  app.set_version_flag("--version", std::string("pmenc ") + PM_VERSION_STRING);
  pm::cli::BatchCommandLine command;
  Settings settings;
  command.add_options(
      app, "Input meshes (.obj .ply .off .stl .gltf .glb), directories (with -r), or - for standard input",
      "Output .pm file, - for standard output, or a template: {stem} {ext} {name} {dir} "
      "(default: {dir}/{stem}.pm, the input's name with .pm)");
  app.add_option("--format", settings.input_format,
                 "Input format when it cannot be told from the name "
                 "(obj, ply, off, stl, gltf, glb); standard input is recognized by its content");
  app.add_option("--metric", settings.encode.metric,
                 "Collapse cost: schroeder (distance to plane or feature line, Schroeder 1992) "
                 "or quadric (Garland and Heckbert 1997)")
      ->transform(CLI::CheckedTransformer(
          std::map<std::string, pm::Metric>{{"schroeder", pm::Metric::kSchroeder},
                                            {"quadric", pm::Metric::kQuadric}},
          CLI::ignore_case))
      ->default_str("quadric");
  app.add_option("--feature-angle", settings.encode.feature_angle_deg,
                 "Edges whose faces meet at more than this angle (degrees) are sharp features "
                 "(default: 30 for schroeder, 180 for quadric, which holds boundaries only)")
      ->check(CLI::Range(0.0, 180.0));
  app.add_option("--max-normal-flip", settings.encode.max_normal_flip_deg,
                 "Reject collapses that turn a face normal by more than this (degrees)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 180.0));
  app.add_flag("--keep-corners", settings.encode.keep_corners,
               "Never remove corner vertices (Schroeder 1992's rule; simplification may stall)");
  app.add_flag("--fast", settings.encode.fast,
               "Leave out the measured distance: 3 to 4 times faster, levels a little closer "
               "to the input than meshoptimizer's on geometry (Hausdorff 1.6 times the "
               "default's); attributes, seams and the recorded errors' bound as without");
  app.add_option("--fast-from", settings.encode.fast_from,
                 "--fast on meshes of at least this many faces, where the measured distance "
                 "takes about four times as long; 0: only with --fast")
      ->capture_default_str()
      ->check(pm::cli::whole_number());
  app.add_option("--threads", settings.encode.threads,
                 "Threads for the collapse loop on large meshes and for compressing the stream (0: the cores, "
                 "or 1 per file when several files are converted at once); the output is the "
                 "same for any number")
      ->capture_default_str();
  app.add_flag("--keep-order", settings.encode.keep_order,
               "Store the input's vertex, face and attribute-table order: full detail lists them as the "
               "input did");
  app.add_flag("--drop-attributes", settings.encode.drop_attributes,
               "Encode geometry only: no colours, texture coordinates, normals or materials");
  app.add_option("--min-faces", settings.encode.min_faces, "Stop simplifying at this many faces")
      ->check(pm::cli::whole_number());
  app.add_option("--min-vertices", settings.encode.min_vertices,
                 "Stop simplifying at this many vertices")
      ->check(pm::cli::whole_number());
  app.add_option("--zstd-level", settings.write.zstd_level, "zstd compression level")
      ->capture_default_str()
      ->check(CLI::Range(1, 22));
  app.add_option("--quantize", settings.write.position_bits,
                 "Store positions on a grid of 2^BITS steps over the bounding box (lossy; 0: "
                 "lossless, the default)")
      ->capture_default_str()
      ->check(CLI::IsMember({0}) | CLI::Range(4, 24));
  app.add_option("--quantize-uv", settings.write.uv_bits,
                 "Store texture coordinates on a grid of 2^BITS steps (lossy; 0: lossless)")
      ->capture_default_str()
      ->check(CLI::IsMember({0}) | CLI::Range(4, 24));
  app.add_option("--quantize-normal", settings.write.normal_bits,
                 "Store normals on a grid of 2^BITS steps (lossy; 0: lossless)")
      ->capture_default_str()
      ->check(CLI::IsMember({0}) | CLI::Range(4, 24));
  app.add_option("--error-bits", settings.error_bits,
                 "Keep BITS significant bits of each split's error bound, rounded up so that it "
                 "stays a bound (lossy; 0: every bit; default: " +
                     std::to_string(pm::kQuantizedErrorBits) + " with --quantize, else 0)")
      ->check(CLI::Range(0, 24));
  app.add_flag("--layered", settings.layered,
               "Layer the splits within whole chunks (--layer-window over each chunk): "
               "smaller still, but levels inside a chunk are coarser than the greedy order's "
               "(the levels at chunk ends are the same)");
  app.add_option("--layer-window", settings.encode.layer_window,
                 "Reorder the splits into layers of independent splits within windows of at "
                 "most this share of the vertices (a smaller .pm; the levels' distance to the "
                 "input stays within about 2%); 0: keep the simplifier's order")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0))
      ->excludes("--layered");
  app.add_option("--chunk-splits", settings.write.chunk_splits,
                 "Largest chunk of vertex splits (each chunk is compressed on its own)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1 << 20));
  app.footer(
      "Exit codes: 0 ok, 1 internal error, 2 usage, 3 cannot read input, 4 invalid input,\n"
      "5 cannot write output, 6 unsupported format or version, 7 input too large,\n"
      "8 several inputs and some failed (each is reported; the others were converted).");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? pm::cli::kExitOk : pm::cli::kExitUsage;
  }

  pm::cli::PlanSettings plan;
  plan.extensions = {"obj", "ply", "off", "stl", "gltf", "glb"};
  plan.default_template = "{dir}/{stem}.pm";
  plan.variants = {{}};
  plan.stdin_default_output = "-";
  std::vector<pm::cli::Task> tasks;
  if (pm::Status s = pm::cli::plan_tasks(command, plan, tasks); !s) {
    std::cerr << kTool << ": " << s.message() << "\n";
    return pm::cli::exit_code_for(s.code());
  }
  if (command.dry_run) {
    pm::cli::print_plan(tasks, command.json, /*outputs_as_array=*/false, command.skip_existing);
    return pm::cli::kExitOk;
  }
  if (tasks.empty() && !command.quiet) std::cerr << kTool << ": no input files\n";

  pm::cli::install_cleanup_handlers();
  std::vector<std::string> outputs;
  for (const pm::cli::Task& task : tasks) outputs.push_back(task.outputs.front());
  pm::cli::remove_stale_temporaries(outputs);
  settings.skip_existing = command.skip_existing;
  settings.create_directories = !command.out_dir.empty();
  const pm::cli::RunOptions run = command.run_options(kTool);
  // Files at once already use the cores: one thread each, unless asked.
  if (settings.encode.threads == 0 && run.jobs > 1 && tasks.size() > 1) settings.encode.threads = 1;
  settings.write.threads = settings.encode.threads;
  settings.write.error_bits = settings.error_bits >= 0     ? settings.error_bits
                              : settings.write.position_bits > 0 ? pm::kQuantizedErrorBits
                                                                 : 0;
  return pm::cli::run_batch(tasks, run,
                            [&settings](const pm::cli::Task& task, pm::cli::JobProgress& progress) {
                              return encode_file(task, progress, settings);
                            });
}
