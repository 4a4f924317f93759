// Runtime refinement and coarsening in place (Hoppe 1998, "Efficient implementation of
// progressive meshes", §4-5: wedges as render vertices, faces in creation order so the
// active ones are a prefix, vsplit / ecol records that rewrite one corner per moved face)
// and geomorphs (Hoppe 1996, "Progressive meshes", §4.2).
#include "pm/lod_runtime.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace pm {
namespace {

// A wedge: a vertex with one texture coordinate and one normal (Hoppe 1996, §3).
struct WedgeKey {
  uint32_t vertex, uv, normal;
  bool operator==(const WedgeKey& o) const {
    return vertex == o.vertex && uv == o.uv && normal == o.normal;
  }
};
struct WedgeKeyHash {
  std::size_t operator()(const WedgeKey& k) const {
    uint64_t h = k.vertex * 0x9E3779B97F4A7C15ull;
    h ^= (h >> 29) + k.uv * 0xBF58476D1CE4E5B9ull;
    h ^= (h >> 31) + k.normal * 0x94D049BB133111EBull;
    return static_cast<std::size_t>(h ^ (h >> 32));
  }
};

constexpr uint32_t kNone = 0xFFFFFFFFu;

}  // namespace

RuntimeLod::RuntimeLod(const ProgressiveMesh& pm) {
  const uint32_t base_faces = static_cast<uint32_t>(pm.base_face_count());
  const uint32_t carried = static_cast<uint32_t>(pm.carried_faces.size() / 3);
  const std::size_t total_faces = pm.total_face_count();
  const bool has_uvs = pm.has_uvs(), has_normals = pm.has_normals();
  base_vertex_count_ = pm.base_vertex_count;
  color_components_ = pm.color_components;
  material_names_ = pm.material_names;
  material_libraries_ = pm.material_libraries;
  if (!pm.welds.empty()) {
    canonical_.resize(pm.base_vertex_count);
    for (uint32_t v = 0; v < pm.base_vertex_count; ++v) canonical_[v] = v;
    for (const Weld& w : pm.welds) canonical_[w.copy] = w.canonical;
  }

  std::unordered_map<WedgeKey, uint32_t, WedgeKeyHash> wedge_of;
  wedge_of.reserve(pm.vertex_count() + pm.vertex_count() / 4);
  std::vector<uint32_t> wedge_uv_id, wedge_normal_id;
  // A vertex's first wedge: the parent of a wedge the vertex gains at a later split (the
  // corner of a new face whose values no face of the coarser mesh has), so that geomorphs
  // move it with its vertex.
  std::vector<uint32_t> first_wedge(pm.vertex_count(), kNone);
  uint32_t splitting = kNone;  // the vertex the current split creates: its wedges merge into u's
  auto wedge = [&](uint32_t vertex, uint32_t uv, uint32_t normal) {
    const auto [it, added] =
        wedge_of.emplace(WedgeKey{vertex, uv, normal}, static_cast<uint32_t>(wedge_vertex_.size()));
    if (added) {
      wedge_vertex_.push_back(vertex);
      wedge_uv_id.push_back(uv);
      wedge_normal_id.push_back(normal);
      wedge_parent_.push_back(vertex == splitting ? kNone : first_wedge[vertex]);
      if (first_wedge[vertex] == kNone) first_wedge[vertex] = it->second;
    }
    return it->second;
  };
  // Face slots: carried faces (active at every level), base faces, then the faces the
  // splits add. pm's creation order is base, split faces, carried; face ids in
  // moved_faces count base and split faces.
  indices_.assign(3 * total_faces, 0);
  face_materials_.reserve(pm.face_materials.size());
  auto creation_index = [&](std::size_t slot) -> std::size_t {
    return slot < carried ? total_faces - carried + slot : slot - carried;
  };
  auto place_face = [&](std::size_t slot, const uint32_t* vertices) {
    const std::size_t created = creation_index(slot);
    for (int c = 0; c < 3; ++c) {
      const uint32_t uv = has_uvs ? pm.face_uvs[3 * created + c] : kNoAttribute;
      const uint32_t normal = has_normals ? pm.face_normals[3 * created + c] : kNoAttribute;
      indices_[3 * slot + c] = wedge(vertices[c], uv, normal);
    }
  };
  for (uint32_t k = 0; k < carried; ++k) place_face(k, &pm.carried_faces[3 * k]);
  for (uint32_t f = 0; f < base_faces; ++f) place_face(carried + f, &pm.base_faces[3 * f]);

  // Replay every split once, recording what it rewrites (Hoppe 1998, §5: vsplit records).
  const std::size_t levels = pm.splits.size();
  splits_.reserve(levels);
  moved_.reserve(pm.moved_faces.size());
  face_end_.reserve(levels + 1);
  wedge_end_.reserve(levels + 1);
  uint32_t faces = carried + base_faces;
  face_end_.push_back(faces);
  wedge_end_.push_back(static_cast<uint32_t>(wedge_vertex_.size()));
  for (std::size_t i = 0; i < levels; ++i) {
    const VertexSplit& s = pm.splits[i];
    const uint32_t v = pm.base_vertex_count + static_cast<uint32_t>(i);
    splitting = v;
    Split record{static_cast<uint32_t>(moved_.size()), 0, s.new_face_count()};
    for (uint32_t k = 0; k < s.moved_count; ++k) {
      const uint32_t entry = s.moved_begin + k;
      const uint32_t slot = carried + pm.moved_faces[entry];
      int c = 0;
      while (wedge_vertex_[indices_[3 * slot + c]] != s.u) ++c;  // validate(): u is there once
      const uint32_t coarse = indices_[3 * slot + c];
      const uint32_t fine = wedge(v, has_uvs ? pm.moved_uvs[entry] : kNoAttribute,
                                  has_normals ? pm.moved_normals[entry] : kNoAttribute);
      if (wedge_parent_[fine] == kNone) wedge_parent_[fine] = coarse;
      moved_.push_back({3 * slot + c, fine, coarse});
      indices_[3 * slot + c] = fine;
    }
    record.moved_end = static_cast<uint32_t>(moved_.size());
    // New faces fl = (v, u, vl), fr = (u, v, vr): v's corner merges into u's of the same face.
    if (s.vl != kNoVertex) {
      const uint32_t corners[3] = {v, s.u, s.vl};
      place_face(faces, corners);
      if (wedge_parent_[indices_[3 * faces]] == kNone)
        wedge_parent_[indices_[3 * faces]] = indices_[3 * faces + 1];
      ++faces;
    }
    if (s.vr != kNoVertex) {
      const uint32_t corners[3] = {s.u, v, s.vr};
      place_face(faces, corners);
      if (wedge_parent_[indices_[3 * faces + 1]] == kNone)
        wedge_parent_[indices_[3 * faces + 1]] = indices_[3 * faces];
      ++faces;
    }
    splits_.push_back(record);
    face_end_.push_back(faces);
    wedge_end_.push_back(static_cast<uint32_t>(wedge_vertex_.size()));
  }
  level_ = levels;

  for (std::size_t slot = 0; slot < total_faces && pm.has_materials(); ++slot)
    face_materials_.push_back(pm.face_materials[creation_index(slot)]);
  vertex_end_.resize(levels + 1);
  errors_.resize(levels + 1);
  for (std::size_t l = 0; l <= levels; ++l) {
    vertex_end_[l] = static_cast<uint32_t>(pm.base_vertex_count + l - pm.welds.size() +
                                           (l == levels ? pm.loose_vertex_count : 0));
    errors_[l] = l < levels ? pm.splits[l].error : 0.0f;
  }

  // Wedge values, stored once.
  const std::size_t wedges = wedge_vertex_.size();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  wedge_positions_.resize(3 * wedges);
  if (has_uvs) wedge_uvs_.assign(2 * wedges, nan);
  if (has_normals) wedge_normals_.assign(3 * wedges, nan);
  wedge_colors_.resize(std::size_t{color_components_} * wedges);
  for (std::size_t w = 0; w < wedges; ++w) {
    const std::size_t v = wedge_vertex_[w];
    std::copy_n(&pm.positions[3 * v], 3, &wedge_positions_[3 * w]);
    if (has_uvs && wedge_uv_id[w] != kNoAttribute)
      std::copy_n(&pm.uvs[2 * std::size_t{wedge_uv_id[w]}], 2, &wedge_uvs_[2 * w]);
    if (has_normals && wedge_normal_id[w] != kNoAttribute)
      std::copy_n(&pm.normals[3 * std::size_t{wedge_normal_id[w]}], 3, &wedge_normals_[3 * w]);
    std::copy_n(pm.colors.begin() + color_components_ * v, color_components_,
                wedge_colors_.begin() + color_components_ * w);
  }
  wedge_has_uv_.resize(has_uvs ? wedges : 0);
  wedge_has_normal_.resize(has_normals ? wedges : 0);
  for (std::size_t w = 0; w < wedge_has_uv_.size(); ++w) wedge_has_uv_[w] = wedge_uv_id[w] != kNoAttribute;
  for (std::size_t w = 0; w < wedge_has_normal_.size(); ++w)
    wedge_has_normal_[w] = wedge_normal_id[w] != kNoAttribute;

  // Back to the base mesh: each face that leaves the prefix is left as it is re-created.
  coarsen_to(0);
}

