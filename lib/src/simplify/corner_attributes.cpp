// Wedges on the half-edge mesh (Hoppe 1996, §3), seams kept as discontinuities
// (Garland and Heckbert 1998, §4), attribute error by quadrics (Hoppe 1999, §4).
#include "simplify/corner_attributes.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <unordered_map>
#include <utility>

namespace pm {
namespace {

using FaceHandle = HalfEdgeMesh::FaceHandle;
using VertexHandle = HalfEdgeMesh::VertexHandle;
using HalfedgeHandle = HalfEdgeMesh::HalfedgeHandle;

constexpr uint32_t kNoWedge = 0xFFFFFFFFu;

// A normal's deviation counts like a displacement of this fraction of the bounding-box
// diagonal per unit of normal: a 6 degree turn (0.1) weighs like 0.1% of the diagonal.
constexpr double kNormalScaleOfDiagonal = 0.01;

// Ids whose values have the same bits get the smallest such id: seams are where values
// differ, whatever ids the file gave them.
std::vector<uint32_t> value_classes(const std::vector<float>& values, int dims) {
  const std::size_t count = values.size() / dims;
  std::vector<uint32_t> cls(count);
  struct Key {
    uint32_t bits[3] = {0, 0, 0};
    bool operator==(const Key& o) const {
      return bits[0] == o.bits[0] && bits[1] == o.bits[1] && bits[2] == o.bits[2];
    }
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      uint64_t h = k.bits[0] * 0x9E3779B97F4A7C15ull;
      h ^= (h >> 29) + k.bits[1] * 0xBF58476D1CE4E5B9ull;
      h ^= (h >> 31) + k.bits[2] * 0x94D049BB133111EBull;
      return static_cast<std::size_t>(h ^ (h >> 32));
    }
  };
  std::unordered_map<Key, uint32_t, KeyHash> first;
  first.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    Key key;
    std::memcpy(key.bits, values.data() + i * dims, sizeof(float) * dims);
    cls[i] = first.emplace(key, static_cast<uint32_t>(i)).first->second;
  }
  return cls;
}

double uv_triangle_area(const float* a, const float* b, const float* c) {
  return 0.5 * ((double(b[0]) - a[0]) * (double(c[1]) - a[1]) -
                (double(b[1]) - a[1]) * (double(c[0]) - a[0]));
}

int sign(double x) { return (x > 0) - (x < 0); }

}  // namespace

CornerAttributes::CornerAttributes(const Mesh& input, const ManifoldMesh& repaired) {
  const HalfEdgeMesh& mesh = repaired.mesh;
  const std::size_t faces = mesh.n_faces();
  vertex_.resize(faces);
  for (auto f : mesh.faces()) {
    int k = 0;
    for (auto w : mesh.fv_range(f)) vertex_[f.idx()][k++] = static_cast<uint32_t>(w.idx());
  }
  // The input corner each half-edge-mesh corner is: the face's vertices are distinct
  // input vertices, so the input vertex of the corner's copy names it.
  auto input_corner = [&](std::size_t f, int k) {
    const uint32_t face = repaired.input_face[f];
    const uint32_t w = repaired.input_vertex[vertex_[f][k]];
    for (int j = 0; j < 3; ++j)
      if (input.triangles[3 * std::size_t{face} + j] == w) return 3 * std::size_t{face} + j;
    return 3 * std::size_t{face};  // unreachable for a face of distinct vertices
  };

  const std::vector<uint32_t>* input_ids[kKinds] = {&input.uv_indices, &input.normal_indices};
  const std::vector<float>* tables[kKinds] = {&input.uvs, &input.normals};
  const int dims[kKinds] = {2, 3};
  for (int kind = 0; kind < kKinds; ++kind) {
    Kind& k = kinds_[kind];
    if (input_ids[kind]->empty()) continue;
    k.present = true;
    k.dims = dims[kind];
    k.values = tables[kind];
    k.value_class = value_classes(*tables[kind], dims[kind]);
    k.ids.resize(faces);
    for (std::size_t f = 0; f < faces; ++f)
      for (int c = 0; c < 3; ++c) k.ids[f][c] = (*input_ids[kind])[input_corner(f, c)];
  }
  if (!input.face_materials.empty()) {
    has_materials_ = true;
    material_.resize(faces);
    for (std::size_t f = 0; f < faces; ++f) material_[f] = input.face_materials[repaired.input_face[f]];
  }

  // Scales that make an attribute deviation comparable to a distance. Texture: the
  // surface's model units per texture unit, the square root of the ratio of the surface's
  // area to its area in texture space. Normals: a fixed share of the diagonal.
  if (has_uvs()) {
    double area = 0, uv_area = 0;
    for (auto f : mesh.faces()) {
      const auto& ids = kinds_[kUv].ids[f.idx()];
      if (ids[0] == kNoAttribute || ids[1] == kNoAttribute || ids[2] == kNoAttribute) continue;
      const Vec3 a = point_of(mesh, mesh.vertex_handle(vertex_[f.idx()][0]));
      const Vec3 b = point_of(mesh, mesh.vertex_handle(vertex_[f.idx()][1]));
      const Vec3 c = point_of(mesh, mesh.vertex_handle(vertex_[f.idx()][2]));
      area += 0.5 * area_vector(a, b, c).norm();
      uv_area += std::abs(uv_triangle_area(kinds_[kUv].value(ids[0]), kinds_[kUv].value(ids[1]),
                                           kinds_[kUv].value(ids[2])));
    }
    kinds_[kUv].scale = uv_area > 0 && area > 0 ? std::sqrt(area / uv_area) : 0;
  }
  if (has_normals()) {
    Vec3 lo(HUGE_VAL, HUGE_VAL, HUGE_VAL), hi(-HUGE_VAL, -HUGE_VAL, -HUGE_VAL);
    for (auto v : mesh.vertices()) {
      lo.minimize(point_of(mesh, v));
      hi.maximize(point_of(mesh, v));
    }
    kinds_[kNormal].scale = mesh.n_vertices() ? kNormalScaleOfDiagonal * (hi - lo).norm() : 0;
  }
  for (int kind = 0; kind < kKinds; ++kind)
    if (kinds_[kind].present) initialize_wedges(kind, mesh);
}

