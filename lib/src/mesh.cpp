// Mesh's attribute invariants, checked once where a mesh enters the encoder.
#include "pm/mesh.h"

#include <string>
#include <utility>

namespace pm {
namespace {

bool fail(std::string* message, std::string text) {
  if (message) *message = std::move(text);
  return false;
}

// Per-corner (or per-face) indices: empty, or one per element, each below count or none.
bool check_indices(const std::vector<uint32_t>& indices, std::size_t expected_size,
                   std::size_t count, const char* what, std::string* message) {
  if (indices.empty()) return true;
  if (indices.size() != expected_size)
    return fail(message, std::string(what) + " has " + std::to_string(indices.size()) +
                             " entries, expected " + std::to_string(expected_size));
  for (std::size_t i = 0; i < indices.size(); ++i)
    if (indices[i] != kNoAttribute && indices[i] >= count)
      return fail(message, std::string(what) + " " + std::to_string(i) + " is " +
                               std::to_string(indices[i]) + ", out of " + std::to_string(count));
  return true;
}

}  // namespace

bool validate_attributes(const Mesh& mesh, std::string* message) {
  if (mesh.color_components != 0 && mesh.color_components != 3 && mesh.color_components != 4)
    return fail(message, "colours have " + std::to_string(mesh.color_components) +
                             " components, not 3 or 4");
  if (mesh.colors.size() != std::size_t{mesh.color_components} * mesh.vertex_count())
    return fail(message, "colours have " + std::to_string(mesh.colors.size()) +
                             " values for " + std::to_string(mesh.vertex_count()) + " vertices");
  if (mesh.uvs.size() % 2 != 0) return fail(message, "texture coordinates: odd value count");
  if (mesh.normals.size() % 3 != 0) return fail(message, "normals: value count not a multiple of 3");
  return check_indices(mesh.uv_indices, mesh.triangles.size(), mesh.uv_count(),
                       "texture coordinate index", message) &&
         check_indices(mesh.normal_indices, mesh.triangles.size(), mesh.normal_count(),
                       "normal index", message) &&
         check_indices(mesh.face_materials, mesh.face_count(), mesh.material_names.size(),
                       "face material", message);
}

}  // namespace pm
