// pmdec --morph FROM:TO[:ALPHA] [--morph-frames K]: a geomorph (Hoppe 1996, §4.2) between
// two levels, written at one alpha or at K evenly spaced ones.
#include <algorithm>

#include "pm/lod_runtime.h"
#include "pmdec/pmdec.h"

namespace pmdec {

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

pm::Status morph_frames(const pm::ProgressiveMesh& progressive, std::size_t full_faces,
                        const Settings& settings, const std::string& input,
                        pm::cli::JobProgress& progress, std::vector<std::size_t>& levels,
                        std::vector<pm::Mesh>& meshes) {
  std::size_t from = 0, to = 0;
  if (pm::Status s = select_level(settings.morph->from, progressive, full_faces, settings, input,
                                  progress, from);
      !s)
    return s;
  if (pm::Status s =
          select_level(settings.morph->to, progressive, full_faces, settings, input, progress, to);
      !s)
    return s;
  // A geomorph runs from the coarser level to the finer; FROM finer than TO runs it backwards.
  const bool backwards = from > to;
  pm::RuntimeLod lod(progressive);
  const pm::RuntimeLod::Geomorph morph = lod.geomorph(std::min(from, to), std::max(from, to));
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    const float alpha = settings.morph->alphas[i];
    meshes[i] = morph.mesh(backwards ? 1.0f - alpha : alpha);
    levels[i] = std::max(from, to);
  }
  return pm::Status::ok();
}

}  // namespace pmdec
