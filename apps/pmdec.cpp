// pmdec: progressive meshes (.pm) in, levels of detail out. Parse, plan, call the library
// per file, report.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <optional>

#include "batch_options.h"
#include "cli_common.h"
#include "pm/lod.h"
#include "pm/lod_runtime.h"
#include "pm/measured_level.h"
#include "pm/mesh_io.h"
#include "pm/pm_codec.h"
#include "pm/selective_refinement.h"
#include "pm/surface_distance.h"

namespace {

constexpr const char* kTool = "pmdec";

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

bool parse_error_bound(std::string text, bool absolute, double& value) {
  const bool percent_sign = !text.empty() && text.back() == '%';
  if (percent_sign) text.pop_back();
  if (percent_sign && absolute) return false;
  try {
    std::size_t used = 0;
    value = std::stod(text, &used);
    return used == text.size() && value >= 0 && std::isfinite(value);
  } catch (const std::exception&) {
    return false;
  }
}

// --lods "100%,25%,5000": percentages of the full-detail faces, or face counts. {lod} is
// each item as written, without its "%".
bool parse_lods(const std::string& text, std::vector<LevelRequest>& levels) {
  levels.clear();
  std::size_t begin = 0;
  for (;;) {
    const std::size_t comma = std::min(text.find(',', begin), text.size());
    std::string item = text.substr(begin, comma - begin);
    item.erase(0, item.find_first_not_of(' '));
    item.erase(item.find_last_not_of(' ') + 1);
    if (item.empty()) return false;
    LevelRequest level;
    const bool percent = item.back() == '%';
    level.label = percent ? item.substr(0, item.size() - 1) : item;
    try {
      std::size_t used = 0;
      if (percent) {
        const double p = std::stod(level.label, &used);
        if (used != level.label.size() || !(p > 0 && p <= 100)) return false;
        level.kind = LevelRequest::Kind::kRatio;
        level.ratio = p / 100;
      } else {
        if (level.label.find_first_not_of("0123456789") != std::string::npos) return false;
        level.kind = LevelRequest::Kind::kFaces;
        level.count = std::stoull(level.label, &used);
      }
    } catch (const std::exception&) {
      return false;
    }
    levels.push_back(level);
    if (comma == text.size()) return true;
    begin = comma + 1;
  }
}

// --morph FROM:TO[:ALPHA] and --morph-frames K: a geomorph (Hoppe 1996, §4.2) between two
// levels, written at one alpha or at K evenly spaced ones.
struct MorphRequest {
  LevelRequest from, to;
  std::vector<float> alphas;  // one per output
};

bool parse_morph(const std::string& text, int frames, MorphRequest& morph) {
  std::vector<std::string> parts;
  std::size_t begin = 0;
  for (std::size_t colon; (colon = text.find(':', begin)) != std::string::npos; begin = colon + 1)
    parts.push_back(text.substr(begin, colon - begin));
  parts.push_back(text.substr(begin));
  if (parts.size() != 2 && parts.size() != 3) return false;
  std::vector<LevelRequest> ends;
  if (!parse_lods(parts[0] + "," + parts[1], ends)) return false;
  morph.from = ends[0];
  morph.to = ends[1];
  morph.alphas.clear();
  if (parts.size() == 3) {
    if (frames) return false;  // one or the other
    try {
      std::size_t used = 0;
      const double alpha = std::stod(parts[2], &used);
      if (used != parts[2].size() || !(alpha >= 0 && alpha <= 1)) return false;
      morph.alphas.push_back(static_cast<float>(alpha));
    } catch (const std::exception&) {
      return false;
    }
  } else {
    if (frames < 1) return false;
    for (int i = 0; i < frames; ++i)
      morph.alphas.push_back(frames == 1 ? 1.0f : float(i) / float(frames - 1));
  }
  return true;
}

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

// Comma-separated finite numbers, exactly `count` of them.
bool parse_numbers(const std::string& text, std::size_t count, std::vector<double>& values) {
  values.clear();
  std::size_t begin = 0;
  for (;;) {
    const std::size_t comma = std::min(text.find(',', begin), text.size());
    const std::string item = text.substr(begin, comma - begin);
    try {
      std::size_t used = 0;
      const double value = std::stod(item, &used);
      if (used != item.size() || !std::isfinite(value)) return false;
      values.push_back(value);
    } catch (const std::exception&) {
      return false;
    }
    if (comma == text.size()) break;
    begin = comma + 1;
  }
  return values.size() == count;
}

// eye=X,Y,Z,target=X,Y,Z[,up=X,Y,Z],fov=DEG,height=PX[,width=PX]: keys in any order.
bool parse_view(const std::string& text, pm::ViewCamera& camera, std::string& problem) {
  const char* keys[] = {"eye=", "target=", "up=", "fov=", "height=", "width="};
  // The positions of the keys split the text; each key's value runs to the next key.
  std::vector<std::pair<std::size_t, int>> found;
  for (int k = 0; k < 6; ++k)
    for (std::size_t at = text.find(keys[k]); at != std::string::npos; at = text.find(keys[k], at + 1))
      if (at == 0 || text[at - 1] == ',') found.push_back({at, k});
  std::sort(found.begin(), found.end());
  if (found.empty() || found[0].first != 0) {
    problem = "expected eye=X,Y,Z,target=X,Y,Z[,up=X,Y,Z],fov=DEG,height=PX[,width=PX]";
    return false;
  }
  bool seen[6] = {};
  for (std::size_t i = 0; i < found.size(); ++i) {
    const int k = found[i].second;
    const std::size_t begin = found[i].first + std::strlen(keys[k]);
    const std::size_t end = i + 1 < found.size() ? found[i + 1].first - 1 : text.size();
    const std::string value = begin <= end ? text.substr(begin, end - begin) : "";
    const std::string name(keys[k], std::strlen(keys[k]) - 1);
    if (seen[k]) {
      problem = name + " given twice";
      return false;
    }
    seen[k] = true;
    std::vector<double> numbers;
    if (!parse_numbers(value, k < 3 ? 3 : 1, numbers)) {
      problem = name + "=" + value + ": expected " + (k < 3 ? "three numbers X,Y,Z" : "a number");
      return false;
    }
    pm::Point3* points[] = {&camera.eye, &camera.target, &camera.up};
    if (k < 3) *points[k] = {numbers[0], numbers[1], numbers[2]};
    if (k == 3) camera.fov_degrees = numbers[0];
    if (k == 4) camera.viewport_height = numbers[0];
    if (k == 5) camera.viewport_width = numbers[0];
  }
  for (int k : {0, 1, 3, 4})
    if (!seen[k]) {
      problem = std::string("missing ") + std::string(keys[k], std::strlen(keys[k]) - 1);
      return false;
    }
  if (pm::Status s = pm::check_camera(camera); !s) {
    problem = s.message();
    return false;
  }
  return true;
}

// sphere:X,Y,Z,R or box:X0,Y0,Z0,X1,Y1,Z1.
bool parse_region(const std::string& text, SelectiveRequest& request) {
  std::vector<double> v;
  if (text.rfind("sphere:", 0) == 0 && parse_numbers(text.substr(7), 4, v) && v[3] >= 0) {
    request.kind = SelectiveRequest::Kind::kSphere;
    request.a = {v[0], v[1], v[2]};
    request.radius = v[3];
    return true;
  }
  if (text.rfind("box:", 0) == 0 && parse_numbers(text.substr(4), 6, v) && v[0] <= v[3] &&
      v[1] <= v[4] && v[2] <= v[5]) {
    request.kind = SelectiveRequest::Kind::kBox;
    request.a = {v[0], v[1], v[2]};
    request.b = {v[3], v[4], v[5]};
    return true;
  }
  return false;
}

struct Settings {
  std::vector<LevelRequest> levels;
  std::optional<MorphRequest> morph;  // the levels are then its frames
  ErrorBound error;
  std::string output_format;  // --format, or empty
  pm::ReadOptions read;
  bool skip_existing = false;
  bool create_directories = false;
  const pm::Mesh* compare_with = nullptr;  // --compare ORIGINAL
  bool json_comparison = false;
  SelectiveRequest selective;  // --view, --region, --viewpoint (with the level's --faces/--vertices)
};

pm::MeshFormat output_format_for(const std::string& output, const std::string& format_option) {
  if (!format_option.empty()) return pm::mesh_format_from_path("." + format_option);
  if (output == "-") return pm::MeshFormat::kObj;
  return pm::mesh_format_from_path(output);
}

// --sizes: where the bytes go (pm::measure_pm_sizes), the chunk streams in bits per split.
int print_sizes(const std::string& input, const std::string& bytes, uint32_t splits,
                const pm::ReadOptions& read_options) {
  pm::PmSizes sizes;
  if (pm::Status s = pm::measure_pm_sizes(bytes, sizes, read_options); !s)
    return pm::cli::fail(kTool, input, s);
  std::string sections = "header " + std::to_string(sizes.header) + " B";
  for (const auto& [tag, size] : sizes.sections) {
    sections += ", " + tag + " " + std::to_string(size) + " B";
    if (tag == "CHNK") sections += " (" + std::to_string(sizes.chunks) + " chunks)";
  }
  std::printf("sections:         %s\n", sections.c_str());
  if (splits == 0) return pm::cli::kExitOk;
  // Each stream compressed alone: about what it costs in the file.
  std::string streams;
  for (std::size_t k = 0; k < sizes.chunk_streams.size(); ++k) {
    if (sizes.chunk_streams[k].second == 0) continue;
    char text[96];
    std::snprintf(text, sizeof text, "%s%s %.2f", streams.empty() ? "" : ", ",
                  sizes.chunk_streams[k].first.c_str(),
                  8.0 * double(sizes.chunk_streams_compressed[k]) / double(splits));
    streams += text;
  }
  std::printf("chunk streams:    bits per split, each alone with zstd -19: %s\n", streams.c_str());
  return pm::cli::kExitOk;
}

int print_info(const std::string& input, const pm::ReadOptions& read_options, bool with_sizes) {
  std::string bytes;
  if (pm::Status s = pm::cli::read_whole_input(input, bytes, read_options.max_memory); !s)
    return pm::cli::fail(kTool, input, s);
  pm::PmInfo info;
  if (pm::Status s = pm::read_pm_info(bytes, info); !s) return pm::cli::fail(kTool, input, s);
  std::printf("file:             %s (%zu bytes)\n", input.c_str(), bytes.size());
  std::printf("format version:   %u.%u\n", info.major, info.minor);
  std::string attributes;
  auto add = [&attributes](const std::string& item) {
    attributes += (attributes.empty() ? "" : "; ") + item;
  };
  if (info.color_components) add(info.color_components == 4 ? "colours (rgba)" : "colours (rgb)");
  if (info.uv_count || info.has_uvs)
    add(std::to_string(info.uv_count) + " texture coordinates" +
        (info.has_uvs ? " per corner" : " (table only)"));
  if (info.normal_count || info.has_normals)
    add(std::to_string(info.normal_count) + " normals" +
        (info.has_normals ? " per corner" : " (table only)"));
  if (info.material_count || info.has_materials)
    add(std::to_string(info.material_count) + " materials" +
        (info.has_materials ? " per face" : " (table only)"));
  if (info.material_library_count)
    add(std::to_string(info.material_library_count) + " material " +
        (info.material_library_count == 1 ? "library" : "libraries"));
  std::printf("flags:            0x%08x\n", info.flags);
  std::printf("attributes:       %s\n", attributes.empty() ? "none" : attributes.c_str());
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
  if (info.major >= 2) {
    const auto bits = [](uint32_t b) { return b == 0 ? std::string("lossless") : std::to_string(b) + " bits"; };
    // 2.3: lossless positions on the grid of their decimals.
    const std::string positions =
        info.positions_decimal      ? "lossless (decimals, a " + std::to_string(info.position_bits) + "-bit grid)"
        : info.positions_significant ? std::string("lossless (decimals of a few significant digits)")
                                     : bits(info.position_bits);
    const auto table = [&](uint32_t b, bool significant) {
      return significant ? std::string("lossless (decimals of a few significant digits)") : bits(b);
    };
    std::printf("quantization:     positions %s, texture coordinates %s, normals %s\n",
                positions.c_str(), table(info.uv_bits, info.uvs_significant).c_str(),
                table(info.normal_bits, info.normals_significant).c_str());
    // The index: what a reader decompresses for a level (pm-format.md §5.6).
    std::printf("chunks:           %zu", info.chunks.size());
    if (!info.chunks.empty()) {
      const pm::PmInfo::Chunk& first = info.chunks.front();
      std::printf(" (the first: %u splits, %llu faces after it, ending at byte %llu)", first.splits,
                  static_cast<unsigned long long>(first.faces_after),
                  static_cast<unsigned long long>(first.stream_end));
    }
    std::printf("\n");
  }
  if (with_sizes) return print_sizes(input, bytes, info.split_count, read_options);
  return pm::cli::kExitOk;
}

// --compare: one line for people, or one JSON object for scripts (--json). A percentage of
// a zero diagonal (a flat point) has no value: "n/a", or null in JSON.
std::string comparison_text(const pm::SurfaceDistance& d, const pm::Mesh& lod, std::size_t level,
                            double seconds, bool json) {
  const bool has_diagonal = d.diagonal > 0;
  const double hausdorff_percent = has_diagonal ? 100 * d.hausdorff / d.diagonal : 0;
  const double rms_percent = has_diagonal ? 100 * d.rms / d.diagonal : 0;
  char text[512];
  if (!json) {
    char percents[2][32] = {"n/a", "n/a"};
    if (has_diagonal) {
      std::snprintf(percents[0], sizeof percents[0], "%.3g%%", hausdorff_percent);
      std::snprintf(percents[1], sizeof percents[1], "%.3g%%", rms_percent);
    }
    std::snprintf(text, sizeof text,
                  "hausdorff %.6g (%s of diagonal) rms %.6g (%s) faces %zu samples %zu\n",
                  d.hausdorff, percents[0], d.rms, percents[1], lod.face_count(), d.samples);
    return text;
  }
  char percents[2][32] = {"null", "null"};
  if (has_diagonal) {
    std::snprintf(percents[0], sizeof percents[0], "%.17g", hausdorff_percent);
    std::snprintf(percents[1], sizeof percents[1], "%.17g", rms_percent);
  }
  std::snprintf(text, sizeof text,
                "{\"faces\":%zu,\"vertices\":%zu,\"level\":%zu,\"hausdorff\":%.17g,\"rms\":%.17g,"
                "\"hausdorff_percent\":%s,\"rms_percent\":%s,\"diagonal\":%.17g,\"samples\":%zu,"
                "\"seconds\":%.3f}\n",
                lod.face_count(), lod.vertex_count(), level, d.hausdorff, d.rms, percents[0],
                percents[1], d.diagonal, d.samples, seconds);
  return text;
}

// The level a request selects in this file.
// `full_faces` is the stream's, which the mesh lacks when only a prefix of it was decoded.
pm::Status select_level(const LevelRequest& request, const pm::ProgressiveMesh& progressive,
                        std::size_t full_faces, const Settings& settings, const std::string& input,
                        pm::cli::JobProgress& progress, std::size_t& level) {
  level = progressive.splits.size();
  switch (request.kind) {
    case LevelRequest::Kind::kFull:
      return pm::Status::ok();
    case LevelRequest::Kind::kVertices:
      level = pm::level_for_vertices(progressive, request.count);
      return pm::Status::ok();
    case LevelRequest::Kind::kFaces:
    case LevelRequest::Kind::kRatio: {
      const std::size_t wanted =
          request.kind == LevelRequest::Kind::kFaces
              ? request.count
              : static_cast<std::size_t>(std::llround(request.ratio * full_faces));
      level = pm::level_for_faces(progressive, wanted);
      const std::size_t base_faces = pm::faces_at_level(progressive, 0);
      if (wanted < base_faces)
        progress.note(input + ": " + std::to_string(wanted) +
                      " faces requested; the base mesh has " + std::to_string(base_faces));
      return pm::Status::ok();
    }
    case LevelRequest::Kind::kError: {
      const double bound =
          settings.error.absolute
              ? settings.error.value
              : settings.error.value * pm::bounding_box_diagonal(progressive.positions) / 100.0;
      if (settings.error.estimate) {
        level = pm::level_for_error(progressive, bound);
        return pm::Status::ok();
      }
      const auto search_start = std::chrono::steady_clock::now();
      pm::MeasuredLevel found;
      if (pm::Status s = pm::level_for_measured_error(progressive, bound, {}, found); !s) return s;
      level = found.level;
      const double diagonal = found.distance.diagonal;
      char note[256];
      std::snprintf(note, sizeof note,
                    ": measured Hausdorff %.6g (%.4g%% of diagonal) <= %.6g, %zu levels "
                    "measured, %.2f s",
                    found.distance.hausdorff,
                    diagonal > 0 ? 100 * found.distance.hausdorff / diagonal : 0.0, bound,
                    found.measurements, pm::cli::seconds_since(search_start));
      progress.note(input + note);
      return pm::Status::ok();
    }
  }
  return pm::Status::ok();
}

// The splits a request needs, from a 2.x stream's chunk index (Hoppe 1996, §3: a level
// needs only the splits before it): the end of the first chunk whose level has the faces or
// vertices asked for. Full detail and error bounds need every split (an error bound is a
// share of the whole mesh's bounding box).
uint64_t splits_needed(const LevelRequest& request, const pm::PmInfo& info) {
  if (info.chunks.empty()) return UINT64_MAX;
  uint64_t wanted = 0;
  bool by_vertices = false;
  switch (request.kind) {
    case LevelRequest::Kind::kVertices:
      wanted = request.count;
      by_vertices = true;
      break;
    case LevelRequest::Kind::kFaces:
      wanted = request.count;
      break;
    case LevelRequest::Kind::kRatio:
      wanted = static_cast<uint64_t>(std::llround(request.ratio * double(info.full_face_count)));
      break;
    default:
      return UINT64_MAX;
  }
  uint64_t splits = 0;
  for (const pm::PmInfo::Chunk& chunk : info.chunks) {
    splits += chunk.splits;
    if ((by_vertices ? chunk.vertices_after : chunk.faces_after) >= wanted) return splits;
  }
  return UINT64_MAX;
}

// What one written level says in the JSON ("null" members until it is written).
struct WrittenLevel {
  std::string output, label;
  bool written = false;
  std::size_t level = 0, faces = 0, vertices = 0;
};

// `stream` is the stream's full face count and split count, once it is read.
struct StreamCounts {
  std::size_t full_faces = 0, splits = 0;
  bool truncated = false;
};
std::string json_members(const std::vector<WrittenLevel>& levels, const StreamCounts* stream) {
  auto number = [](bool known, std::size_t value) {
    return known ? std::to_string(value) : std::string("null");
  };
  std::string json = "\"outputs\":[";
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const WrittenLevel& l = levels[i];
    json += std::string(i ? "," : "") +
            "{\"output\":" + (l.output.empty() ? "null" : pm::cli::json_string(l.output)) +
            ",\"lod\":" + (l.label.empty() ? "null" : pm::cli::json_string(l.label)) +
            ",\"level\":" + number(l.written, l.level) +
            ",\"faces\":" + number(l.written, l.faces) +
            ",\"vertices\":" + number(l.written, l.vertices) + "}";
  }
  json += "],\"full_faces\":" + number(stream, stream ? stream->full_faces : 0) +
          ",\"splits\":" + number(stream, stream ? stream->splits : 0);
  if (stream && stream->truncated) json += ",\"truncated\":true";
  return json;
}