std::size_t RuntimeLod::vertex_count() const { return vertex_end_[level_]; }

void RuntimeLod::refine_to(std::size_t level) {
  for (; level_ < level; ++level_) {
    const Split& s = splits_[level_];
    for (uint32_t k = s.moved_begin; k < s.moved_end; ++k) indices_[moved_[k].index] = moved_[k].fine;
  }
}

void RuntimeLod::coarsen_to(std::size_t level) {
  while (level_ > level) {
    const Split& s = splits_[--level_];
    for (uint32_t k = s.moved_end; k-- > s.moved_begin;) indices_[moved_[k].index] = moved_[k].coarse;
  }
}

void RuntimeLod::set_level(std::size_t level) {
  level = std::min(level, max_level());
  if (level > level_) refine_to(level);
  else coarsen_to(level);
}

void RuntimeLod::set_face_count(std::size_t n) {
  const auto it = std::lower_bound(face_end_.begin(), face_end_.end(), n);
  set_level(it == face_end_.end() ? max_level() : std::size_t(it - face_end_.begin()));
}

void RuntimeLod::set_vertex_count(std::size_t n) {
  // vertex_end_ is increasing but for the last level (loose vertices): search the rest.
  const auto it = std::lower_bound(vertex_end_.begin(), vertex_end_.end() - 1, n);
  set_level(std::size_t(it - vertex_end_.begin()));
}