// One wedge per vertex and value; each face adds its quadric to its three corners' wedges.
void CornerAttributes::initialize_wedges(int kind, const HalfEdgeMesh& mesh) {
  Kind& k = kinds_[kind];
  k.wedge.assign(mesh.n_faces(), {kNoWedge, kNoWedge, kNoWedge});
  uint32_t wedges = 0;
  std::vector<std::pair<uint32_t, uint32_t>> seen;  // (class, wedge) around one vertex
  for (auto v : mesh.vertices()) {
    seen.clear();
    for (auto f : mesh.vf_range(v)) {
      const int c = corner_of(f, v);
      const uint32_t cls = k.class_of(k.ids[f.idx()][c]);
      if (cls == kNoAttribute) continue;
      auto it = std::find_if(seen.begin(), seen.end(), [&](auto& s) { return s.first == cls; });
      if (it == seen.end()) it = seen.insert(seen.end(), {cls, wedges++});
      k.wedge[f.idx()][c] = it->second;
    }
  }
  if (kind == kUv) uv_quadrics_.assign(wedges, {});
  else normal_quadrics_.assign(wedges, {});
  for (auto f : mesh.faces()) {
    const auto& ids = k.ids[f.idx()];
    if (ids[0] == kNoAttribute || ids[1] == kNoAttribute || ids[2] == kNoAttribute) continue;
    Vec3 p[3];
    const float* values[3];
    for (int c = 0; c < 3; ++c) {
      p[c] = point_of(mesh, mesh.vertex_handle(vertex_[f.idx()][c]));
      values[c] = k.value(ids[c]);
    }
    const double area = 0.5 * area_vector(p[0], p[1], p[2]).norm();
    for (int c = 0; c < 3; ++c) {
      const uint32_t w = k.wedge[f.idx()][c];
      if (kind == kUv)
        uv_quadrics_[w] += AttributeQuadric<2>::from_face(p, values, area);
      else
        normal_quadrics_[w] += AttributeQuadric<3>::from_face(p, values, area);
    }
  }
}

int CornerAttributes::corner_of(FaceHandle f, VertexHandle w) const {
  const auto& vs = vertex_[f.idx()];
  const uint32_t x = static_cast<uint32_t>(w.idx());
  return vs[0] == x ? 0 : vs[1] == x ? 1 : 2;
}

bool CornerAttributes::is_seam_of_kind(int kind, const HalfEdgeMesh& mesh, HalfedgeHandle h) const {
  if (mesh.is_boundary(mesh.edge_handle(h))) return false;
  const FaceHandle f = mesh.face_handle(h), g = mesh.opposite_face_handle(h);
  if (kind == kKinds) return material_[f.idx()] != material_[g.idx()];
  const VertexHandle a = mesh.from_vertex_handle(h), b = mesh.to_vertex_handle(h);
  return class_at(kind, f, a) != class_at(kind, g, a) || class_at(kind, f, b) != class_at(kind, g, b);
}

