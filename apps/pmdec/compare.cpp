// pmdec --compare ORIGINAL: how far the written level is from the original mesh
// (pm::measure_surface_distance, Cignoni, Rocchini and Scopigno 1998), as text or JSON.
#include <cstdio>

#include "pmdec/pmdec.h"

namespace pmdec {

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

}  // namespace pmdec
