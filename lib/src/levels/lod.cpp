// Levels of detail by replaying vertex splits on a flat face array (Hoppe 1996, §3:
// M^0 -> vsplit_0 -> M^1 -> ... -> M^n). No connectivity is needed: each split names
// the faces whose corner u becomes v.
#include "pm/lod.h"

#include <algorithm>
#include <functional>
#include <vector>

#include "core/memory_pages.h"
#include "levels/level_output.h"

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
  // Every face asked for: full detail (its loose vertices too), past last splits that add
  // no face, if a stream has such.
  if (faces == n) {
    std::size_t rest = level;
    while (rest < pm.splits.size() && pm.splits[rest].new_face_count() == 0) ++rest;
    if (rest == pm.splits.size()) return rest;
  }
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

namespace {

using detail::output_attribute;

// Appends entries [3 * first, 3 * (first + count)) of per-face-corner data (or
// [first, first + count) when per_face is 1).
void append_created(std::vector<uint32_t>& out, const std::vector<uint32_t>& created,
                    std::size_t per_face, std::size_t first, std::size_t count) {
  out.insert(out.end(), created.begin() + per_face * first,
             created.begin() + per_face * (first + count));
}

// The faces of a level, walked up from the base mesh one split at a time (Hoppe 1996, §3:
// M^0 -> vsplit_0 -> M^1 -> ...). Corner attributes live beside the faces: the base faces'
// as created, then each split sets its moved corners' and appends its new faces'.
class LevelWalker {
 public:
  explicit LevelWalker(const ProgressiveMesh& pm)
      : pm_(pm), uvs_(pm.has_uvs()), normals_(pm.has_normals()), materials_(pm.has_materials()) {
    const std::size_t base_faces = pm.base_face_count();
    faces_ = pm.base_faces;
    if (uvs_) append_created(corner_uvs_, pm.face_uvs, 3, 0, base_faces);
    if (normals_) append_created(corner_normals_, pm.face_normals, 3, 0, base_faces);
    if (materials_) append_created(face_materials_, pm.face_materials, 1, 0, base_faces);
    created_ = base_faces;
  }

  // Applies the splits up to `level` (never backwards).
  void advance(std::size_t level) {
    level = std::min(level, pm_.splits.size());
    const std::size_t capacity = faces_.capacity();
    faces_.reserve(3 * faces_at_level(pm_, level));
    // Written at random, split by split (memory_pages.h); asked once per new allocation, not
    // at every step of an incremental walk.
    if (faces_.capacity() != capacity) detail::prefer_huge_pages(faces_);
    // The faces a split moves are scattered over the mesh, and named in advance: fetched a
    // few splits ahead, their cache misses overlap instead of coming one after the other.
    constexpr std::size_t kFetchAhead = 16;
    const std::size_t fetched_faces = faces_.capacity() / 3;
    for (; level_ < level; ++level_) {
      if (level_ + kFetchAhead < level) {
        const VertexSplit& ahead = pm_.splits[level_ + kFetchAhead];
        for (uint32_t k = 0; k < ahead.moved_count; ++k) {
          const std::size_t f = pm_.moved_faces[ahead.moved_begin + k];
          if (f < fetched_faces) __builtin_prefetch(faces_.data() + 3 * f, 1);
        }
      }
      const VertexSplit& s = pm_.splits[level_];
      const uint32_t v = pm_.base_vertex_count + static_cast<uint32_t>(level_);
      for (uint32_t k = 0; k < s.moved_count; ++k) {
        const std::size_t f = pm_.moved_faces[s.moved_begin + k];
        uint32_t* face = &faces_[3 * f];
        for (int c = 0; c < 3; ++c) {
          if (face[c] != s.u) continue;
          face[c] = v;
          if (uvs_) corner_uvs_[3 * f + c] = pm_.moved_uvs[s.moved_begin + k];
          if (normals_) corner_normals_[3 * f + c] = pm_.moved_normals[s.moved_begin + k];
        }
      }
      if (s.vl != kNoVertex) faces_.insert(faces_.end(), {v, s.u, s.vl});
      if (s.vr != kNoVertex) faces_.insert(faces_.end(), {s.u, v, s.vr});
      const std::size_t added = s.new_face_count();
      if (uvs_) append_created(corner_uvs_, pm_.face_uvs, 3, created_, added);
      if (normals_) append_created(corner_normals_, pm_.face_normals, 3, created_, added);
      if (materials_) append_created(face_materials_, pm_.face_materials, 1, created_, added);
      created_ += added;
    }
  }

