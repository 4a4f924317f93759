// The indexed triangle mesh that goes in and comes out of the library.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "pm/status.h"

namespace pm {

// A corner or face without the attribute (an OBJ face corner written "v" or "v//vn", a
// face before the first usemtl).
inline constexpr uint32_t kNoAttribute = 0xFFFFFFFFu;

// A triangle soup with shared vertices: no topology is implied or required. Input
// readers produce it; LOD extraction produces it; writers consume it.
//
// Attributes follow Hoppe 1996, §3: values that belong to a point of the surface
// (colours) are per vertex; values that may differ between the faces around a vertex
// (texture coordinates and normals: a UV seam, a crease) are per corner, as indices into
// a table of values, so that one vertex can carry several ("wedges"). Every attribute is
// optional: an empty vector means the mesh has none.
// Ownership: a value that owns its arrays; no function keeps a reference to one it is given.
struct Mesh {
  std::vector<float> positions;     // x, y, z per vertex (float32, as stored in files)
  std::vector<uint32_t> triangles;  // three vertex indices per face, counter-clockwise

  // Per vertex: color_components (3: r g b, or 4: r g b a) floats, or empty. OBJ stores
  // them as written after x y z; 8-bit PLY/OFF colours are stored as c / 255.
  uint32_t color_components = 0;
  std::vector<float> colors;

  // Per corner, parallel to triangles (3 per face), or empty: an index into the value
  // table, or kNoAttribute.
  std::vector<float> uvs;  // u, v per entry (OBJ vt)
  std::vector<uint32_t> uv_indices;
  std::vector<float> normals;  // x, y, z per entry (OBJ vn), as stored: not normalized
  std::vector<uint32_t> normal_indices;

  // Per face, or empty: an index into material_names, or kNoAttribute.
  std::vector<uint32_t> face_materials;
  std::vector<std::string> material_names;      // OBJ usemtl names, first use first
  std::vector<std::string> material_libraries;  // OBJ mtllib file names, as written

  std::size_t vertex_count() const { return positions.size() / 3; }
  std::size_t face_count() const { return triangles.size() / 3; }
  std::size_t uv_count() const { return uvs.size() / 2; }
  std::size_t normal_count() const { return normals.size() / 3; }
  bool has_colors() const { return color_components != 0; }
  bool has_uvs() const { return !uv_indices.empty(); }
  bool has_normals() const { return !normal_indices.empty(); }
  bool has_materials() const { return !face_materials.empty(); }
  bool has_attributes() const {
    return has_colors() || has_uvs() || has_normals() || has_materials() ||
           !material_libraries.empty();
  }
};

// Checks the attribute arrays against the counts above (sizes, indices in range or
// kNoAttribute, 3 or 4 colour components). kInvalidArgument with a message on the first
// violation. Readers produce valid meshes; encode() refuses an invalid one.
[[nodiscard]] Status validate_attributes(const Mesh& mesh);

// Reorders the faces so that each material's faces are contiguous: materials in the order
// of their first face, faces without a material where their first one stood, each group's
// faces in their order (a stable sort). Corners and attributes travel with their faces;
// vertices are not touched. A level of a progressive mesh lists its faces as the splits
// made them, so its materials interleave (hundreds of `usemtl` switches, and as many draw
// calls in a renderer that makes one per group); grouped, an OBJ has one `usemtl` per
// material. Without materials, or with a material index out of range, nothing changes.
void group_faces_by_material(Mesh& mesh);

}  // namespace pm
