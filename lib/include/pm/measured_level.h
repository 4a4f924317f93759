// The coarsest level of detail whose measured distance to the full-detail mesh is within a
// tolerance. The full detail of a .pm is the input exactly, so the original is always at
// hand: the answer is measured (Metro sampling, surface_distance.h), not estimated.
#pragma once

#include <cstddef>

#include "pm/progressive_mesh.h"
#include "pm/status.h"
#include "pm/surface_distance.h"

namespace pm {

struct MeasuredLevelOptions {
  DistanceOptions distance;  // the sampling used for every measurement
  // The search stops when the level it returns has at most this factor more faces than a
  // level that measured above the tolerance (or is the base mesh). Must be > 1.
  double face_ratio = 1.1;
};

struct MeasuredLevel {
  std::size_t level = 0;      // the level returned (split_count() for full detail)
  SurfaceDistance distance;   // its measurement against full detail (zero at full detail)
  std::size_t measurements = 0;  // how many levels were measured to find it
};

// Finds a level whose measured Hausdorff distance to full detail is at most max_hausdorff
// (model units) and that is nearly the coarsest such: either the base mesh, or a level with
// at most options.face_ratio times the faces of a coarser level measuring above the
// tolerance. The recorded per-split errors give the first guess; from there it gallops
// (factor 1.5 in faces) to bracket the answer and bisects the bracket in face count.
// Measured error is not strictly monotone in the level, so "coarsest" is up to the
// bracket; the bound on the returned level always holds, since it was measured.
// Errors: kInvalidArgument (max_hausdorff negative or not finite, face_ratio <= 1, an
// invalid pm), and those of measure_surface_distance.
[[nodiscard]] Status level_for_measured_error(const ProgressiveMesh& pm, double max_hausdorff,
                                const MeasuredLevelOptions& options, MeasuredLevel& out);

}  // namespace pm
