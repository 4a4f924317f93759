// The fast collapse loop (pmenc --fast, EncodeOptions::fast): Garland and Heckbert's quadric
// metric on a flat, array-based connectivity (Campagna, Kobbelt and Seidel 1998, "Directed
// edges"), without the measured error the default loop charges (removed_points.h). It
// keeps every rule that makes the result a valid progressive mesh of the same topology:
// the link condition, the normal-flip and degeneracy limits, pinned vertices, welds,
// carried faces, boundaries and feature edges. Geometry only: the encoder takes the default
// loop when texture coordinates, normals or materials are to be kept.
#pragma once

#include <cstdint>
#include <vector>

#include "collapse_sequence.h"
#include "manifold_repair.h"
#include "pm/encoder.h"

namespace pm {

struct FastSimplification {
  std::vector<Collapse> collapses;
  std::vector<uint32_t> moved_faces;  // half-edge-mesh face ids, Collapse::moved_begin
  BaseMesh base;
  std::vector<float> points;  // three per half-edge-mesh vertex
};

// Runs the whole collapse sequence on repaired.mesh. Its connectivity is copied into flat
// arrays first, then the OpenMesh mesh is cleared to give its memory back: afterwards only
// repaired's per-vertex and per-face tables remain, and out.points replaces its points.
// Requires options.metric == Metric::kQuadric.
void simplify_fast(ManifoldMesh& repaired, const EncodeOptions& options, FastSimplification& out);

}  // namespace pm
