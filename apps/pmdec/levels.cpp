// pmdec's levels: the level each request selects (a single-level option, each item of
// --lods, or the coarsest level within --error), and the splits of the stream it needs.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "cli_common.h"
#include "pm/lod.h"
#include "pm/measured_level.h"
#include "pmdec/pmdec.h"

namespace pmdec {

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

}  // namespace pmdec