void RuntimeLod::set_error(double e) {
  // errors_ is non-increasing: the first level whose bound is at most e.
  const auto it = std::partition_point(errors_.begin(), errors_.end(),
                                       [e](float bound) { return bound > e; });
  set_level(std::size_t(it - errors_.begin()));
}

Mesh RuntimeLod::to_mesh() const {
  Mesh mesh;
  const std::size_t faces = face_count();
  std::vector<uint32_t> output(wedge_count(), kNone);
  const bool uvs = !wedge_uvs_.empty(), normals = !wedge_normals_.empty();
  mesh.color_components = color_components_;
  mesh.triangles.resize(3 * faces);
  if (uvs) mesh.uv_indices.resize(3 * faces);
  if (normals) mesh.normal_indices.resize(3 * faces);
  for (std::size_t i = 0; i < 3 * faces; ++i) {
    const uint32_t w = indices_[i];
    if (output[w] == kNone) {
      output[w] = static_cast<uint32_t>(mesh.positions.size() / 3);
      mesh.positions.insert(mesh.positions.end(), &wedge_positions_[3 * w], &wedge_positions_[3 * w] + 3);
      mesh.colors.insert(mesh.colors.end(), wedge_colors_.begin() + color_components_ * w,
                         wedge_colors_.begin() + color_components_ * (w + 1));
      if (uvs) mesh.uvs.insert(mesh.uvs.end(), &wedge_uvs_[2 * w], &wedge_uvs_[2 * w] + 2);
      if (normals)
        mesh.normals.insert(mesh.normals.end(), &wedge_normals_[3 * w], &wedge_normals_[3 * w] + 3);
    }
    mesh.triangles[i] = output[w];
    if (uvs) mesh.uv_indices[i] = wedge_has_uv_[w] ? output[w] : kNoAttribute;
    if (normals) mesh.normal_indices[i] = wedge_has_normal_[w] ? output[w] : kNoAttribute;
  }
  if (!face_materials_.empty()) mesh.face_materials.assign(face_materials_.begin(), face_materials_.begin() + faces);
  mesh.material_names = material_names_;
  return mesh;
}

