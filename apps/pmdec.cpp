// pmdec: progressive meshes (.pm) in, levels of detail out. Parse, plan, call the library
// per file, report. The modes are in pmdec/ (pmdec/pmdec.h says which file holds which).
#include "pmdec/pmdec.h"

#include <CLI/CLI.hpp>
#include <iostream>

#include "batch_options.h"
#include "cli_common.h"

namespace {

using namespace pmdec;

int fail_usage(const std::string& message) {
  std::cerr << kTool << ": " << message << "\n";
  return pm::cli::kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  pm::cli::return_large_blocks_when_freed();
  CLI::App app{
      "pmdec: decode levels of detail from progressive meshes (.pm).\n"
      "Without a level option, writes full detail: the input mesh, exactly.\n"
      "Many inputs are decoded at once (-j); a failure does not stop the others."};
  app.set_version_flag("--version", std::string("pmdec ") + PM_VERSION_STRING);
  Settings settings;
  CommandLine line;
  add_options(app, line, settings);
  const pm::cli::BatchCommandLine& command = line.command;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? pm::cli::kExitOk : pm::cli::kExitUsage;
  }
  if (line.max_memory->count() > 0 &&
      !pm::cli::parse_size(line.max_memory_text, settings.read.max_memory))
    return fail_usage("--max-memory " + line.max_memory_text +
                      ": expected a positive size such as 1000000, 512M or 2G");

  if (line.info) {
    if (command.inputs.empty() && command.lists.empty())
      return fail_usage("no input: give files, directories with -r, or --from-list FILE");
    return print_infos(command, settings.read, line.sizes);
  }

  if (line.from_stdin) {
    if (!command.inputs.empty() || !command.lists.empty())
      return fail_usage("--stdin reads standard input: give no input files");
    if (command.output.empty() || command.output == "-" ||
        command.output.find("{faces}") == std::string::npos)
      return fail_usage("--stdin needs -o with {faces} in it, e.g. -o 'lod_{faces}.obj'");
    return decode_progressively(settings, line.every, command.output, command.quiet);
  }
  if (command.output.empty() && command.out_dir.empty() && line.compare_path.empty())
    return fail_usage(
        "no output given (use -o FILE, -o - for OBJ on standard output, or --out-dir DIR)");
  if (command.output == "-" && !line.compare_path.empty())
    return fail_usage("--compare prints on standard output: write the mesh to a file");

  SelectiveRequest& selective = settings.selective;
  if (*line.exact_ring_flag && !*line.by_view && !*line.by_region && !*line.by_viewpoint)
    return fail_usage("--exact-ring needs --view, --region or --viewpoint");
  if (line.exact_ring) selective.rule = pm::DependencyRule::kExactRing;
  if (*line.by_view) {
    std::string problem;
    if (!parse_view(line.view_text, selective.camera, problem))
      return fail_usage("--view " + line.view_text + ": " + problem);
    selective.kind = SelectiveRequest::Kind::kView;
    std::vector<double> p;
    if (!line.pixel_error_text.empty()) {
      if (!parse_numbers(line.pixel_error_text, 1, p) || !(p[0] > 0))
        return fail_usage("--pixel-error " + line.pixel_error_text +
                          ": expected a positive number of pixels");
      selective.options.pixel_error = p[0];
    }
  } else if (*line.by_region) {
    if (!parse_region(line.region_text, selective))
      return fail_usage("--region " + line.region_text +
                        ": expected sphere:X,Y,Z,R (R >= 0) or box:X0,Y0,Z0,X1,Y1,Z1 (X0 <= X1, "
                        "Y0 <= Y1, Z0 <= Z1)");
  } else if (*line.by_viewpoint) {
    std::vector<double> p;
    if (!parse_numbers(line.viewpoint_text, 3, p))
      return fail_usage("--viewpoint " + line.viewpoint_text + ": expected three numbers X,Y,Z");
    if (!*line.by_faces && !*line.by_vertices)
      return fail_usage("--viewpoint needs a budget: --faces N or --vertices N");
    selective.kind = SelectiveRequest::Kind::kViewpoint;
    selective.a = {p[0], p[1], p[2]};
  }

