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
  auto built = std::make_shared<Wedges>();
  Wedges& W = *built;
  const uint32_t base_faces = static_cast<uint32_t>(pm.base_face_count());
  const uint32_t carried = static_cast<uint32_t>(pm.carried_faces.size() / 3);
  const std::size_t total_faces = pm.total_face_count();
  const bool has_uvs = pm.has_uvs(), has_normals = pm.has_normals();
  base_vertex_count_ = pm.base_vertex_count;
  W.color_components = pm.color_components;
  W.material_names = pm.material_names;
  W.material_libraries = pm.material_libraries;
  if (!pm.welds.empty()) {
    W.canonical.resize(pm.base_vertex_count);
    for (uint32_t v = 0; v < pm.base_vertex_count; ++v) W.canonical[v] = v;
    for (const Weld& w : pm.welds) W.canonical[w.copy] = w.canonical;
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
        wedge_of.emplace(WedgeKey{vertex, uv, normal}, static_cast<uint32_t>(W.vertex.size()));
    if (added) {
      W.vertex.push_back(vertex);
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
  W.face_materials.reserve(pm.face_materials.size());
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
  wedge_end_.push_back(static_cast<uint32_t>(W.vertex.size()));
  for (std::size_t i = 0; i < levels; ++i) {
    const VertexSplit& s = pm.splits[i];
    const uint32_t v = pm.base_vertex_count + static_cast<uint32_t>(i);
    splitting = v;
    Split record{static_cast<uint32_t>(moved_.size()), 0, s.new_face_count()};
    for (uint32_t k = 0; k < s.moved_count; ++k) {
      const uint32_t entry = s.moved_begin + k;
      const uint32_t slot = carried + pm.moved_faces[entry];
      int c = 0;
      while (W.vertex[indices_[3 * slot + c]] != s.u) ++c;  // validate(): u is there once
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
    wedge_end_.push_back(static_cast<uint32_t>(W.vertex.size()));
  }
  level_ = levels;

  for (std::size_t slot = 0; slot < total_faces && pm.has_materials(); ++slot)
    W.face_materials.push_back(pm.face_materials[creation_index(slot)]);
  vertex_end_.resize(levels + 1);
  errors_.resize(levels + 1);
  for (std::size_t l = 0; l <= levels; ++l) {
    vertex_end_[l] = static_cast<uint32_t>(pm.base_vertex_count + l - pm.welds.size() +
                                           (l == levels ? pm.loose_vertex_count : 0));
    errors_[l] = l < levels ? pm.splits[l].error : 0.0f;
  }

  // Wedge values, stored once.
  const std::size_t wedges = W.vertex.size();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  W.positions.resize(3 * wedges);
  if (has_uvs) W.uvs.assign(2 * wedges, nan);
  if (has_normals) W.normals.assign(3 * wedges, nan);
  W.colors.resize(std::size_t{W.color_components} * wedges);
  for (std::size_t w = 0; w < wedges; ++w) {
    const std::size_t v = W.vertex[w];
    std::copy_n(&pm.positions[3 * v], 3, &W.positions[3 * w]);
    if (has_uvs && wedge_uv_id[w] != kNoAttribute)
      std::copy_n(&pm.uvs[2 * std::size_t{wedge_uv_id[w]}], 2, &W.uvs[2 * w]);
    if (has_normals && wedge_normal_id[w] != kNoAttribute)
      std::copy_n(&pm.normals[3 * std::size_t{wedge_normal_id[w]}], 3, &W.normals[3 * w]);
    std::copy_n(pm.colors.begin() + W.color_components * v, W.color_components,
                W.colors.begin() + W.color_components * w);
  }
  W.has_uv.resize(has_uvs ? wedges : 0);
  W.has_normal.resize(has_normals ? wedges : 0);
  for (std::size_t w = 0; w < W.has_uv.size(); ++w) W.has_uv[w] = wedge_uv_id[w] != kNoAttribute;
  for (std::size_t w = 0; w < W.has_normal.size(); ++w)
    W.has_normal[w] = wedge_normal_id[w] != kNoAttribute;

  // Back to the base mesh: each face that leaves the prefix is left as it is re-created.
  wedges_ = std::move(built);
  coarsen_to(0);
}

std::size_t RuntimeLod::vertex_count() const { return vertex_end_[level_]; }
const float* RuntimeLod::positions() const { return wedges_->positions.data(); }
const float* RuntimeLod::uvs() const {
  return wedges_->uvs.empty() ? nullptr : wedges_->uvs.data();
}
const float* RuntimeLod::normals() const {
  return wedges_->normals.empty() ? nullptr : wedges_->normals.data();
}
const float* RuntimeLod::colors() const {
  return wedges_->colors.empty() ? nullptr : wedges_->colors.data();
}
uint32_t RuntimeLod::color_components() const { return wedges_->color_components; }
const uint32_t* RuntimeLod::face_materials() const {
  return wedges_->face_materials.empty() ? nullptr : wedges_->face_materials.data();
}
const std::vector<std::string>& RuntimeLod::material_names() const {
  return wedges_->material_names;
}
const std::vector<std::string>& RuntimeLod::material_libraries() const {
  return wedges_->material_libraries;
}

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

RuntimeLod::IndexRange RuntimeLod::set_level(std::size_t level) {
  level = std::min(level, max_level());
  if (level == level_) return {};
  // The splits between the two levels rewrite the corners moved_[first, last), whatever the
  // direction (Hoppe 1998, §5: a collapse undoes its split's rewrites).
  const bool refine = level > level_;
  const uint32_t first = splits_[refine ? level_ : level].moved_begin;
  const uint32_t last = splits_[(refine ? level : level_) - 1].moved_end;
  const std::size_t old_end = 3 * std::size_t{face_end_[level_]};
  const std::size_t new_end = 3 * std::size_t{face_end_[level]};
  std::size_t low = new_end, high = 0;
  for (uint32_t k = first; k < last; ++k) {
    const std::size_t index = moved_[k].index;
    if (index >= new_end) continue;  // a face that leaves the prefix
    low = std::min(low, index);
    high = std::max(high, index + 1);
  }
  if (refine) {
    refine_to(level);
    return {std::min(low, old_end), new_end};  // the appended faces too
  }
  coarsen_to(level);
  return low < high ? IndexRange{low, high} : IndexRange{};
}

RuntimeLod::IndexRange RuntimeLod::set_face_count(std::size_t n) {
  const auto it = std::lower_bound(face_end_.begin(), face_end_.end(), n);
  return set_level(it == face_end_.end() ? max_level() : std::size_t(it - face_end_.begin()));
}

RuntimeLod::IndexRange RuntimeLod::set_vertex_count(std::size_t n) {
  // vertex_end_ is increasing but for the last level (loose vertices): search the rest.
  const auto it = std::lower_bound(vertex_end_.begin(), vertex_end_.end() - 1, n);
  return set_level(std::size_t(it - vertex_end_.begin()));
}

RuntimeLod::IndexRange RuntimeLod::set_error(double e) {
  // errors_ is non-increasing: the first level whose bound is at most e.
  const auto it = std::partition_point(errors_.begin(), errors_.end(),
                                       [e](float bound) { return bound > e; });
  return set_level(std::size_t(it - errors_.begin()));
}

Mesh RuntimeLod::to_mesh() const {
  const Wedges& data = *wedges_;
  Mesh mesh;
  const std::size_t faces = face_count();
  std::vector<uint32_t> output(wedge_count(), kNone);
  const bool uvs = !data.uvs.empty(), normals = !data.normals.empty();
  mesh.color_components = data.color_components;
  mesh.triangles.resize(3 * faces);
  if (uvs) mesh.uv_indices.resize(3 * faces);
  if (normals) mesh.normal_indices.resize(3 * faces);
  for (std::size_t i = 0; i < 3 * faces; ++i) {
    const uint32_t w = indices_[i];
    if (output[w] == kNone) {
      output[w] = static_cast<uint32_t>(mesh.positions.size() / 3);
      mesh.positions.insert(mesh.positions.end(), &data.positions[3 * w], &data.positions[3 * w] + 3);
      mesh.colors.insert(mesh.colors.end(), data.colors.begin() + data.color_components * w,
                         data.colors.begin() + data.color_components * (w + 1));
      if (uvs) mesh.uvs.insert(mesh.uvs.end(), &data.uvs[2 * w], &data.uvs[2 * w] + 2);
      if (normals)
        mesh.normals.insert(mesh.normals.end(), &data.normals[3 * w], &data.normals[3 * w] + 3);
    }
    mesh.triangles[i] = output[w];
    if (uvs) mesh.uv_indices[i] = data.has_uv[w] ? output[w] : kNoAttribute;
    if (normals) mesh.normal_indices[i] = data.has_normal[w] ? output[w] : kNoAttribute;
  }
  if (!data.face_materials.empty()) mesh.face_materials.assign(data.face_materials.begin(), data.face_materials.begin() + faces);
  mesh.material_names = data.material_names;
  mesh.material_libraries = data.material_libraries;
  return mesh;
}

std::size_t RuntimeLod::memory_bytes() const {
  const Wedges& data = *wedges_;
  auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  return sizeof(*this) + sizeof(Wedges) + bytes(splits_) + bytes(moved_) + bytes(face_end_) + bytes(wedge_end_) +
         bytes(vertex_end_) + bytes(errors_) + bytes(indices_) + bytes(data.positions) +
         bytes(data.uvs) + bytes(data.normals) + bytes(data.colors) + bytes(data.vertex) +
         bytes(wedge_parent_) + bytes(data.face_materials) + data.has_uv.capacity() / 8 +
         data.has_normal.capacity() / 8;
}

RuntimeLod::Geomorph RuntimeLod::geomorph(std::size_t from, std::size_t to) {
  const Wedges& data = *wedges_;
  to = std::min(to, max_level());
  from = std::min(from, to);
  set_level(to);
  Geomorph g;
  g.wedges_ = wedges_;  // shared: the geomorph outlives a move of this object
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
    while (start[x] == kNone && data.vertex[x] >= active && wedge_parent_[x] != kNone) {
      chain.push_back(x);
      x = wedge_parent_[x];
    }
    const uint32_t root = start[x] == kNone ? x : start[x];
    for (uint32_t y : chain) start[y] = root;
    start[x] = root;
  }
  const bool uvs = !data.uvs.empty(), normals = !data.normals.empty();
  for (uint32_t w = 0; w < g.wedge_count_; ++w) {
    if (start[w] == w) continue;
    const uint32_t s = start[w];
    g.morphing_.push_back(w);
    g.starts_.push_back(s);
    g.start_positions_.insert(g.start_positions_.end(), &data.positions[3 * s], &data.positions[3 * s] + 3);
    g.end_positions_.insert(g.end_positions_.end(), &data.positions[3 * w], &data.positions[3 * w] + 3);
    if (uvs) {
      g.start_uvs_.insert(g.start_uvs_.end(), &data.uvs[2 * s], &data.uvs[2 * s] + 2);
      g.end_uvs_.insert(g.end_uvs_.end(), &data.uvs[2 * w], &data.uvs[2 * w] + 2);
    }
    if (normals) {
      g.start_normals_.insert(g.start_normals_.end(), &data.normals[3 * s], &data.normals[3 * s] + 3);
      g.end_normals_.insert(g.end_normals_.end(), &data.normals[3 * w], &data.normals[3 * w] + 3);
    }
    const std::size_t cc = data.color_components;
    g.start_colors_.insert(g.start_colors_.end(), data.colors.begin() + cc * s,
                           data.colors.begin() + cc * (s + 1));
    g.end_colors_.insert(g.end_colors_.end(), data.colors.begin() + cc * w,
                         data.colors.begin() + cc * (w + 1));
  }
  return g;
}

void RuntimeLod::Geomorph::evaluate(float alpha, float* positions, float* uvs, float* normals,
                                    float* colors) const {
  const Wedges& lod = *wedges_;
  const std::size_t cc = lod.color_components;
  std::copy_n(lod.positions.data(), 3 * wedge_count_, positions);
  if (uvs && !lod.uvs.empty()) std::copy_n(lod.uvs.data(), 2 * wedge_count_, uvs);
  if (normals && !lod.normals.empty())
    std::copy_n(lod.normals.data(), 3 * wedge_count_, normals);
  if (colors && cc) std::copy_n(lod.colors.data(), cc * wedge_count_, colors);
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
  const Wedges& lod = *wedges_;
  const std::size_t cc = lod.color_components;
  std::vector<float> positions(3 * wedge_count_), uvs, normals, colors(cc * wedge_count_);
  if (!lod.uvs.empty()) uvs.resize(2 * wedge_count_);
  if (!lod.normals.empty()) normals.resize(3 * wedge_count_);
  evaluate(alpha, positions.data(), uvs.empty() ? nullptr : uvs.data(),
           normals.empty() ? nullptr : normals.data(), colors.empty() ? nullptr : colors.data());
  // One output vertex per vertex of the level (welded copies as their canonical vertex),
  // as extract_level() writes it: a vertex's wedges share its position and colour, which
  // morph together since they share an ancestor. Texture coordinates and normals stay per
  // corner, one table entry per wedge in use.
  // Whether a corner has a texture coordinate (normal): the start wedge's flag at alpha 0,
  // where the mesh is level `from` exactly, the end wedge's above.
  std::vector<uint32_t> flags_of(wedge_count_);
  for (uint32_t w = 0; w < wedge_count_; ++w) flags_of[w] = w;
  if (alpha <= 0)
    for (std::size_t k = 0; k < morphing_.size(); ++k) flags_of[morphing_[k]] = starts_[k];
  Mesh mesh;
  mesh.color_components = lod.color_components;
  std::unordered_map<uint32_t, uint32_t> vertex_out, wedge_out;
  mesh.triangles.resize(indices_.size());
  if (!uvs.empty()) mesh.uv_indices.resize(indices_.size());
  if (!normals.empty()) mesh.normal_indices.resize(indices_.size());
  for (std::size_t i = 0; i < indices_.size(); ++i) {
    const uint32_t w = indices_[i];
    uint32_t vertex = lod.vertex[w];
    if (vertex < lod.canonical.size()) vertex = lod.canonical[vertex];
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
    if (!uvs.empty()) mesh.uv_indices[i] = lod.has_uv[flags_of[w]] ? t->second : kNoAttribute;
    if (!normals.empty())
      mesh.normal_indices[i] = lod.has_normal[flags_of[w]] ? t->second : kNoAttribute;
  }
  if (!lod.face_materials.empty())
    mesh.face_materials.assign(lod.face_materials.begin(), lod.face_materials.begin() + face_count());
  mesh.material_names = lod.material_names;
  mesh.material_libraries = lod.material_libraries;
  return mesh;
}

}  // namespace pm
