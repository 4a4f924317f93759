// The collapse loop (the one left since issue 25; once pmenc --fast): Garland and Heckbert's
// quadric metric (or Schroeder's, schroeder_costs.cpp) on a flat, array-based connectivity
// (Campagna, Kobbelt and Seidel 1998, "Directed edges"), with a measured error bounded per collapse
// (kept_points.h) where the former default loop (deleted in issue 25; commit 3cb92db) charged every
// removed point. It keeps every rule that makes the result a valid progressive mesh of the same
// topology: the link condition, the normal-flip and degeneracy limits, pinned vertices, welds,
// carried faces, boundaries and feature edges; and the attributes
// (corner_attributes.h, seam_drift.h): seams and material borders kept,
// the attribute error in the cost, texture-seam drift in the measured key.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "pm/encoder.h"
#include "pm/mesh.h"
#include "pm/status.h"
#include "simplify/collapse_sequence.h"
#include "simplify/corner_attributes.h"
#include "simplify/manifold_repair.h"
#include "simplify/record_list.h"

namespace pm {

// Switches of the loop that only tests turn; encode() runs with the defaults. Passed with
// each call, not kept in a global, so that encodes on other threads never see a test's.
struct LoopSwitches {
  // Whether the loop with its measure reuses the fan's part of a measure that still holds
  // (collapse_measure.cpp). The reuse saves work and keeps the sequence: test_encoder.cpp
  // runs the loop with and without it and compares.
  bool reuse_fan_part = true;
  // Whether, geometry only, vl and vr keep their queued candidate after a collapse when it
  // is still their cheapest (collapse_apply.cpp's apply()), instead of being evaluated again.
  // The same sequence with fewer evaluations: test_encoder.cpp compares.
  bool keep_apex_candidates = true;
  // Whether the loop without its measure, geometry only, adds the plane term to the
  // quadric's cost (collapse_loop.h, FanPlanes). Off: the quadric alone, whose shortcuts
  // (keep_apex_candidates) leave the sequence as it was; test_encoder.cpp compares the levels.
  bool plane_term = true;
  // Whether the loop renames its faces without the dead ones between rounds, shrinking its
  // per-face arrays (face_renumbering.h). The same sequence in less memory: test_encoder.cpp
  // compares.
  bool compact_faces = true;
  // Whether the loop without its measure, with attributes, prices a vertex's options (their
  // attribute error) only when it comes to the top, queued until then at its cheapest
  // geometric cost, a lower bound (collapse_options.cpp). Off: every evaluation prices them.
  bool price_at_top = true;
};

struct Simplification {
  std::vector<Collapse> collapses;
  RecordList moved_faces{kMovedEntriesPerBlock};  // half-edge-mesh face ids, Collapse::moved_begin
  BaseMesh base;
  std::vector<float> points;  // three per half-edge-mesh vertex
  // With attributes kept (the input has some, and not EncodeOptions::drop_attributes): the
  // corners as the base mesh has them, in half-edge-mesh ids, and what each split restores
  // (Collapse::moved_begin, new_faces_begin). Null otherwise.
  std::unique_ptr<CornerAttributes> attributes;
  CollapseAttributes attribute_record;
  std::size_t face_renamings = 0;  // how often the loop renamed its faces (tests)
};

// Runs the whole collapse sequence on repaired.mesh, in its ids. Its triangles and points
// are copied into flat arrays first, then the OpenMesh mesh is cleared to give its memory
// back: afterwards only repaired's per-vertex and per-face tables remain, and out.points
// replaces its points. Either metric (Schroeder's: schroeder_costs.cpp). kInternal if the mesh
// is not the manifold build_manifold_mesh makes.
// `input` is the mesh repaired was built from (its attributes). `loop_built`, when set, is
// called once the loop holds its own copy of all it reads of `input` (its connectivity,
// points and corner attributes; the attribute tables, uvs and normals, it still reads):
// encode(Mesh&&) lets the input's other arrays go there.
Status simplify(const Mesh& input, ManifoldMesh& repaired, const EncodeOptions& options,
                Simplification& out, const LoopSwitches& switches = {},
                const std::function<void()>& loop_built = {});

// The same on the input as it is, in its ids, when it is a manifold that needs no repair (see
// build_manifold_mesh: no face with a repeated vertex, no vertex without faces, every edge
// in one face or two of opposite orientation, every vertex's faces one fan): the OpenMesh
// mesh is never built. False, with nothing done, otherwise. The input must have passed
// check_encodable.
bool simplify_direct(const Mesh& input, const EncodeOptions& options, Simplification& out,
                     const LoopSwitches& switches = {},
                     const std::function<void()>& loop_built = {});

// pm::encode() with the loop's test switches (encode.cpp).
Status encode_with_switches(const Mesh& input, const EncodeOptions& options,
                            const LoopSwitches& switches, ProgressiveMesh& out);

}  // namespace pm