  LevelRequest single;
  if (*line.by_morph) {
    MorphRequest morph;
    if (!parse_morph(line.morph_text, line.morph_frames, morph))
      return fail_usage("--morph " + line.morph_text +
                        ": expected FROM:TO:ALPHA (ALPHA in [0, 1]), or FROM:TO with "
                        "--morph-frames K; FROM and TO are percentages (25%) or face counts");
    // One output per frame; {frame} numbers them from 0, zero-padded.
    const std::size_t width = std::to_string(morph.alphas.size() - 1).size();
    for (std::size_t i = 0; i < morph.alphas.size(); ++i) {
      LevelRequest frame;
      frame.label = std::string(width - std::to_string(i).size(), '0') + std::to_string(i);
      settings.levels.push_back(frame);
    }
    if (command.output == "-" && settings.levels.size() > 1)
      return fail_usage("-o - takes one frame; --morph-frames gives " +
                        std::to_string(settings.levels.size()));
    settings.morph = morph;
  } else if (*line.by_lods) {
    if (!parse_lods(line.lods_text, settings.levels))
      return fail_usage("--lods " + line.lods_text +
                        ": expected a comma-separated list of percentages (25%) or face counts");
    for (std::size_t i = 0; i < settings.levels.size(); ++i)
      for (std::size_t j = 0; j < i; ++j)
        if (settings.levels[i].label == settings.levels[j].label)
          return fail_usage("--lods " + line.lods_text + ": two levels are named " +
                            settings.levels[i].label);
    if (command.output == "-" && settings.levels.size() > 1)
      return fail_usage("-o - takes one level; --lods gives " +
                        std::to_string(settings.levels.size()));
  } else {
    if (*line.by_vertices) {
      single.kind = LevelRequest::Kind::kVertices;
      single.count = line.vertices;
    } else if (*line.by_faces) {
      single.kind = LevelRequest::Kind::kFaces;
      single.count = line.faces;
    } else if (*line.by_ratio) {
      single.kind = LevelRequest::Kind::kRatio;
      single.ratio = line.ratio;
    } else if (*line.by_error) {
      single.kind = LevelRequest::Kind::kError;
      if (!parse_error_bound(line.error_text, settings.error.absolute, settings.error.value))
        return fail_usage(std::string("--error: not a non-negative number") +
                          (settings.error.absolute ? " (no % with --absolute)" : " or percentage") +
                          ": " + line.error_text);
    }
    settings.levels = {single};
  }

  // glTF output: --lods writes one file; --quantize and --material-from need it.
  const pm::MeshFormat named_format =
      command.output.empty() ? output_format_for(".obj", settings.output_format)
                             : output_format_for(command.output, settings.output_format);
  if ((*line.quantize || *line.material_from) && !pm::cli::is_gltf(named_format))
    return fail_usage(std::string(*line.quantize ? "--quantize" : "--material-from") +
                      " is for glTF output: give -o FILE.glb or FILE.gltf, or --format glb");
  settings.gltf_chain = *line.by_lods && pm::cli::is_gltf(named_format);

