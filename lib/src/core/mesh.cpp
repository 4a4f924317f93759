// Mesh's attribute invariants, checked once where a mesh enters the encoder; faces grouped
// by material for writing.
#include "pm/mesh.h"

#include <algorithm>
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

bool check_attributes(const Mesh& mesh, std::string* message) {
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

}  // namespace

Status validate_attributes(const Mesh& mesh) {
  std::string problem;
  if (check_attributes(mesh, &problem)) return Status::ok();
  return Status(ErrorCode::kInvalidArgument, std::move(problem));
}

void group_faces_by_material(Mesh& mesh) {
  const std::size_t faces = mesh.face_count();
  if (mesh.face_materials.size() != faces || faces == 0) return;
  // Each group's rank: the order of its first face (kNoAttribute is a group too).
  std::vector<uint32_t> rank_of(mesh.material_names.size() + 1, kNoAttribute);
  std::vector<uint32_t> rank(faces);
  uint32_t groups = 0;
  for (std::size_t f = 0; f < faces; ++f) {
    const uint32_t m = mesh.face_materials[f];
    if (m != kNoAttribute && m >= mesh.material_names.size()) return;  // invalid: left as is
    uint32_t& r = rank_of[m == kNoAttribute ? mesh.material_names.size() : m];
    if (r == kNoAttribute) r = groups++;
    rank[f] = r;
  }
  if (groups < 2) return;
  std::vector<uint32_t> order(faces);
  for (std::size_t f = 0; f < faces; ++f) order[f] = static_cast<uint32_t>(f);
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return rank[a] < rank[b]; });
  const auto permute = [&](std::vector<uint32_t>& values, std::size_t per_face) {
    if (values.size() != per_face * faces) return;
    std::vector<uint32_t> out(values.size());
    for (std::size_t k = 0; k < faces; ++k)
      std::copy_n(&values[per_face * order[k]], per_face, &out[per_face * k]);
    values = std::move(out);
  };
  permute(mesh.triangles, 3);
  permute(mesh.uv_indices, 3);
  permute(mesh.normal_indices, 3);
  permute(mesh.face_materials, 1);
}

}  // namespace pm
