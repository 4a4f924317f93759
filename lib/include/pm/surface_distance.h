// Measured error between two triangle meshes, as Metro does it (Cignoni, Rocchini and
// Scopigno 1998, "Metro: measuring error on simplified surfaces"): sample one surface
// densely, measure each sample's distance to the other surface, and both ways round,
// since the one-sided distance misses whatever the other surface has and this one lacks.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "pm/mesh.h"
#include "pm/status.h"

namespace pm {

struct DistanceOptions {
  // Each face gets at least this many samples, more in proportion to its area where it is
  // larger than the mean; every vertex used by a face is a sample too. At least 1.
  double samples_per_face = 10;
  // The random points inside each face come from this seed and the face's own positions:
  // results are reproducible, and do not depend on the thread count, on the order of the
  // faces, on vertex numbering or on which corner of a face is written first.
  uint64_t seed = 1;
  // Worker threads; 0 uses every hardware thread. With one, the two meshes' hierarchies
  // are built one after the other, so that only one is in memory at a time.
  unsigned threads = 0;
};

struct SurfaceDistance {
  double hausdorff = 0;                     // max(forward_max, backward_max), model units
  double rms = 0;                           // root mean square over the samples of both directions
  double forward_max = 0, forward_rms = 0;  // from samples of `reference` to `other`
  double backward_max = 0, backward_rms = 0;  // from samples of `other` to `reference`
  double diagonal = 0;      // bounding-box diagonal of `reference` (all its vertices)
  std::size_t samples = 0;  // both directions
};

// Samples each surface (every vertex used by a face, plus stratified random points in
// each face: at least options.samples_per_face per face) and measures the exact distance
// from each sample to the nearest triangle of the other mesh, found through a bounding
// volume hierarchy. Unreferenced vertices are not part of the surface and are ignored.
// The sums of squares are exact, so the results do not depend on the order of the work.
// Memory: about 150 bytes per face of both meshes together (with one thread, less).
// Errors: kInvalidArgument (a mesh with no faces, a vertex index out of range, a
// non-finite coordinate, samples_per_face below 1 or not finite).
[[nodiscard]] Status measure_surface_distance(const Mesh& reference, const Mesh& other,
                                const DistanceOptions& options, SurfaceDistance& out);

// The diagonal of the bounding box of x, y, z triples (0 for none): the unit of errors
// given in percent.
double bounding_box_diagonal(const std::vector<float>& positions);

}  // namespace pm