  pm::cli::PlanSettings plan;
  plan.extensions = {"pm"};
  plan.extra_names = {"lod", "frame"};
  plan.default_template = *line.by_lods     ? "{dir}/{stem}_{lod}.obj"
                          : *line.by_frames ? "{dir}/{stem}_morph_{frame}.obj"
                          : *line.by_morph  ? "{dir}/{stem}_morph.obj"
                                            : "{dir}/{stem}.obj";
  for (const LevelRequest& level : settings.levels)
    plan.variants.push_back(
        {{"lod", *line.by_lods ? level.label : ""}, {"frame", *line.by_morph ? level.label : ""}});
  if (settings.gltf_chain) {
    plan.variants = {{{"lod", ""}, {"frame", ""}}};  // one file holds every level
    plan.default_template = std::string("{dir}/{stem}.") + pm::mesh_format_name(named_format);
  }
  pm::cli::OutputTemplate name_template;
  if (!command.output.empty() && command.output != "-" &&
      pm::cli::OutputTemplate::parse(command.output, plan.extra_names, name_template)) {
    if (name_template.has_placeholder("lod") && !*line.by_lods)
      return fail_usage("-o " + command.output + ": {lod} needs --lods");
    if (name_template.has_placeholder("lod") && settings.gltf_chain)
      return fail_usage("-o " + command.output + ": a glTF output holds every level of --lods: no {lod}");
    if (name_template.has_placeholder("frame") && !*line.by_frames)
      return fail_usage("-o " + command.output + ": {frame} needs --morph-frames");
    if (!name_template.has_placeholder("frame") && *line.by_frames && settings.levels.size() > 1)
      return fail_usage("-o " + command.output + ": name the frames apart with {frame}");
    if (!name_template.has_placeholder("lod") && *line.by_lods && settings.levels.size() > 1 &&
        !settings.gltf_chain)
      return fail_usage("-o " + command.output + ": name the levels of --lods apart with {lod}");
  }
  std::vector<pm::cli::Task> tasks;
  if (pm::Status s = pm::cli::plan_tasks(command, plan, tasks); !s) {
    std::cerr << kTool << ": " << s.message() << "\n";
    return pm::cli::exit_code_for(s.code());
  }
  // --compare alone writes no mesh.
  if (command.output.empty() && command.out_dir.empty())
    for (pm::cli::Task& task : tasks) task.outputs.clear();
  for (const pm::cli::Task& task : tasks)
    for (const std::string& output : task.outputs)
      if (output_format_for(output, settings.output_format) == pm::MeshFormat::kUnknown)
        return pm::cli::fail(
            kTool, output,
            pm::Status(pm::ErrorCode::kUnsupportedFormat,
                       "unknown output format (use .obj .ply .off .stl .gltf .glb or --format)"));
  if (command.dry_run) {
    pm::cli::print_plan(tasks, command.json, /*outputs_as_array=*/true, command.skip_existing);
    return pm::cli::kExitOk;
  }

  // Read before any work is done or any file written, so that a bad ORIGINAL costs nothing.
  pm::Mesh original;
  pm::cli::RunOptions run_options = command.run_options(kTool);
  if (!line.compare_path.empty()) {
    if (tasks.size() != 1)
      return fail_usage("--compare takes a single input (" + std::to_string(tasks.size()) +
                        " given)");
    if (pm::Status s = pm::read_mesh(line.compare_path, original); !s)
      return pm::cli::fail(kTool, line.compare_path, s);
    settings.compare_with = &original;
    // The comparison is the JSON object of --json.
    settings.json_comparison = command.json;
    run_options.json = false;
  }
  if (tasks.empty() && !command.quiet) std::cerr << kTool << ": no input files\n";
  if (pm::Status s = pm::cli::load_material_source(settings.gltf); !s)
    return pm::cli::fail(kTool, settings.gltf.material_source_path, s);

  pm::cli::install_cleanup_handlers();
  std::vector<std::string> outputs;
  for (const pm::cli::Task& task : tasks)
    outputs.insert(outputs.end(), task.outputs.begin(), task.outputs.end());
  pm::cli::remove_stale_temporaries(outputs);
  settings.skip_existing = command.skip_existing;
  settings.create_directories = !command.out_dir.empty();
  return pm::cli::run_batch(tasks, run_options,
                            [&settings](const pm::cli::Task& task, pm::cli::JobProgress& progress) {
                              return decode_file(task, progress, settings);
                            });
}