bool CornerAttributes::is_seam(const HalfEdgeMesh& mesh, HalfEdgeMesh::EdgeHandle e) const {
  const HalfedgeHandle h = mesh.halfedge_handle(e, 0);
  for (int kind = 0; kind < kKinds; ++kind)
    if (kinds_[kind].present && is_seam_of_kind(kind, mesh, h)) return true;
  return has_materials() && is_seam_of_kind(kKinds, mesh, h);
}

bool CornerAttributes::is_uv_seam(const HalfEdgeMesh& mesh, HalfEdgeMesh::EdgeHandle e) const {
  return has_uvs() && is_seam_of_kind(kUv, mesh, mesh.halfedge_handle(e, 0));
}

// kind kKinds stands for materials.
bool CornerAttributes::kind_allows(int kind, const HalfEdgeMesh& mesh, HalfedgeHandle h) const {
  const VertexHandle v = mesh.from_vertex_handle(h);
  int seams = 0;
  bool along = false;
  for (auto out : mesh.voh_range(v)) {
    if (!is_seam_of_kind(kind, mesh, out)) continue;
    ++seams;
    along |= mesh.edge_handle(out) == mesh.edge_handle(h);
  }
  if (seams == 0) return true;  // v-u is no seam: u's two sides of it agree too
  if (seams != 2 || !along) return false;
  if (kind == kKinds) return true;
  // v's two sides must differ, so that its corners split between u's two sides; a seam
  // that differs only at u would open a new seam there.
  const VertexHandle u = mesh.to_vertex_handle(h);
  const FaceHandle fl = mesh.face_handle(h), fr = mesh.opposite_face_handle(h);
  return class_at(kind, fl, v) != class_at(kind, fr, v) || class_at(kind, fl, u) == class_at(kind, fr, u);
}

std::pair<FaceHandle, int> CornerAttributes::target_corner(int kind, const HalfEdgeMesh& mesh,
                                                           HalfedgeHandle h, uint32_t v_class) const {
  const VertexHandle v = mesh.from_vertex_handle(h), u = mesh.to_vertex_handle(h);
  const FaceHandle fl = mesh.face_handle(h), fr = mesh.opposite_face_handle(h);
  const bool left = fl.is_valid() && (!fr.is_valid() || class_at(kind, fl, v) == v_class);
  const FaceHandle f = left ? fl : fr;
  return {f, corner_of(f, u)};
}

bool CornerAttributes::keeps_uv_winding(const HalfEdgeMesh& mesh, HalfedgeHandle h) const {
  const Kind& k = kinds_[kUv];
  const VertexHandle v = mesh.from_vertex_handle(h);
  const FaceHandle fl = mesh.face_handle(h), fr = mesh.opposite_face_handle(h);
  for (auto g : mesh.vf_range(v)) {
    if (g == fl || g == fr) continue;
    const auto& ids = k.ids[g.idx()];
    if (ids[0] == kNoAttribute || ids[1] == kNoAttribute || ids[2] == kNoAttribute) continue;
    const int c = corner_of(g, v);
    const auto [tf, tc] = target_corner(kUv, mesh, h, k.class_of(ids[c]));
    const uint32_t target = k.ids[tf.idx()][tc];
    if (target == kNoAttribute) return false;
    const float* value[3] = {k.value(ids[0]), k.value(ids[1]), k.value(ids[2])};
    const int before = sign(uv_triangle_area(value[0], value[1], value[2]));
    value[c] = k.value(target);
    const int after = sign(uv_triangle_area(value[0], value[1], value[2]));
    if (before != 0 && after != before) return false;
  }
  return true;
}

bool CornerAttributes::collapse_keeps_attributes(const HalfEdgeMesh& mesh, HalfedgeHandle h) const {
  for (int kind = 0; kind < kKinds; ++kind)
    if (kinds_[kind].present && !kind_allows(kind, mesh, h)) return false;
  if (has_materials() && !kind_allows(kKinds, mesh, h)) return false;
  return !has_uvs() || keeps_uv_winding(mesh, h);
}