std::size_t RuntimeLod::memory_bytes() const {
  auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  return sizeof(*this) + bytes(splits_) + bytes(moved_) + bytes(face_end_) + bytes(wedge_end_) +
         bytes(vertex_end_) + bytes(errors_) + bytes(indices_) + bytes(wedge_positions_) +
         bytes(wedge_uvs_) + bytes(wedge_normals_) + bytes(wedge_colors_) + bytes(wedge_vertex_) +
         bytes(wedge_parent_) + bytes(face_materials_) + wedge_has_uv_.capacity() / 8 +
         wedge_has_normal_.capacity() / 8;
}

RuntimeLod::Geomorph RuntimeLod::geomorph(std::size_t from, std::size_t to) {
  to = std::min(to, max_level());
  from = std::min(from, to);
  set_level(to);
  Geomorph g;
  g.owner_ = this;
  g.wedge_count_ = wedge_count();
  g.indices_.assign(indices_.begin(), indices_.begin() + 3 * face_count());
  // Hoppe 1996, §4.2: a vertex that `from` does not have starts where its ancestor is in
  // `from`: follow the wedges each collapse merges it into until one is active there.
  const uint32_t active = base_vertex_count_ + static_cast<uint32_t>(from);
  std::vector<uint32_t> start(g.wedge_count_, kNone);
  std::vector<uint32_t> chain;
  for (uint32_t w = 0; w < g.wedge_count_; ++w) {
    uint32_t x = w;
    chain.clear();
    while (start[x] == kNone && wedge_vertex_[x] >= active && wedge_parent_[x] != kNone) {
      chain.push_back(x);
      x = wedge_parent_[x];
    }
    const uint32_t root = start[x] == kNone ? x : start[x];
    for (uint32_t y : chain) start[y] = root;
    start[x] = root;
  }
  const bool uvs = !wedge_uvs_.empty(), normals = !wedge_normals_.empty();
  for (uint32_t w = 0; w < g.wedge_count_; ++w) {
    if (start[w] == w) continue;
    const uint32_t s = start[w];
    g.morphing_.push_back(w);
    g.start_positions_.insert(g.start_positions_.end(), &wedge_positions_[3 * s], &wedge_positions_[3 * s] + 3);
    g.end_positions_.insert(g.end_positions_.end(), &wedge_positions_[3 * w], &wedge_positions_[3 * w] + 3);
    if (uvs) {
      g.start_uvs_.insert(g.start_uvs_.end(), &wedge_uvs_[2 * s], &wedge_uvs_[2 * s] + 2);
      g.end_uvs_.insert(g.end_uvs_.end(), &wedge_uvs_[2 * w], &wedge_uvs_[2 * w] + 2);
    }
    if (normals) {
      g.start_normals_.insert(g.start_normals_.end(), &wedge_normals_[3 * s], &wedge_normals_[3 * s] + 3);
      g.end_normals_.insert(g.end_normals_.end(), &wedge_normals_[3 * w], &wedge_normals_[3 * w] + 3);
    }
    const std::size_t cc = color_components_;
    g.start_colors_.insert(g.start_colors_.end(), wedge_colors_.begin() + cc * s,
                           wedge_colors_.begin() + cc * (s + 1));
    g.end_colors_.insert(g.end_colors_.end(), wedge_colors_.begin() + cc * w,
                         wedge_colors_.begin() + cc * (w + 1));
  }
  return g;
}