// Faces grouped by material for writing (one usemtl per material), unless the mesh is
// the input's own order, which the output keeps: a level from extract_level at full detail
// of a stream made with --keep-order (a selective mesh or a geomorph never is).
void group_materials_for_output(const pm::ProgressiveMesh& progressive, bool extracted,
                                std::size_t level, pm::Mesh& mesh) {
  if (!(extracted && progressive.keeps_order() && level == progressive.splits.size()))
    pm::group_faces_by_material(mesh);
}

pm::cli::Outcome decode_file(const pm::cli::Task& task, pm::cli::JobProgress& progress,
                             const Settings& settings) {
  const auto start = std::chrono::steady_clock::now();
  const std::string& input = task.input.path;
  std::vector<WrittenLevel> written(settings.levels.size());
  for (std::size_t i = 0; i < written.size(); ++i) {
    written[i].label = settings.levels[i].label;
    if (i < task.outputs.size()) written[i].output = task.outputs[i];
  }
  pm::cli::Outcome outcome;
  outcome.json = json_members(written, nullptr);
  auto failed = [&outcome](const pm::Status& status) {
    outcome.status = status;
    outcome.exit_code = pm::cli::exit_code_for(status.code());
    return outcome;
  };
  if (!task.input.problem) return failed(task.input.problem);
  if (settings.skip_existing && pm::cli::all_outputs_exist(task)) {
    outcome.skipped = true;
    outcome.summary = input + ": skipped, its outputs exist";
    return outcome;
  }

  std::string bytes;
  if (pm::Status s = pm::cli::read_whole_input(input, bytes, settings.read.max_memory); !s)
    return failed(s);
  // A 2.x stream's index says which chunks the requested levels need: only those are
  // decompressed. A stream cut short decodes to the finest level it holds, with a warning.
  pm::ReadOptions read_options = settings.read;
  read_options.allow_truncated = true;
  pm::PmInfo info;
  const bool indexed = pm::read_pm_info(bytes, info).is_ok();
  // Selective refinement may need any split: the whole stream.
  if (indexed && !settings.compare_with && settings.selective.kind == SelectiveRequest::Kind::kNone) {
    read_options.max_splits = 0;
    std::vector<LevelRequest> requests = settings.levels;
    if (settings.morph) requests = {settings.morph->from, settings.morph->to};
    for (const LevelRequest& request : requests)
      read_options.max_splits = std::max(read_options.max_splits, splits_needed(request, info));
  }
  pm::ProgressiveMesh progressive;
  pm::ReadResult read_result;
  if (pm::Status s = pm::read_pm(bytes, progressive, read_options, &read_result); !s)
    return failed(s);
  std::string().swap(bytes);  // frees the buffer (assigning an empty string keeps it)
  if (read_result.truncated) {
    progress.note(input + ": warning: " + read_result.warning +
                  "; writing the finest level it holds");
    outcome.exit_code = pm::cli::kExitTruncated;
  }
  const std::size_t full_faces =
      indexed ? static_cast<std::size_t>(info.full_face_count)
              : pm::faces_at_level(progressive, progressive.splits.size());
  if (!task.conflict) return failed(task.conflict);

  // The meshes to write: each requested level, all from one walk over the splits
  // (pm::extract_levels), or the frames of a geomorph.
  std::vector<std::size_t> levels(settings.levels.size());
  std::vector<pm::Mesh> meshes(settings.levels.size());
  const bool selective = settings.selective.kind != SelectiveRequest::Kind::kNone;
  if (selective) {
    // One selectively refined mesh; its "level" is the number of splits applied.
    const SelectiveRequest& request = settings.selective;
    pm::SelectiveRefinement refinement(progressive, request.rule);
    switch (request.kind) {
      case SelectiveRequest::Kind::kView:
        if (pm::Status s = refinement.set_view(request.camera, request.options); !s) return failed(s);
        break;
      case SelectiveRequest::Kind::kSphere:
        refinement.refine_sphere(request.a, request.radius);
        break;
      case SelectiveRequest::Kind::kBox:
        refinement.refine_box(request.a, request.b);
        break;
      case SelectiveRequest::Kind::kViewpoint: {
        const LevelRequest& budget = settings.levels.front();
        const std::size_t faces = budget.kind == LevelRequest::Kind::kFaces ? budget.count : 0;
        const std::size_t vertices = budget.kind == LevelRequest::Kind::kVertices ? budget.count : 0;
        if (pm::Status s = refinement.refine_toward(request.a, faces, vertices); !s) return failed(s);
        break;
      }
      case SelectiveRequest::Kind::kNone:
        break;
    }
    meshes[0] = refinement.to_mesh();
    levels[0] = refinement.applied_count();
  } else if (settings.morph) {
    std::size_t from = 0, to = 0;
    if (pm::Status s = select_level(settings.morph->from, progressive, full_faces, settings, input, progress, from); !s)
      return failed(s);
    if (pm::Status s = select_level(settings.morph->to, progressive, full_faces, settings, input, progress, to); !s)
      return failed(s);
    // A geomorph runs from the coarser level to the finer; FROM finer than TO runs it backwards.
    const bool backwards = from > to;
    pm::RuntimeLod lod(progressive);
    const pm::RuntimeLod::Geomorph morph = lod.geomorph(std::min(from, to), std::max(from, to));
    for (std::size_t i = 0; i < meshes.size(); ++i) {
      const float alpha = settings.morph->alphas[i];
      meshes[i] = morph.mesh(backwards ? 1.0f - alpha : alpha);
      levels[i] = std::max(from, to);
    }
  } else {
    for (std::size_t i = 0; i < settings.levels.size(); ++i)
      if (pm::Status s =
              select_level(settings.levels[i], progressive, full_faces, settings, input, progress, levels[i]);
          !s)
        return failed(s);
    pm::extract_levels(progressive, levels, [&](std::size_t level, const pm::Mesh& mesh) {
      for (std::size_t i = 0; i < levels.size(); ++i)
        if (levels[i] == level) meshes[i] = mesh;
    });
  }

  std::string faces_list;
  pm::Mesh last;
  for (std::size_t i = 0; i < settings.levels.size(); ++i) {
    const std::size_t level = levels[i];
    last = std::move(meshes[i]);
    group_materials_for_output(progressive, !selective && !settings.morph, level, last);
    if (!written[i].output.empty()) {
      const std::string& output = written[i].output;
      const pm::MeshFormat format = output_format_for(output, settings.output_format);
      std::string encoded;
      if (pm::Status s = pm::write_mesh_to_memory(last, format, encoded); !s) {
        outcome.error_file = output;
        return failed(s);
      }
      const bool binary = format == pm::MeshFormat::kPly || format == pm::MeshFormat::kStl;
      pm::Status s =
          settings.create_directories ? pm::cli::make_parent_directories(output) : pm::Status::ok();
      if (s) s = pm::cli::write_output_atomically(output, encoded, binary);
      if (!s) {
        failed(s);
        outcome.exit_code = pm::cli::exit_code_for_write(s);
        outcome.error_file = output;
        return outcome;
      }
    }
    written[i].written = true;
    written[i].level = level;
    written[i].faces = last.face_count();
    written[i].vertices = last.vertex_count();
    outcome.faces += last.face_count();
    faces_list += (i ? ", " : "") + std::to_string(last.face_count());
    progress.set_faces(outcome.faces);
    progress.set_fraction(static_cast<double>(i + 1) / settings.levels.size());
  }
  if (settings.compare_with) {
    const auto compare_start = std::chrono::steady_clock::now();
    pm::SurfaceDistance distance;
    if (pm::Status s = pm::measure_surface_distance(*settings.compare_with, last, {}, distance); !s)
      return failed(s);
    outcome.stdout_text =
        comparison_text(distance, last, written.front().level,
                        pm::cli::seconds_since(compare_start), settings.json_comparison);
  }
  // The error bound of a level; the last level of a prefix has the index's (it is not full
  // detail, whose bound is 0).
  const auto level_error = [&](std::size_t level) {
    if (indexed && level == progressive.splits.size() && level < info.split_count) {
      uint64_t splits = 0;
      for (const pm::PmInfo::Chunk& chunk : info.chunks)
        if ((splits += chunk.splits) == level) return chunk.error_after;
    }
    return pm::error_at_level(progressive, level);
  };
  StreamCounts counts;
  counts.full_faces = full_faces;
  counts.splits = indexed ? info.split_count : progressive.splits.size();
  counts.truncated = read_result.truncated;
  outcome.json = json_members(written, &counts);
  char summary[256];
  const std::string name = input == "-" ? "(stdin)" : input;
  if (selective) {
    std::snprintf(summary, sizeof summary,
                  ": selective: %zu of %zu splits applied: %zu faces, %zu vertices, %.2f s",
                  written[0].level, progressive.splits.size(), written[0].faces,
                  written[0].vertices, pm::cli::seconds_since(start));
    outcome.summary = name + summary;
  } else if (written.size() == 1) {
    std::snprintf(summary, sizeof summary,
                  ": level %zu of %zu: %zu faces, %zu vertices, recorded error %.6g, %.2f s",
                  written[0].level, counts.splits, written[0].faces,
                  written[0].vertices, double(level_error(written[0].level)),
                  pm::cli::seconds_since(start));
    outcome.summary = name + summary;
  } else {
    std::snprintf(summary, sizeof summary, " faces, %.2f s", pm::cli::seconds_since(start));
    outcome.summary =
        name + ": " + std::to_string(written.size()) + " levels: " + faces_list + summary;
  }
  return outcome;
}