  // The mesh of the current level, with welded copies merged back, unused vertices dropped,
  // and the carried faces after the others.
  Mesh mesh() const {
    const ProgressiveMesh& pm = pm_;
    // The walker's faces, then the carried ones, are read in place (not copied: at full
    // detail of a big mesh a copy is tens of MB, each page written once more).
    std::vector<uint32_t> corner_uvs, corner_normals, face_materials;
    if (uvs_) corner_uvs = corner_uvs_;
    if (normals_) corner_normals = corner_normals_;
    if (materials_) face_materials = face_materials_;
    const std::size_t carried = pm.carried_faces.size() / 3;
    const std::size_t first_carried = pm.total_face_count() - carried;
    if (uvs_) append_created(corner_uvs, pm.face_uvs, 3, first_carried, carried);
    if (normals_) append_created(corner_normals, pm.face_normals, 3, first_carried, carried);
    if (materials_) append_created(face_materials, pm.face_materials, 1, first_carried, carried);

    // Output numbering: active vertices in id order, copies merged into their canonical
    // vertex, loose vertices at full detail only.
    const uint32_t active = pm.base_vertex_count + static_cast<uint32_t>(level_);
    const uint32_t total = static_cast<uint32_t>(pm.vertex_count());
    std::vector<uint32_t> canonical(active);
    for (uint32_t v = 0; v < active; ++v) canonical[v] = v;
    for (const Weld& w : pm.welds) canonical[w.copy] = w.canonical;
    const bool full = level_ == pm.splits.size();
    const uint32_t emitted = full ? total : active;
    std::vector<uint32_t> output_id(emitted, kNoVertex);
    Mesh mesh;
    const std::size_t cc = pm.color_components;
    mesh.color_components = pm.color_components;
    mesh.positions.reserve(3 * vertices_at_level(pm, level_));
    mesh.colors.reserve(cc * vertices_at_level(pm, level_));
    for (uint32_t v = 0; v < emitted; ++v) {
      if (v < active && canonical[v] != v) continue;
      output_id[v] = static_cast<uint32_t>(mesh.positions.size() / 3);
      mesh.positions.insert(mesh.positions.end(), pm.positions.begin() + 3 * v,
                            pm.positions.begin() + 3 * v + 3);
      mesh.colors.insert(mesh.colors.end(), pm.colors.begin() + cc * v,
                         pm.colors.begin() + cc * (v + 1));
    }
    mesh.triangles.resize(faces_.size() + pm.carried_faces.size());
    for (std::size_t i = 0; i < faces_.size(); ++i)
      mesh.triangles[i] = output_id[canonical[faces_[i]]];
    for (std::size_t i = 0; i < pm.carried_faces.size(); ++i)
      mesh.triangles[faces_.size() + i] = output_id[canonical[pm.carried_faces[i]]];

    if (uvs_) output_attribute(corner_uvs, pm.uvs, 2, full, mesh.uvs, mesh.uv_indices);
    if (normals_)
      output_attribute(corner_normals, pm.normals, 3, full, mesh.normals, mesh.normal_indices);
    mesh.face_materials = std::move(face_materials);
    mesh.material_names = pm.material_names;
    mesh.material_libraries = pm.material_libraries;
    if (full && pm.keeps_order()) return in_input_order(std::move(mesh), output_id);
    return mesh;
  }

  // Full detail with the input's vertex and face order (pmenc --keep-order). Faces are in
  // creation order here, carried last: face id = index.
  Mesh in_input_order(Mesh mesh, const std::vector<uint32_t>& output_id) const {
    const ProgressiveMesh& pm = pm_;
    Mesh out;
    out.color_components = mesh.color_components;
    const std::size_t cc = mesh.color_components;
    std::vector<uint32_t> new_index(mesh.vertex_count());
    for (std::size_t i = 0; i < pm.input_vertices.size(); ++i) {
      const uint32_t from = output_id[pm.input_vertices[i]];
      new_index[from] = static_cast<uint32_t>(i);
      out.positions.insert(out.positions.end(), mesh.positions.begin() + 3 * from,
                           mesh.positions.begin() + 3 * from + 3);
      out.colors.insert(out.colors.end(), mesh.colors.begin() + cc * from,
                        mesh.colors.begin() + cc * (from + 1));
    }
    for (uint32_t code : pm.input_faces) {
      const std::size_t face = code / 3, rotation = code % 3;  // the input's first corner
      for (std::size_t c = 0; c < 3; ++c) {
        const std::size_t from = 3 * face + (rotation + c) % 3;
        out.triangles.push_back(new_index[mesh.triangles[from]]);
        if (mesh.has_uvs()) out.uv_indices.push_back(mesh.uv_indices[from]);
        if (mesh.has_normals()) out.normal_indices.push_back(mesh.normal_indices[from]);
      }
      if (mesh.has_materials()) out.face_materials.push_back(mesh.face_materials[face]);
    }
    out.uvs = std::move(mesh.uvs);
    out.normals = std::move(mesh.normals);
    out.material_names = std::move(mesh.material_names);
    out.material_libraries = std::move(mesh.material_libraries);
    return out;
  }

 private:
  const ProgressiveMesh& pm_;
  const bool uvs_, normals_, materials_;
  std::vector<uint32_t> faces_, corner_uvs_, corner_normals_, face_materials_;
  std::size_t level_ = 0;
  std::size_t created_ = 0;  // faces so far, in creation order
};

}  // namespace

Mesh extract_level(const ProgressiveMesh& pm, std::size_t level) {
  LevelWalker walker(pm);
  walker.advance(level);
  return walker.mesh();
}

void extract_levels(const ProgressiveMesh& pm, std::vector<std::size_t> levels,
                    const std::function<void(std::size_t, const Mesh&)>& emit) {
  for (std::size_t& level : levels) level = std::min(level, pm.splits.size());
  std::sort(levels.begin(), levels.end());
  levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
  LevelWalker walker(pm);
  for (std::size_t level : levels) {
    walker.advance(level);
    emit(level, walker.mesh());
  }
}

}  // namespace pm
