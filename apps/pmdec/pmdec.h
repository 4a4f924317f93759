// pmdec's parts, internal to the tool. pmdec.cpp parses the command line (command_line.cpp
// declares its options) and dispatches to the modes, one file each: levels, --lods and
// --error (levels.cpp), --morph (morph.cpp), --view, --region and --viewpoint
// (selective.cpp), --compare (compare.cpp), all written by decode_file.cpp; --stdin
// (stdin.cpp); --info (info.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "batch.h"
#include "batch_options.h"
#include "gltf_output.h"
#include "pm/mesh_io.h"
#include "pm/pm_codec.h"
#include "pm/selective_refinement.h"
#include "pm/surface_distance.h"

namespace pmdec {

inline constexpr const char* kTool = "pmdec";

// One level to write for each input: a single-level option, or one item of --lods.
struct LevelRequest {
  enum class Kind { kFull, kVertices, kFaces, kRatio, kError };
  Kind kind = Kind::kFull;
  std::size_t count = 0;  // vertices or faces
  double ratio = 1;       // kRatio
  std::string label;      // what {lod} stands for; empty without --lods
};

// --error E: a percentage of the bounding-box diagonal ("0.5", "0.5%"), or with --absolute
// model units ("0.5"). Checked before any file is read; the bound in model units depends on
// each mesh's diagonal.
struct ErrorBound {
  double value = 0;
  bool absolute = false;
  bool estimate = false;  // --estimate: select by the errors recorded in the file
};

// levels.cpp
bool parse_error_bound(std::string text, bool absolute, double& value);
bool parse_lods(const std::string& text, std::vector<LevelRequest>& levels);

// --morph FROM:TO[:ALPHA] and --morph-frames K: a geomorph (Hoppe 1996, §4.2) between two
// levels, written at one alpha or at K evenly spaced ones.
struct MorphRequest {
  LevelRequest from, to;
  std::vector<float> alphas;  // one per output
};

// morph.cpp
bool parse_morph(const std::string& text, int frames, MorphRequest& morph);

// --view, --region, --viewpoint: one selectively refined mesh instead of a level (Hoppe 1997,
// "View-dependent refinement of progressive meshes"; pm/selective_refinement.h).
struct SelectiveRequest {
  enum class Kind { kNone, kView, kSphere, kBox, kViewpoint };
  Kind kind = Kind::kNone;
  pm::ViewCamera camera;
  pm::ViewOptions options;
  pm::Point3 a{}, b{};  // sphere centre (radius in radius), box corners, or the viewpoint
  double radius = 0;
  pm::DependencyRule rule = pm::DependencyRule::kHoppe1997;  // --exact-ring: kExactRing
};

// selective.cpp
// Comma-separated finite numbers, exactly `count` of them.
bool parse_numbers(const std::string& text, std::size_t count, std::vector<double>& values);
bool parse_view(const std::string& text, pm::ViewCamera& camera, std::string& problem);
bool parse_region(const std::string& text, SelectiveRequest& request);

struct Settings {
  std::vector<LevelRequest> levels;
  std::optional<MorphRequest> morph;  // the levels are then its frames
  ErrorBound error;
  std::string output_format;  // --format, or empty
  pm::cli::GltfOutputOptions gltf;  // --quantize, --material-from (glTF output)
  bool gltf_chain = false;          // --lods into one glTF file
  pm::ReadOptions read;
  bool skip_existing = false;
  bool create_directories = false;
  const pm::Mesh* compare_with = nullptr;  // --compare ORIGINAL
  bool json_comparison = false;
  // --view, --region, --viewpoint (with the level's --faces/--vertices)
  SelectiveRequest selective;
};

// The command line as parsed (command_line.cpp declares the options): the values, and the
// options whose presence pmdec.cpp asks about.
struct CommandLine {
  pm::cli::BatchCommandLine command;
  std::string error_text, compare_path, lods_text, max_memory_text;
  std::size_t vertices = 0, faces = 0;
  double ratio = 1.0;
  bool info = false;
  bool sizes = false;
  std::string morph_text;
  int morph_frames = 0;
  std::string view_text, pixel_error_text, region_text, viewpoint_text;
  bool exact_ring = false;
  bool from_stdin = false;
  uint64_t every = 0;
  // The options, set by add_options.
  CLI::Option *by_vertices = nullptr, *by_faces = nullptr, *by_ratio = nullptr, *by_error = nullptr,
              *by_lods = nullptr, *compare = nullptr, *max_memory = nullptr, *by_morph = nullptr,
              *by_frames = nullptr, *by_view = nullptr, *by_region = nullptr,
              *by_viewpoint = nullptr, *exact_ring_flag = nullptr, *quantize = nullptr,
              *material_from = nullptr;
};

// command_line.cpp: pmdec's options, in the order --help lists them; --format, --absolute
// and --estimate go straight to `settings`.
void add_options(CLI::App& app, CommandLine& line, Settings& settings);

// info.cpp: pmdec --info [--sizes] on each input.
int print_infos(const pm::cli::BatchCommandLine& command, const pm::ReadOptions& read_options,
                bool with_sizes);

// levels.cpp
pm::Status select_level(const LevelRequest& request, const pm::ProgressiveMesh& progressive,
                        std::size_t full_faces, const Settings& settings, const std::string& input,
                        pm::cli::JobProgress& progress, std::size_t& level);
uint64_t splits_needed(const LevelRequest& request, const pm::PmInfo& info);

// morph.cpp: the frames of settings.morph, with the level each is written as.
pm::Status morph_frames(const pm::ProgressiveMesh& progressive, std::size_t full_faces,
                        const Settings& settings, const std::string& input,
                        pm::cli::JobProgress& progress, std::vector<std::size_t>& levels,
                        std::vector<pm::Mesh>& meshes);

// selective.cpp: settings.selective's mesh; its "level" is the number of splits applied.
pm::Status refine_selectively(const pm::ProgressiveMesh& progressive, const Settings& settings,
                              pm::Mesh& mesh, std::size_t& level);

// compare.cpp
std::string comparison_text(const pm::SurfaceDistance& d, const pm::Mesh& lod, std::size_t level,
                            double seconds, bool json);

// decode_file.cpp
pm::MeshFormat output_format_for(const std::string& output, const std::string& format_option);
void group_materials_for_output(const pm::ProgressiveMesh& progressive, bool extracted,
                                std::size_t level, pm::Mesh& mesh);
pm::cli::Outcome decode_file(const pm::cli::Task& task, pm::cli::JobProgress& progress,
                             const Settings& settings);

// stdin.cpp
int decode_progressively(const Settings& settings, uint64_t every, const std::string& output,
                         bool quiet);

}  // namespace pmdec