// pmdec --stdin [--every N]: the stream decoded as it arrives (Hoppe 1996, §3, progressive
// transmission), a level written each time N more faces have arrived, and the finest level
// at the end.
int decode_progressively(const Settings& settings, uint64_t every, const std::string& output,
                         bool quiet) {
  const std::string input = "(stdin)";
  pm::ReadOptions options = settings.read;
  options.allow_truncated = true;
  pm::PmStreamReader reader(options);
  const auto write_level = [&](uint64_t name_faces, std::size_t level) {
    pm::Mesh mesh = pm::extract_level(reader.mesh(), level);
    group_materials_for_output(reader.mesh(), true, level, mesh);
    std::string path = output;
    path.replace(path.find("{faces}"), 7, std::to_string(name_faces));
    const pm::MeshFormat format = output_format_for(path, settings.output_format);
    std::string encoded;
    pm::Status s = pm::write_mesh_to_memory(mesh, format, encoded);
    if (s && settings.create_directories) s = pm::cli::make_parent_directories(path);
    if (s) {
      s = pm::cli::write_output_atomically(
          path, encoded, format == pm::MeshFormat::kPly || format == pm::MeshFormat::kStl);
    }
    if (!s) return pm::cli::fail(kTool, path, s);
    if (!quiet)
      std::cerr << kTool << ": " << path << ": level " << level << ", " << mesh.face_count()
                << " faces\n";
    return static_cast<int>(pm::cli::kExitOk);
  };
  uint64_t next = every;
  std::vector<char> buffer(1 << 16);
  for (;;) {
    const std::size_t n = std::fread(buffer.data(), 1, buffer.size(), stdin);
    if (n == 0) break;
    if (pm::Status s = reader.append(std::string_view(buffer.data(), n)); !s)
      return pm::cli::fail(kTool, input, s);
    while (every != 0 && reader.has_base() && reader.decoded_face_count() >= next) {
      const pm::ProgressiveMesh& mesh = reader.mesh();
      if (const int code = write_level(next, pm::level_for_faces(mesh, next)); code != 0) return code;
      next += every;
    }
  }
  if (std::ferror(stdin)) {
    return pm::cli::fail(kTool, input, pm::Status(pm::ErrorCode::kIoError, "cannot read standard input"));
  }
  pm::ReadResult result;
  if (pm::Status s = reader.finish(&result); !s) return pm::cli::fail(kTool, input, s);
  if (result.truncated && !quiet)
    std::cerr << kTool << ": " << input << ": warning: " << result.warning << "\n";
  const pm::ProgressiveMesh& mesh = reader.mesh();
  if (const int code = write_level(reader.decoded_face_count(), mesh.splits.size()); code != 0)
    return code;
  return result.truncated ? pm::cli::kExitTruncated : pm::cli::kExitOk;
}

