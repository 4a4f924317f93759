// encode() on views of the caller's arrays (pointer, count, stride), so that numpy arrays,
// JS typed arrays and an engine's interleaved vertex buffers pass without first being copied
// into a Mesh.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "pm/encoder.h"
#include "pm/mesh.h"
#include "pm/progressive_mesh.h"
#include "pm/status.h"

namespace pm {

// Rows of caller-owned values, without a copy into a Mesh first (a numpy array, a JS typed
// array, an engine's interleaved vertex buffer): row i is the `width` values at
// reinterpret_cast<const char*>(data) + i * stride, the width fixed by the field (3 floats
// for a position, 3 indices for a triangle, ...). stride is in bytes; 0 means rows packed
// back to back (width * sizeof(T)). count 0 (and data null): the mesh has none.
template <class T>
struct RowsView {
  const T* data = nullptr;
  std::size_t count = 0;   // rows
  std::size_t stride = 0;  // bytes from one row to the next; 0: packed
};

// A Mesh (mesh.h) as views of the caller's arrays, field for field; the same rules apply
// (validate_attributes()). Ownership: borrowed for the duration of the call only.
struct MeshView {
  RowsView<float> positions;           // a vertex: x, y, z
  RowsView<uint32_t> triangles;        // a face: three vertex indices
  uint32_t color_components = 0;       // 0, 3 or 4
  RowsView<float> colors;              // a vertex: color_components values
  RowsView<float> uvs;                 // a table entry: u, v
  RowsView<uint32_t> uv_indices;       // a face: its three corners' entries
  RowsView<float> normals;             // a table entry: x, y, z
  RowsView<uint32_t> normal_indices;   // a face: its three corners' entries
  RowsView<uint32_t> face_materials;   // a face: one index into material_names
  const std::vector<std::string>* material_names = nullptr;      // null: none
  const std::vector<std::string>* material_libraries = nullptr;  // null: none
};

// encode() on views: the same progressive mesh as encode() on the Mesh holding the same
// values, bit for bit. The values are gathered once into the encoder's input (as the Mesh
// overload reads its Mesh), with no copy on the caller's side; that input goes to
// encode(Mesh&&), which lets its arrays go once the collapse loop has its own. Errors: those
// of encode(), and kInvalidArgument for a view with rows but no data or a stride shorter
// than its row.
[[nodiscard]] Status encode(const MeshView& input, const EncodeOptions& options,
                            ProgressiveMesh& out, EncodeStats* stats = nullptr);
// The same, for a stream to be written with `stream` (as encode() on a Mesh with it).
[[nodiscard]] Status encode(const MeshView& input, const EncodeOptions& options,
                            const WriteOptions& stream, ProgressiveMesh& out,
                            EncodeStats* stats = nullptr);

}  // namespace pm
