// Turning an arbitrary triangle soup into a manifold half-edge mesh without losing
// anything: complex edges are cut, each fan of a pinched vertex gets its own copy,
// faces with a repeated index are carried aside. Every change is recorded so that the
// decoder can undo it at full detail.
#pragma once

#include <cstdint>
#include <vector>

#include "simplify/half_edge_mesh.h"
#include "pm/encoder.h"
#include "pm/mesh.h"
#include "pm/status.h"

namespace pm {

struct ManifoldMesh {
  HalfEdgeMesh mesh;
  // Per half-edge-mesh vertex: the input vertex it stands for.
  std::vector<uint32_t> input_vertex;
  // Per half-edge-mesh vertex: never removed (Schroeder's complex vertices: the copies
  // made here, the vertices they were copied from, and vertices of carried faces).
  std::vector<uint8_t> pinned;
  // Per half-edge-mesh vertex: the vertex it is a copy of, or itself.
  std::vector<uint32_t> canonical;
  // Per half-edge-mesh face: the input face it is.
  std::vector<uint32_t> input_face;
  // Faces with a repeated index, as half-edge-mesh vertex ids (canonical copies).
  std::vector<uint32_t> carried_faces;
  std::vector<uint32_t> carried_input_faces;  // per carried face: the input face it is
  // Input vertices no face uses, in input order.
  std::vector<uint32_t> loose_vertices;
  RepairReport report;
};

// Whether the encoder can take the mesh at all. Errors: kInvalidArgument (arrays not in
// threes), kEmptyMesh, kParseError (an index out of range, a non-finite coordinate),
// kResourceLimit (2^30 vertices or faces, a bounding-box diagonal above kMaxEncodeDiagonal).
Status check_encodable(const Mesh& input);

// Errors: check_encodable's.
Status build_manifold_mesh(const Mesh& input, ManifoldMesh& out);

}  // namespace pm