int fail_usage(const std::string& message) {
  std::cerr << kTool << ": " << message << "\n";
  return pm::cli::kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "pmdec: decode levels of detail from progressive meshes (.pm).\n"
      "Without a level option, writes full detail: the input mesh, exactly.\n"
      "Many inputs are decoded at once (-j); a failure does not stop the others."};
  app.set_version_flag("--version", std::string("pmdec ") + PM_VERSION_STRING);
  pm::cli::BatchCommandLine command;
  Settings settings;
  std::string error_text, compare_path, lods_text, max_memory_text;
  std::size_t vertices = 0, faces = 0;
  double ratio = 1.0;
  bool info = false;
  bool sizes = false;
  command.add_options(
      app, "Input .pm files, directories (with -r), or - for standard input",
      "Output mesh, - for OBJ on standard output, or a template: {stem} {ext} {name} {dir} "
      "{lod}; the extension picks OBJ, PLY, OFF or STL (default with --out-dir: "
      "{dir}/{stem}.obj, with --lods {dir}/{stem}_{lod}.obj)");
  app.add_option("--format", settings.output_format,
                 "Output format, overriding the extension (obj, ply, off, stl)");
  auto* by_vertices =
      app.add_option("--vertices", vertices, "Level with at least this many vertices")
          ->check(pm::cli::whole_number());
  auto* by_faces = app.add_option("--faces", faces,
                                  "Level with this many faces (one more where a split adds two)")
                       ->check(pm::cli::whole_number());
  auto* by_ratio = app.add_option("--ratio", ratio, "Level with this fraction of the full faces")
                       ->check(CLI::Range(0.0, 1.0));
  auto* by_error = app.add_option(
      "--error", error_text,
      "Coarsest level whose measured Hausdorff distance to full detail is at most E percent "
      "of the bounding-box diagonal (E or E%); see --absolute and --estimate");
  auto* by_lods = app.add_option(
      "--lods", lods_text,
      "Several levels per input, comma-separated: percentages of the full faces (25%) or "
      "face counts (5000); name the outputs with {lod} in -o");
  app.add_flag("--absolute", settings.error.absolute, "With --error: E is in model units")
      ->needs(by_error);
  app.add_flag("--estimate", settings.error.estimate,
               "With --error: select by the errors recorded in the file, without measuring "
               "(instant, but not a guarantee)")
      ->needs(by_error);
  by_vertices->excludes(by_faces)->excludes(by_ratio)->excludes(by_error)->excludes(by_lods);
  by_faces->excludes(by_ratio)->excludes(by_error)->excludes(by_lods);
  by_ratio->excludes(by_error)->excludes(by_lods);
  by_error->excludes(by_lods);
  auto* compare = app.add_option("--compare", compare_path,
                                 "Measure the level's distance (Hausdorff, RMS) to this original "
                                 "mesh and print it on standard output (one input; -o becomes "
                                 "optional; with --json, one JSON object)");
  compare->excludes(by_lods);
  auto* max_memory = app.add_option("--max-memory", max_memory_text,
                                    "Refuse a .pm whose decoding needs more memory than this "
                                    "(1000000, 512k, 512M, 2G: powers of 1024)")
                         ->type_name("SIZE");
  std::string morph_text;
  int morph_frames = 0;
  auto* by_morph = app.add_option(
      "--morph", morph_text,
      "FROM:TO[:ALPHA]: a geomorph between two levels (face counts or percentages, as in "
      "--lods), blended at ALPHA in [0, 1] (0: FROM's geometry, 1: TO's), with the finer "
      "level's connectivity");
  auto* by_frames = app.add_option("--morph-frames", morph_frames,
                                   "With --morph FROM:TO: write K frames, alpha from 0 to 1 "
                                   "({frame} in -o numbers them)")
                        ->check(CLI::PositiveNumber)
                        ->needs(by_morph);
  by_morph->excludes(by_vertices)->excludes(by_faces)->excludes(by_ratio)->excludes(by_error)
      ->excludes(by_lods)->excludes(compare);
  std::string view_text, pixel_error_text, region_text, viewpoint_text;
  auto* by_view = app.add_option(
      "--view", view_text,
      "eye=X,Y,Z,target=X,Y,Z[,up=X,Y,Z],fov=DEG,height=PX[,width=PX]: a view-dependent mesh, "
      "refined where its projected error exceeds --pixel-error, coarse outside the view "
      "frustum and where it faces away (up defaults to 0,1,0, width to the height)");
  app.add_option("--pixel-error", pixel_error_text,
                 "With --view: the screen-space tolerance in pixels (default 1)")
      ->needs(by_view);
  auto* by_region = app.add_option(
      "--region", region_text,
      "sphere:X,Y,Z,R or box:X0,Y0,Z0,X1,Y1,Z1: full detail inside the region, the base mesh "
      "elsewhere (and what the detail inside needs around it)");
  auto* by_viewpoint = app.add_option(
      "--viewpoint", viewpoint_text,
      "X,Y,Z: with --faces N or --vertices N, a mesh within that budget that keeps the "
      "vertices nearest the viewpoint first");
  bool exact_ring = false;
  auto* exact_ring_flag = app.add_flag(
      "--exact-ring", exact_ring,
      "With --view, --region or --viewpoint: apply each split only with every face around its "
      "vertex as it was recorded, so that every face is one of some level (no face joins "
      "vertices that never met; much more refinement is forced)");
  for (auto* other : {by_region, by_viewpoint, by_vertices, by_faces, by_ratio, by_error, by_lods,
                      by_morph, compare})
    by_view->excludes(other);
  for (auto* other : {by_viewpoint, by_vertices, by_faces, by_ratio, by_error, by_lods, by_morph,
                      compare})
    by_region->excludes(other);
  for (auto* other : {by_ratio, by_error, by_lods, by_morph, compare}) by_viewpoint->excludes(other);
  bool from_stdin = false;
  uint64_t every = 0;
  auto* stdin_flag = app.add_flag(
      "--stdin", from_stdin,
      "Decode a stream from standard input as it arrives (a download in progress); with "
      "--every N, write a level each time N more faces have arrived; at the end, the finest "
      "level (-o with {faces}: the level's face target, or its face count at the end)");
  app.add_option("--every", every, "With --stdin: write a level every N faces")
      ->check(CLI::PositiveNumber)
      ->needs(stdin_flag);
  stdin_flag->excludes(by_vertices)->excludes(by_faces)->excludes(by_ratio)->excludes(by_error)
      ->excludes(by_lods)->excludes(by_morph)->excludes(compare)->excludes(by_view)
      ->excludes(by_region)->excludes(by_viewpoint);
  CLI::Option* info_option =
      app.add_flag("--info", info, "Print the header, counts, attributes and error range, and exit");
  app.add_flag("--sizes", sizes,
               "With --info: decode the stream and print each section's bytes and the chunk "
               "streams' bits per split (u, vl, vr, positions, attribute ids, ...)")
      ->needs(info_option);
  app.footer(
      "Exit codes: 0 ok, 1 internal error, 2 usage, 3 cannot read input, 4 invalid or\n"
      "truncated .pm, 5 cannot write output, 6 unsupported format or version, 7 too large\n"
      "(or more than --max-memory), 8 several inputs and some failed (each is reported)\n"
      "or ended early, 9 the .pm ended early: the output is the finest level it holds.");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? pm::cli::kExitOk : pm::cli::kExitUsage;
  }
  if (max_memory->count() > 0 && !pm::cli::parse_size(max_memory_text, settings.read.max_memory))
    return fail_usage("--max-memory " + max_memory_text +
                      ": expected a positive size such as 1000000, 512M or 2G");

  if (info) {
    std::vector<pm::cli::Input> inputs;
    pm::cli::InputOptions input_options{command.inputs, command.lists, command.recursive, {"pm"}};
    if (command.inputs.empty() && command.lists.empty())
      return fail_usage("no input: give files, directories with -r, or --from-list FILE");
    if (pm::Status s = pm::cli::gather_inputs(input_options, inputs); !s) {
      std::cerr << kTool << ": " << s.message() << "\n";
      return pm::cli::exit_code_for(s.code());
    }
    int exit_code = pm::cli::kExitOk;
    std::size_t failures = 0;
    for (std::size_t i = 0; i < inputs.size(); ++i) {
      if (i > 0) std::printf("\n");
      exit_code = inputs[i].problem ? print_info(inputs[i].path, settings.read, sizes)
                                    : pm::cli::fail(kTool, inputs[i].path, inputs[i].problem);
      if (exit_code != pm::cli::kExitOk) ++failures;
    }
    if (inputs.size() == 1) return exit_code;
    return failures ? pm::cli::kExitSomeFailed : pm::cli::kExitOk;
  }

  if (from_stdin) {
    if (!command.inputs.empty() || !command.lists.empty())
      return fail_usage("--stdin reads standard input: give no input files");
    if (command.output.empty() || command.output == "-" ||
        command.output.find("{faces}") == std::string::npos)
      return fail_usage("--stdin needs -o with {faces} in it, e.g. -o 'lod_{faces}.obj'");
    return decode_progressively(settings, every, command.output, command.quiet);
  }
  if (command.output.empty() && command.out_dir.empty() && compare_path.empty())
    return fail_usage(
        "no output given (use -o FILE, -o - for OBJ on standard output, or --out-dir DIR)");
  if (command.output == "-" && !compare_path.empty())
    return fail_usage("--compare prints on standard output: write the mesh to a file");

  SelectiveRequest& selective = settings.selective;
  if (*exact_ring_flag && !*by_view && !*by_region && !*by_viewpoint)
    return fail_usage("--exact-ring needs --view, --region or --viewpoint");
  if (exact_ring) selective.rule = pm::DependencyRule::kExactRing;
  if (*by_view) {
    std::string problem;
    if (!parse_view(view_text, selective.camera, problem))
      return fail_usage("--view " + view_text + ": " + problem);
    selective.kind = SelectiveRequest::Kind::kView;
    std::vector<double> p;
    if (!pixel_error_text.empty()) {
      if (!parse_numbers(pixel_error_text, 1, p) || !(p[0] > 0))
        return fail_usage("--pixel-error " + pixel_error_text + ": expected a positive number of pixels");
      selective.options.pixel_error = p[0];
    }
  } else if (*by_region) {
    if (!parse_region(region_text, selective))
      return fail_usage("--region " + region_text +
                        ": expected sphere:X,Y,Z,R (R >= 0) or box:X0,Y0,Z0,X1,Y1,Z1 (X0 <= X1, "
                        "Y0 <= Y1, Z0 <= Z1)");
  } else if (*by_viewpoint) {
    std::vector<double> p;
    if (!parse_numbers(viewpoint_text, 3, p))
      return fail_usage("--viewpoint " + viewpoint_text + ": expected three numbers X,Y,Z");
    if (!*by_faces && !*by_vertices)
      return fail_usage("--viewpoint needs a budget: --faces N or --vertices N");
    selective.kind = SelectiveRequest::Kind::kViewpoint;
    selective.a = {p[0], p[1], p[2]};
  }

  LevelRequest single;
  if (*by_morph) {
    MorphRequest morph;
    if (!parse_morph(morph_text, morph_frames, morph))
      return fail_usage("--morph " + morph_text +
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
  } else if (*by_lods) {
    if (!parse_lods(lods_text, settings.levels))
      return fail_usage("--lods " + lods_text +
                        ": expected a comma-separated list of percentages (25%) or face counts");
    for (std::size_t i = 0; i < settings.levels.size(); ++i)
      for (std::size_t j = 0; j < i; ++j)
        if (settings.levels[i].label == settings.levels[j].label)
          return fail_usage("--lods " + lods_text + ": two levels are named " +
                            settings.levels[i].label);
    if (command.output == "-" && settings.levels.size() > 1)
      return fail_usage("-o - takes one level; --lods gives " +
                        std::to_string(settings.levels.size()));
  } else {
    if (*by_vertices) {
      single.kind = LevelRequest::Kind::kVertices;
      single.count = vertices;
    } else if (*by_faces) {
      single.kind = LevelRequest::Kind::kFaces;
      single.count = faces;
    } else if (*by_ratio) {
      single.kind = LevelRequest::Kind::kRatio;
      single.ratio = ratio;
    } else if (*by_error) {
      single.kind = LevelRequest::Kind::kError;
      if (!parse_error_bound(error_text, settings.error.absolute, settings.error.value))
        return fail_usage(std::string("--error: not a non-negative number") +
                          (settings.error.absolute ? " (no % with --absolute)" : " or percentage") +
                          ": " + error_text);
    }
    settings.levels = {single};
  }

  pm::cli::PlanSettings plan;
  plan.extensions = {"pm"};
  plan.extra_names = {"lod", "frame"};
  plan.default_template = *by_lods                              ? "{dir}/{stem}_{lod}.obj"
                          : *by_frames                          ? "{dir}/{stem}_morph_{frame}.obj"
                          : *by_morph                           ? "{dir}/{stem}_morph.obj"
                                                                : "{dir}/{stem}.obj";
  for (const LevelRequest& level : settings.levels)
    plan.variants.push_back({{"lod", *by_lods ? level.label : ""},
                             {"frame", *by_morph ? level.label : ""}});
  pm::cli::OutputTemplate name_template;
  if (!command.output.empty() && command.output != "-" &&
      pm::cli::OutputTemplate::parse(command.output, plan.extra_names, name_template)) {
    if (name_template.has_placeholder("lod") && !*by_lods)
      return fail_usage("-o " + command.output + ": {lod} needs --lods");
    if (name_template.has_placeholder("frame") && !*by_frames)
      return fail_usage("-o " + command.output + ": {frame} needs --morph-frames");
    if (!name_template.has_placeholder("frame") && *by_frames && settings.levels.size() > 1)
      return fail_usage("-o " + command.output + ": name the frames apart with {frame}");
    if (!name_template.has_placeholder("lod") && *by_lods && settings.levels.size() > 1)
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
                       "unknown output format (use .obj .ply .off .stl or --format)"));
  if (command.dry_run) {
    pm::cli::print_plan(tasks, command.json, /*outputs_as_array=*/true, command.skip_existing);
    return pm::cli::kExitOk;
  }

  // Read before any work is done or any file written, so that a bad ORIGINAL costs nothing.
  pm::Mesh original;
  pm::cli::RunOptions run_options = command.run_options(kTool);
  if (!compare_path.empty()) {
    if (tasks.size() != 1)
      return fail_usage("--compare takes a single input (" + std::to_string(tasks.size()) +
                        " given)");
    if (pm::Status s = pm::read_mesh(compare_path, original); !s)
      return pm::cli::fail(kTool, compare_path, s);
    settings.compare_with = &original;
    // The comparison is the JSON object of --json.
    settings.json_comparison = command.json;
    run_options.json = false;
  }
  if (tasks.empty() && !command.quiet) std::cerr << kTool << ": no input files\n";

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
