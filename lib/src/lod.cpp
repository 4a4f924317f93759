// Levels of detail by replaying vertex splits on a flat face array (Hoppe 1996, §3:
// M^0 -> vsplit_0 -> M^1 -> ... -> M^n). No connectivity is needed: each split names
// the faces whose corner u becomes v.
#include "pm/lod.h"

#include <algorithm>

namespace pm {

std::size_t faces_at_level(const ProgressiveMesh& pm, std::size_t level) {
  level = std::min(level, pm.splits.size());
  std::size_t faces = pm.base_face_count() + pm.carried_faces.size() / 3;
  for (std::size_t i = 0; i < level; ++i) faces += pm.splits[i].new_face_count();
  return faces;
}

std::size_t vertices_at_level(const ProgressiveMesh& pm, std::size_t level) {
  level = std::min(level, pm.splits.size());
  std::size_t vertices = pm.base_vertex_count + level - pm.welds.size();
  if (level == pm.splits.size()) vertices += pm.loose_vertex_count;
  return vertices;
}

float error_at_level(const ProgressiveMesh& pm, std::size_t level) {
  return level < pm.splits.size() ? pm.splits[level].error : 0.0f;
}

std::size_t level_for_faces(const ProgressiveMesh& pm, std::size_t n) {
  std::size_t faces = faces_at_level(pm, 0);
  std::size_t level = 0;
  while (level < pm.splits.size() && faces < n) faces += pm.splits[level++].new_face_count();
  return level;
}

std::size_t level_for_vertices(const ProgressiveMesh& pm, std::size_t n) {
  for (std::size_t level = 0; level < pm.splits.size(); ++level)
    if (vertices_at_level(pm, level) >= n) return level;
  return pm.splits.size();
}

std::size_t level_for_error(const ProgressiveMesh& pm, double e) {
  // Errors are non-increasing along the splits: binary search for the first level
  // whose bound is at most e.
  std::size_t lo = 0, hi = pm.splits.size();
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    if (pm.splits[mid].error <= e)
      hi = mid;
    else
      lo = mid + 1;
  }
  return lo;
}

Mesh extract_level(const ProgressiveMesh& pm, std::size_t level) {
  level = std::min(level, pm.splits.size());
  std::vector<uint32_t> faces(pm.base_faces);
  faces.reserve(3 * faces_at_level(pm, level));
  for (std::size_t i = 0; i < level; ++i) {
    const VertexSplit& s = pm.splits[i];
    const uint32_t v = pm.base_vertex_count + static_cast<uint32_t>(i);
    for (uint32_t k = 0; k < s.moved_count; ++k) {
      uint32_t* face = &faces[3 * pm.moved_faces[s.moved_begin + k]];
      for (int c = 0; c < 3; ++c)
        if (face[c] == s.u) face[c] = v;
    }
    if (s.vl != kNoVertex) faces.insert(faces.end(), {v, s.u, s.vl});
    if (s.vr != kNoVertex) faces.insert(faces.end(), {s.u, v, s.vr});
  }
  faces.insert(faces.end(), pm.carried_faces.begin(), pm.carried_faces.end());

  // Output numbering: active vertices in id order, copies merged into their canonical
  // vertex, loose vertices at full detail only.
  const uint32_t active = pm.base_vertex_count + static_cast<uint32_t>(level);
  const uint32_t total = static_cast<uint32_t>(pm.vertex_count());
  std::vector<uint32_t> canonical(active);
  for (uint32_t v = 0; v < active; ++v) canonical[v] = v;
  for (const Weld& w : pm.welds) canonical[w.copy] = w.canonical;
  const bool full = level == pm.splits.size();
  const uint32_t emitted = full ? total : active;
  std::vector<uint32_t> output_id(emitted, kNoVertex);
  Mesh mesh;
  mesh.positions.reserve(3 * vertices_at_level(pm, level));
  for (uint32_t v = 0; v < emitted; ++v) {
    if (v < active && canonical[v] != v) continue;
    output_id[v] = static_cast<uint32_t>(mesh.positions.size() / 3);
    mesh.positions.insert(mesh.positions.end(), pm.positions.begin() + 3 * v,
                          pm.positions.begin() + 3 * v + 3);
  }
  mesh.triangles.resize(faces.size());
  for (std::size_t i = 0; i < faces.size(); ++i) mesh.triangles[i] = output_id[canonical[faces[i]]];
  return mesh;
}

}  // namespace pm
