// The progressive mesh: a base mesh and the vertex splits that refine it back to the
// input (Hoppe 1996, "Progressive Meshes", §3). One record type serves the simplifier
// that emits it, the .pm codec that stores it and the decoder that replays it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "pm/mesh.h"  // kNoAttribute
#include "pm/status.h"

namespace pm {

inline constexpr uint32_t kNoVertex = 0xFFFFFFFFu;

// Vertex split i: the inverse of the half-edge collapse v -> u that removed vertex v.
// v is not stored: it is vertex base_vertex_count + i, at positions[3 * v].
//
//            vl                            vl
//           /  \                          /|\   .
//          / fl \        collapse        / | \  .
//   ... --v------u-- ...   ------>   ... --u-- ...    v's other faces now use u
//          \ fr /     <------            \ | /  .
//           \  /     split (this)         \|/   .
//            vr                            vr
//
// The split re-creates v, turns the moved faces' corner u back into v, and appends
// the new faces fl = (v, u, vl) when vl exists, then fr = (u, v, vr) when vr exists
// (counter-clockwise). vl or vr is kNoVertex when v-u is a boundary edge on that side.
struct VertexSplit {
  uint32_t u = 0;
  uint32_t vl = kNoVertex;
  uint32_t vr = kNoVertex;
  // Error bound of the mesh before this split is applied, in model units: at least the
  // distance from every input vertex (that a face uses) to its surface (formats/pm-format.md
  // §5.6). Non-increasing along the splits.
  float error = 0.0f;
  // The faces that go from u to v: ProgressiveMesh::moved_faces[moved_begin ...
  // moved_begin + moved_count), as face ids of the mesh before the split.
  uint32_t moved_begin = 0;
  uint32_t moved_count = 0;

  uint32_t new_face_count() const { return (vl != kNoVertex) + (vr != kNoVertex); }
};

// A welded vertex: the input had one vertex where the manifold mesh needs two (a
// pinched vertex, a complex edge). The copy is output as the canonical vertex.
struct Weld {
  uint32_t copy = 0;
  uint32_t canonical = 0;
};

// Vertex ids: [0, base_vertex_count) base vertices; then one per split in order; then
// loose_vertex_count vertices that no face of the input used, output at full detail only.
// Face ids: base faces first, then the faces each split appends, in order.
// Ownership: a value that owns its arrays. Only SelectiveRefinement keeps one after its
// constructor returns (borrowed or shared, see there); RuntimeLod copies what it needs.
struct ProgressiveMesh {
  uint32_t base_vertex_count = 0;
  uint32_t loose_vertex_count = 0;
  std::vector<float> positions;       // x, y, z per vertex id
  std::vector<uint32_t> base_faces;   // 3 per base face
  std::vector<VertexSplit> splits;    // refinement order: coarse to fine
  std::vector<uint32_t> moved_faces;  // the splits' moved face ids, back to back
  std::vector<Weld> welds;            // copies are never removed (complex vertices)
  // Input faces with a repeated vertex index ((a, a, b)): no half-edge mesh can hold
  // them, so they are carried as-is. Their vertices are never removed; they are output
  // at every level.
  std::vector<uint32_t> carried_faces;  // 3 per face

  // Attributes (Hoppe 1996, §3: each corner refers to a "wedge" of attribute values).
  // Every kind is optional: its vectors are empty when the input had none.
  //
  // Colours are per vertex id, like positions (color_components floats each).
  uint32_t color_components = 0;
  std::vector<float> colors;
  // Value tables, the input's own, in its order: texture coordinates (2 floats each) and
  // normals (3 floats each). Corners refer to them by id; kNoAttribute is none.
  std::vector<float> uvs;
  std::vector<float> normals;
  std::vector<std::string> material_names;
  std::vector<std::string> material_libraries;
  // What each face has when it appears, by creation order: the base faces, then the faces
  // the splits add (fl before fr, split by split), then the carried faces. face_uvs and
  // face_normals hold 3 ids per face (its corners, in the order of its vertices);
  // face_materials one material id per face.
  std::vector<uint32_t> face_uvs;
  std::vector<uint32_t> face_normals;
  std::vector<uint32_t> face_materials;
  // Parallel to moved_faces: the attribute the moved face's corner takes when the split
  // turns it from u into v (the collapse had given it one of u's wedges). A split changes
  // no other corner: u keeps its wedges, as the half-edge collapse kept u's position.
  std::vector<uint32_t> moved_uvs;
  std::vector<uint32_t> moved_normals;

  // The input's order, for full detail (optional: pmenc --keep-order). input_vertices[i] is
  // the vertex id of input vertex i (never a welded copy); input_faces[t] is 3 * f + r for
  // input triangle t: f its face id (creation order), r the corner of f that is t's first.
  // Empty: full detail lists vertices by id and faces in creation order, carried last.
  std::vector<uint32_t> input_vertices;
  std::vector<uint32_t> input_faces;

  std::size_t vertex_count() const { return positions.size() / 3; }  // all levels, all kinds
  std::size_t base_face_count() const { return base_faces.size() / 3; }
  std::size_t split_count() const { return splits.size(); }
  std::size_t uv_count() const { return uvs.size() / 2; }
  std::size_t normal_count() const { return normals.size() / 3; }
  // Faces of all levels: base, added by splits, carried.
  std::size_t total_face_count() const;
  bool has_uvs() const { return !face_uvs.empty(); }
  bool has_normals() const { return !face_normals.empty(); }
  bool has_materials() const { return !face_materials.empty(); }
  bool keeps_order() const { return !input_vertices.empty() || !input_faces.empty(); }
};

// Validates every invariant a decoder relies on (ids in range, faces that hold u,
// non-increasing errors, ...). kInvalidArgument with a message on the first violation.
[[nodiscard]] Status validate(const ProgressiveMesh& pm);

}  // namespace pm