double CornerAttributes::collapse_cost(const HalfEdgeMesh& mesh, HalfedgeHandle h) const {
  const VertexHandle v = mesh.from_vertex_handle(h), u = mesh.to_vertex_handle(h);
  const Vec3 pu = point_of(mesh, u);
  double cost = 0;
  uint32_t seen[64];
  for (int kind = 0; kind < kKinds; ++kind) {
    const Kind& k = kinds_[kind];
    if (!k.present || k.scale == 0) continue;
    double error = 0, weight = 0;
    int seen_count = 0;
    for (auto g : mesh.vf_range(v)) {
      const int c = corner_of(g, v);
      const uint32_t w = k.wedge[g.idx()][c];
      if (w == kNoWedge || std::find(seen, seen + seen_count, w) != seen + seen_count) continue;
      if (seen_count < 64) seen[seen_count++] = w;
      const auto [tf, tc] = target_corner(kind, mesh, h, k.class_of(k.ids[g.idx()][c]));
      const uint32_t target = k.ids[tf.idx()][tc];
      if (target == kNoAttribute) continue;
      if (kind == kUv) {
        error += uv_quadrics_[w].error(pu, k.value(target));
        weight += uv_quadrics_[w].weight;
      } else {
        error += normal_quadrics_[w].error(pu, k.value(target));
        weight += normal_quadrics_[w].weight;
      }
    }
    if (weight > 0) cost += k.scale * k.scale * error / weight;
  }
  return cost;
}

void CornerAttributes::collapse(const HalfEdgeMesh& mesh, HalfedgeHandle h,
                                CollapseAttributes& record) {
  const VertexHandle v = mesh.from_vertex_handle(h), u = mesh.to_vertex_handle(h);
  const FaceHandle fl = mesh.face_handle(h), fr = mesh.opposite_face_handle(h);
  // The removed faces as the split re-creates them.
  auto record_face = [&](FaceHandle f, VertexHandle a, VertexHandle b, VertexHandle c) {
    uint32_t uvs[3], normals[3];
    corner_ids(f, {a, b, c}, uvs, normals);
    if (has_uvs()) record.new_face_uvs.insert(record.new_face_uvs.end(), uvs, uvs + 3);
    if (has_normals()) record.new_face_normals.insert(record.new_face_normals.end(), normals, normals + 3);
  };
  if (fl.is_valid()) record_face(fl, v, u, mesh.to_vertex_handle(mesh.next_halfedge_handle(h)));
  if (fr.is_valid()) {
    const HalfedgeHandle o = mesh.opposite_halfedge_handle(h);
    record_face(fr, u, v, mesh.to_vertex_handle(mesh.next_halfedge_handle(o)));
  }

  // v's wedges merge into u's (their quadrics add, Garland and Heckbert 1997 §4), then
  // the moved corners take u's ids. Targets are read from fl and fr, which do not move.
  for (int kind = 0; kind < kKinds; ++kind) {
    Kind& k = kinds_[kind];
    if (!k.present) continue;
    uint32_t merged[64];
    int merged_count = 0;
    for (auto g : mesh.vf_range(v)) {
      const int c = corner_of(g, v);
      const uint32_t w = k.wedge[g.idx()][c];
      if (w == kNoWedge || std::find(merged, merged + merged_count, w) != merged + merged_count)
        continue;
      if (merged_count < 64) merged[merged_count++] = w;
      const auto [tf, tc] = target_corner(kind, mesh, h, k.class_of(k.ids[g.idx()][c]));
      const uint32_t target = k.wedge[tf.idx()][tc];
      if (target == kNoWedge || target == w) continue;
      if (kind == kUv) uv_quadrics_[target] += uv_quadrics_[w];
      else normal_quadrics_[target] += normal_quadrics_[w];
    }
  }
  for (auto g : mesh.vf_range(v)) {
    if (g == fl || g == fr) continue;
    const int c = corner_of(g, v);
    for (int kind = 0; kind < kKinds; ++kind) {
      Kind& k = kinds_[kind];
      if (!k.present) continue;
      std::vector<uint32_t>& moved = kind == kUv ? record.moved_uvs : record.moved_normals;
      moved.push_back(k.ids[g.idx()][c]);
      const auto [tf, tc] = target_corner(kind, mesh, h, k.class_of(k.ids[g.idx()][c]));
      k.ids[g.idx()][c] = k.ids[tf.idx()][tc];
      k.wedge[g.idx()][c] = k.wedge[tf.idx()][tc];
    }
    vertex_[g.idx()][c] = static_cast<uint32_t>(u.idx());
  }
}

void CornerAttributes::corner_ids(FaceHandle f, const VertexHandle (&at)[3], uint32_t (&uvs)[3],
                                  uint32_t (&normals)[3]) const {
  for (int i = 0; i < 3; ++i) {
    const int c = corner_of(f, at[i]);
    uvs[i] = has_uvs() ? kinds_[kUv].ids[f.idx()][c] : kNoAttribute;
    normals[i] = has_normals() ? kinds_[kNormal].ids[f.idx()][c] : kNoAttribute;
  }
}

}  // namespace pm
