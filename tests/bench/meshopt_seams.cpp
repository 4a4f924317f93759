// meshopt_simplify on a seam-split vertex buffer; see meshopt_seams.h.
#include "meshopt_seams.h"

#include <meshoptimizer.h>

#include <array>
#include <cfloat>
#include <chrono>
#include <map>
#include <vector>

namespace pm::bench {

MeshoptLod meshopt_seam_split_lod(const pm::Mesh& original, std::size_t target_faces) {
  MeshoptLod result;
  pm::Mesh& lod = result.lod;
  lod.color_components = original.color_components;

  // One split vertex per (position, uv, normal) index triple; corners without a UV or
  // normal give a copy without one.
  using Key = std::array<uint32_t, 3>;
  std::map<Key, uint32_t> copies;
  std::vector<Key> copy_keys;
  std::vector<unsigned int> split_corners(original.triangles.size());
  for (std::size_t i = 0; i < original.triangles.size(); ++i) {
    const Key key = {original.triangles[i],
                     original.has_uvs() ? original.uv_indices[i] : pm::kNoAttribute,
                     original.has_normals() ? original.normal_indices[i] : pm::kNoAttribute};
    const auto [it, inserted] = copies.emplace(key, uint32_t(copy_keys.size()));
    if (inserted) copy_keys.push_back(key);
    split_corners[i] = it->second;
  }
  std::vector<float> split_positions(3 * copy_keys.size());
  for (std::size_t v = 0; v < copy_keys.size(); ++v)
    for (int axis = 0; axis < 3; ++axis)
      split_positions[3 * v + axis] = original.positions[3 * std::size_t(copy_keys[v][0]) + axis];

  // One primitive for the whole mesh. Split by material, as glTF stores it, each
  // primitive's border would be free to move under options 0, tearing the surface apart
  // where two materials meet; as one, meshopt holds the seams of the split buffer, which on
  // our meshes include the material borders (they are UV seams too).
  std::vector<unsigned int> kept(split_corners.size());
  const auto start = std::chrono::steady_clock::now();
  // meshoptimizer 0.18: target_error is relative to the mesh's extent; FLT_MAX lifts the
  // limit, so that only the face target and meshopt's own rules stop it.
  const std::size_t count = meshopt_simplify(
      kept.data(), split_corners.data(), split_corners.size(), split_positions.data(),
      copy_keys.size(), 3 * sizeof(float), 3 * target_faces, FLT_MAX, /*options=*/0,
      /*result_error=*/nullptr);
  result.milliseconds =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  kept.resize(count);

  // The copies still used, renumbered in order of first use. Each has its own UV and
  // normal entry (when it has one), so a corner's value is its copy's.
  std::vector<uint32_t> renumbered(copy_keys.size(), pm::kNoAttribute);
  std::vector<uint32_t> uv_of_copy, normal_of_copy;
  const bool uvs = original.has_uvs(), normals = original.has_normals();
  for (unsigned int& corner : kept) {
    if (renumbered[corner] == pm::kNoAttribute) {
      renumbered[corner] = uint32_t(lod.vertex_count());
      const Key& key = copy_keys[corner];
      lod.positions.insert(lod.positions.end(), &split_positions[3 * std::size_t(corner)],
                           &split_positions[3 * std::size_t(corner) + 3]);
      if (lod.color_components)
        lod.colors.insert(lod.colors.end(),
                          &original.colors[std::size_t(key[0]) * original.color_components],
                          &original.colors[std::size_t(key[0] + 1) * original.color_components]);
      uv_of_copy.push_back(key[1] == pm::kNoAttribute ? pm::kNoAttribute
                                                      : uint32_t(lod.uv_count()));
      if (key[1] != pm::kNoAttribute)
        lod.uvs.insert(lod.uvs.end(), &original.uvs[2 * std::size_t(key[1])],
                       &original.uvs[2 * std::size_t(key[1]) + 2]);
      normal_of_copy.push_back(key[2] == pm::kNoAttribute ? pm::kNoAttribute
                                                          : uint32_t(lod.normal_count()));
      if (key[2] != pm::kNoAttribute)
        lod.normals.insert(lod.normals.end(), &original.normals[3 * std::size_t(key[2])],
                           &original.normals[3 * std::size_t(key[2]) + 3]);
    }
    corner = renumbered[corner];
  }
  lod.triangles.assign(kept.begin(), kept.end());
  if (uvs)
    for (uint32_t corner : lod.triangles) lod.uv_indices.push_back(uv_of_copy[corner]);
  if (normals)
    for (uint32_t corner : lod.triangles) lod.normal_indices.push_back(normal_of_copy[corner]);
  return result;
}

}  // namespace pm::bench
