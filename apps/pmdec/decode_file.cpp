// pmdec's work on one input: read the .pm (only the chunks the requested levels need), make
// the meshes of the mode (levels, a geomorph's frames or a selectively refined mesh), write
// them, measure them against --compare's original, and say what was written.
#include <algorithm>
#include <chrono>
#include <cstdio>

#include "cli_common.h"
#include "pm/lod.h"
#include "pmdec/pmdec.h"

namespace pmdec {

pm::MeshFormat output_format_for(const std::string& output, const std::string& format_option) {
  if (!format_option.empty()) return pm::mesh_format_from_path("." + format_option);
  if (output == "-") return pm::MeshFormat::kObj;
  return pm::mesh_format_from_path(output);
}

namespace {

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

}  // namespace

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
    // A glTF chain: every level goes into the one file.
    if (settings.gltf_chain && !task.outputs.empty()) written[i].output = task.outputs.front();
  }
  pm::cli::Outcome outcome;
  outcome.json = json_members(written, nullptr);
  auto failed = [&outcome](const pm::Status& status) { return outcome.failed_with(status); };
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
  if (indexed && !settings.compare_with &&
      settings.selective.kind == SelectiveRequest::Kind::kNone) {
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
  const std::size_t full_faces = indexed
                                     ? static_cast<std::size_t>(info.full_face_count)
                                     : pm::faces_at_level(progressive, progressive.splits.size());
  if (!task.conflict) return failed(task.conflict);

  // The meshes to write: each requested level, all from one walk over the splits
  // (pm::extract_levels), or the frames of a geomorph.
  std::vector<std::size_t> levels(settings.levels.size());
  std::vector<pm::Mesh> meshes(settings.levels.size());
  const bool selective = settings.selective.kind != SelectiveRequest::Kind::kNone;
  if (selective) {
    if (pm::Status s = refine_selectively(progressive, settings, meshes[0], levels[0]); !s)
      return failed(s);
  } else if (settings.morph) {
    if (pm::Status s =
            morph_frames(progressive, full_faces, settings, input, progress, levels, meshes);
        !s)
      return failed(s);
  } else {
    for (std::size_t i = 0; i < settings.levels.size(); ++i)
      if (pm::Status s = select_level(settings.levels[i], progressive, full_faces, settings, input,
                                      progress, levels[i]);
          !s)
        return failed(s);
    if (levels.size() == 1) {
      // One level (the usual request): the walker's mesh itself, not a copy of it beside it.
      meshes[0] = pm::extract_level(progressive, levels[0]);
    } else {
      pm::extract_levels(progressive, levels, [&](std::size_t level, const pm::Mesh& mesh) {
        for (std::size_t i = 0; i < levels.size(); ++i)
          if (levels[i] == level) meshes[i] = mesh;
      });
    }
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
  std::string faces_list;
  pm::Mesh last;
  // glTF outputs: a chain's levels are gathered and written with its last one.
  std::vector<std::pair<std::size_t, pm::Mesh>> gltf_levels;
  for (std::size_t i = 0; i < settings.levels.size(); ++i) {
    const std::size_t level = levels[i];
    last = std::move(meshes[i]);
    group_materials_for_output(progressive, !selective && !settings.morph, level, last);
    if (!written[i].output.empty()) {
      const std::string& output = written[i].output;
      const pm::MeshFormat format = output_format_for(output, settings.output_format);
      // A failure of the mesh's own (exit_code_for()) or of the output (exit_code_for_write()).
      pm::Status s;
      bool output_failed = false;
      if (pm::cli::is_gltf(format)) {
        // Coarse to fine (pm/gltf.h): the finest is the level loaders without MSFT_lod show.
        gltf_levels.push_back({level, last});
        if (!settings.gltf_chain || i + 1 == settings.levels.size()) {
          std::stable_sort(gltf_levels.begin(), gltf_levels.end(),
                           [](const auto& a, const auto& b) { return a.first < b.first; });
          std::vector<pm::GltfLevel> chain;
          for (const auto& [chain_level, mesh] : gltf_levels) chain.push_back({&mesh, level_error(chain_level)});
          std::string encoded;
          s = pm::cli::encode_gltf_output(chain, format, output, settings.gltf, encoded);
          gltf_levels.clear();
          if (s) {
            output_failed = true;
            if (settings.create_directories) s = pm::cli::make_parent_directories(output);
            if (s) s = pm::cli::write_output_atomically(output, encoded, pm::cli::is_binary_format(format));
          }
        }  // else a level of a chain, written with the last
      } else {
        // Given to the file as it is made (write_mesh_output): the full detail of the
        // 950,272-face textured mesh as OBJ, 111 MB of text, is never whole in memory.
        s = pm::cli::write_mesh_output(last, format, output, settings.create_directories,
                                       &output_failed);
      }
      if (!s) {
        outcome.error_file = output;
        if (!output_failed) return failed(s);
        outcome.status = s;
        outcome.exit_code = pm::cli::exit_code_for_write(s);
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
                  written[0].level, counts.splits, written[0].faces, written[0].vertices,
                  double(level_error(written[0].level)), pm::cli::seconds_since(start));
    outcome.summary = name + summary;
  } else {
    std::snprintf(summary, sizeof summary, " faces, %.2f s", pm::cli::seconds_since(start));
    outcome.summary =
        name + ": " + std::to_string(written.size()) + " levels: " + faces_list + summary;
  }
  return outcome;
}

}  // namespace pmdec
