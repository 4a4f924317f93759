// What a simplifier hands to the encoder's assembly: the half-edge collapses in the order
// they happened, and the base mesh they left (Hoppe 1996, "Progressive meshes", §3: the
// collapses, last first, are the vertex splits that refine the base mesh back).
#pragma once

#include <cstdint>
#include <vector>

namespace pm {

// One half-edge collapse v -> u as it happened, in half-edge-mesh ids (the ids of
// build_manifold_mesh's mesh, which every simplifier keeps).
struct Collapse {
  uint32_t v, u;
  uint32_t vl, vr;  // kNoVertex on a boundary side
  int fl, fr;       // removed faces, -1 when absent
  uint32_t moved_begin, moved_count;
  uint32_t new_faces_begin;  // fl's (then fr's) entry in CollapseAttributes' new-face lists
  float bound;               // error bound of the mesh after this collapse
};

// The mesh left after the last collapse, in half-edge-mesh ids.
struct BaseMesh {
  std::vector<uint32_t> vertices;  // the vertices left, in increasing id
  std::vector<uint32_t> faces;     // the faces left, in increasing id
  std::vector<uint32_t> corners;   // three vertex ids per face of `faces`, in its order
};

}  // namespace pm
