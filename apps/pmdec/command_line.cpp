// pmdec's options: what each means (--help, and the man page apps/man/pmdec.1 that
// tests/test_cli.cpp checks against it) and which go together.
#include <CLI/CLI.hpp>

#include "cli_common.h"
#include "pmdec/pmdec.h"

namespace pmdec {

void add_options(CLI::App& app, CommandLine& line, Settings& settings) {
  line.command.add_options(
      app, "Input .pm files, directories (with -r), or - for standard input",
      "Output mesh, - for OBJ on standard output, or a template: {stem} {ext} {name} {dir} "
      "{lod}; the extension picks OBJ, PLY, OFF, STL or glTF (.glb, .gltf: with --lods, every "
      "level in the one file) (default with --out-dir: {dir}/{stem}.obj, with --lods "
      "{dir}/{stem}_{lod}.obj)");
  app.add_option("--format", settings.output_format,
                 "Output format, overriding the extension (obj, ply, off, stl, gltf, glb)");
  line.quantize = app.add_flag("--quantize", settings.gltf.quantize,
                               "glTF output: KHR_mesh_quantization (16-bit positions, 8-bit normals, "
                               "16-bit texture coordinates in [0, 1]), a required extension");
  line.material_from = app.add_option("--material-from", settings.gltf.material_source_path,
                                      "glTF output: copy the material definitions (textures, images "
                                      "by reference) of the same-named materials of this glTF file")
                           ->type_name("IN.gltf");
  line.by_vertices =
      app.add_option("--vertices", line.vertices, "Level with at least this many vertices")
          ->check(pm::cli::whole_number());
  line.by_faces = app.add_option("--faces", line.faces,
                                 "Level with this many faces (one more where a split adds two)")
                      ->check(pm::cli::whole_number());
  line.by_ratio =
      app.add_option("--ratio", line.ratio, "Level with this fraction of the full faces")
          ->check(CLI::Range(0.0, 1.0));
  line.by_error = app.add_option(
      "--error", line.error_text,
      "Coarsest level whose measured Hausdorff distance to full detail is at most E percent "
      "of the bounding-box diagonal (E or E%); see --absolute and --estimate");
  line.by_lods = app.add_option(
      "--lods", line.lods_text,
      "Several levels per input, comma-separated: percentages of the full faces (25%) or "
      "face counts (5000); name the outputs with {lod} in -o");
  app.add_flag("--absolute", settings.error.absolute, "With --error: E is in model units")
      ->needs(line.by_error);
  app.add_flag("--estimate", settings.error.estimate,
               "With --error: select by the errors recorded in the file, without measuring "
               "(instant, but not a guarantee)")
      ->needs(line.by_error);
  line.by_vertices->excludes(line.by_faces)
      ->excludes(line.by_ratio)
      ->excludes(line.by_error)
      ->excludes(line.by_lods);
  line.by_faces->excludes(line.by_ratio)->excludes(line.by_error)->excludes(line.by_lods);
  line.by_ratio->excludes(line.by_error)->excludes(line.by_lods);
  line.by_error->excludes(line.by_lods);
  line.compare = app.add_option("--compare", line.compare_path,
                                "Measure the level's distance (Hausdorff, RMS) to this original "
                                "mesh and print it on standard output (one input; -o becomes "
                                "optional; with --json, one JSON object)");
  line.compare->excludes(line.by_lods);
  line.max_memory = app.add_option("--max-memory", line.max_memory_text,
                                   "Refuse a .pm whose decoding needs more memory than this "
                                   "(1000000, 512k, 512M, 2G: powers of 1024)")
                        ->type_name("SIZE");
  line.by_morph = app.add_option(
      "--morph", line.morph_text,
      "FROM:TO[:ALPHA]: a geomorph between two levels (face counts or percentages, as in "
      "--lods), blended at ALPHA in [0, 1] (0: FROM's geometry, 1: TO's), with the finer "
      "level's connectivity");
  line.by_frames = app.add_option("--morph-frames", line.morph_frames,
                                  "With --morph FROM:TO: write K frames, alpha from 0 to 1 "
                                  "({frame} in -o numbers them)")
                       ->check(CLI::PositiveNumber)
                       ->needs(line.by_morph);
  line.by_morph->excludes(line.by_vertices)
      ->excludes(line.by_faces)
      ->excludes(line.by_ratio)
      ->excludes(line.by_error)
      ->excludes(line.by_lods)
      ->excludes(line.compare);
  line.by_view = app.add_option(
      "--view", line.view_text,
      "eye=X,Y,Z,target=X,Y,Z[,up=X,Y,Z],fov=DEG,height=PX[,width=PX]: a view-dependent mesh, "
      "refined where its projected error exceeds --pixel-error, coarse outside the view "
      "frustum and where it faces away (up defaults to 0,1,0, width to the height)");
  app.add_option("--pixel-error", line.pixel_error_text,
                 "With --view: the screen-space tolerance in pixels (default 1)")
      ->needs(line.by_view);
  line.by_region = app.add_option(
      "--region", line.region_text,
      "sphere:X,Y,Z,R or box:X0,Y0,Z0,X1,Y1,Z1: full detail inside the region, the base mesh "
      "elsewhere (and what the detail inside needs around it)");
  line.by_viewpoint = app.add_option(
      "--viewpoint", line.viewpoint_text,
      "X,Y,Z: with --faces N or --vertices N, a mesh within that budget that keeps the "
      "vertices nearest the viewpoint first");
  line.exact_ring_flag = app.add_flag(
      "--exact-ring", line.exact_ring,
      "With --view, --region or --viewpoint: apply each split only with every face around its "
      "vertex as it was recorded, so that every face is one of some level (no face joins "
      "vertices that never met; much more refinement is forced)");
  for (auto* other : {line.by_region, line.by_viewpoint, line.by_vertices, line.by_faces,
                      line.by_ratio, line.by_error, line.by_lods, line.by_morph, line.compare})
    line.by_view->excludes(other);
  for (auto* other : {line.by_viewpoint, line.by_vertices, line.by_faces, line.by_ratio,
                      line.by_error, line.by_lods, line.by_morph, line.compare})
    line.by_region->excludes(other);
  for (auto* other : {line.by_ratio, line.by_error, line.by_lods, line.by_morph, line.compare})
    line.by_viewpoint->excludes(other);
  auto* stdin_flag = app.add_flag(
      "--stdin", line.from_stdin,
      "Decode a stream from standard input as it arrives (a download in progress); with "
      "--every N, write a level each time N more faces have arrived; at the end, the finest "
      "level (-o with {faces}: the level's face target, or its face count at the end)");
  app.add_option("--every", line.every, "With --stdin: write a level every N faces")
      ->check(CLI::PositiveNumber)
      ->needs(stdin_flag);
  stdin_flag->excludes(line.by_vertices)
      ->excludes(line.by_faces)
      ->excludes(line.by_ratio)
      ->excludes(line.by_error)
      ->excludes(line.by_lods)
      ->excludes(line.by_morph)
      ->excludes(line.compare)
      ->excludes(line.by_view)
      ->excludes(line.by_region)
      ->excludes(line.by_viewpoint);
  CLI::Option* info_option = app.add_flag(
      "--info", line.info, "Print the header, counts, attributes and error range, and exit");
  app.add_flag("--sizes", line.sizes,
               "With --info: decode the stream and print each section's bytes and the chunk "
               "streams' bits per split (u, vl, vr, positions, attribute ids, ...)")
      ->needs(info_option);
  app.footer(
      "Exit codes: 0 ok, 1 internal error, 2 usage, 3 cannot read input, 4 invalid or\n"
      "truncated .pm, 5 cannot write output, 6 unsupported format or version, 7 too large\n"
      "(or more than --max-memory), 8 several inputs and some failed (each is reported)\n"
      "or ended early, 9 the .pm ended early: the output is the finest level it holds.");
}

}  // namespace pmdec