void RuntimeLod::Geomorph::evaluate(float alpha, float* positions, float* uvs, float* normals,
                                    float* colors) const {
  const RuntimeLod& lod = *owner_;
  const std::size_t cc = lod.color_components_;
  std::copy_n(lod.wedge_positions_.data(), 3 * wedge_count_, positions);
  if (uvs && !lod.wedge_uvs_.empty()) std::copy_n(lod.wedge_uvs_.data(), 2 * wedge_count_, uvs);
  if (normals && !lod.wedge_normals_.empty())
    std::copy_n(lod.wedge_normals_.data(), 3 * wedge_count_, normals);
  if (colors && cc) std::copy_n(lod.wedge_colors_.data(), cc * wedge_count_, colors);
  // (1 - alpha) s + alpha e, with the ends copied so that they are exact to the bit (the
  // blend would turn a -0 end into +0).
  const float beta = 1.0f - alpha;
  auto blend = [&](const std::vector<float>& s, const std::vector<float>& e, std::size_t dims,
                   float* out) {
    if (!out || s.empty()) return;
    const std::vector<float>* end = alpha <= 0 ? &s : alpha >= 1 ? &e : nullptr;
    for (std::size_t k = 0; k < morphing_.size(); ++k) {
      float* to = out + dims * morphing_[k];
      if (end) {
        std::copy_n(end->data() + dims * k, dims, to);
        continue;
      }
      for (std::size_t d = 0; d < dims; ++d) to[d] = beta * s[dims * k + d] + alpha * e[dims * k + d];
    }
  };
  blend(start_positions_, end_positions_, 3, positions);
  blend(start_uvs_, end_uvs_, 2, uvs);
  blend(start_normals_, end_normals_, 3, normals);
  blend(start_colors_, end_colors_, cc, colors);
}

Mesh RuntimeLod::Geomorph::mesh(float alpha) const {
  const RuntimeLod& lod = *owner_;
  const std::size_t cc = lod.color_components_;
  std::vector<float> positions(3 * wedge_count_), uvs, normals, colors(cc * wedge_count_);
  if (!lod.wedge_uvs_.empty()) uvs.resize(2 * wedge_count_);
  if (!lod.wedge_normals_.empty()) normals.resize(3 * wedge_count_);
  evaluate(alpha, positions.data(), uvs.empty() ? nullptr : uvs.data(),
           normals.empty() ? nullptr : normals.data(), colors.empty() ? nullptr : colors.data());
  // One output vertex per vertex of the level (welded copies as their canonical vertex),
  // as extract_level() writes it: a vertex's wedges share its position and colour, which
  // morph together since they share an ancestor. Texture coordinates and normals stay per
  // corner, one table entry per wedge in use.
  Mesh mesh;
  mesh.color_components = lod.color_components_;
  std::unordered_map<uint32_t, uint32_t> vertex_out, wedge_out;
  mesh.triangles.resize(indices_.size());
  if (!uvs.empty()) mesh.uv_indices.resize(indices_.size());
  if (!normals.empty()) mesh.normal_indices.resize(indices_.size());
  for (std::size_t i = 0; i < indices_.size(); ++i) {
    const uint32_t w = indices_[i];
    uint32_t vertex = lod.wedge_vertex_[w];
    if (vertex < lod.canonical_.size()) vertex = lod.canonical_[vertex];
    const auto [v, new_vertex] = vertex_out.emplace(vertex, static_cast<uint32_t>(vertex_out.size()));
    if (new_vertex) {
      mesh.positions.insert(mesh.positions.end(), &positions[3 * w], &positions[3 * w] + 3);
      mesh.colors.insert(mesh.colors.end(), colors.begin() + cc * w, colors.begin() + cc * (w + 1));
    }
    mesh.triangles[i] = v->second;
    const auto [t, new_wedge] = wedge_out.emplace(w, static_cast<uint32_t>(wedge_out.size()));
    if (new_wedge) {
      if (!uvs.empty()) mesh.uvs.insert(mesh.uvs.end(), &uvs[2 * w], &uvs[2 * w] + 2);
      if (!normals.empty()) mesh.normals.insert(mesh.normals.end(), &normals[3 * w], &normals[3 * w] + 3);
    }
    if (!uvs.empty()) mesh.uv_indices[i] = lod.wedge_has_uv_[w] ? t->second : kNoAttribute;
    if (!normals.empty()) mesh.normal_indices[i] = lod.wedge_has_normal_[w] ? t->second : kNoAttribute;
  }
  if (!lod.face_materials_.empty())
    mesh.face_materials.assign(lod.face_materials_.begin(), lod.face_materials_.begin() + face_count());
  mesh.material_names = lod.material_names_;
  mesh.material_libraries = lod.material_libraries_;
  return mesh;
}

}  // namespace pm
