// Wedges on the half-edge mesh (Hoppe 1996, §3), seams kept as discontinuities
// (Garland and Heckbert 1998, §4), attribute error as Hoppe 1999, §4 measures it, over the
// current faces (memoryless: Lindstrom and Turk 1998, §3).
#include "simplify/corner_attributes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <utility>

#include "core/memory_pages.h"
#include "core/in_turn.h"

namespace pm {
namespace {

constexpr uint32_t kNoWedge = 0xFFFFFFFFu;

// A normal's deviation counts like a displacement of this fraction of the bounding-box
// diagonal per unit of normal: a 6 degree turn (0.1) weighs like 0.1% of the diagonal.
constexpr double kNormalScaleOfDiagonal = 0.01;

// Ids whose values have the same bits get the smallest such id: seams are where values
// differ, whatever ids the file gave them. An open-addressed table of ids (a million normals
// in a node-based map are a million allocations, and their frees).
std::vector<uint32_t> value_classes(const std::vector<float>& values, int dims) {
  const std::size_t count = values.size() / dims;
  std::vector<uint32_t> cls(count);
  auto bits_of = [&](std::size_t i) {
    std::array<uint32_t, 3> bits = {0, 0, 0};
    std::memcpy(bits.data(), values.data() + i * dims, sizeof(float) * dims);
    return bits;
  };
  auto hash = [](const std::array<uint32_t, 3>& bits) {
    uint64_t h = bits[0] * 0x9E3779B97F4A7C15ull;
    h ^= (h >> 29) + bits[1] * 0xBF58476D1CE4E5B9ull;
    h ^= (h >> 31) + bits[2] * 0x94D049BB133111EBull;
    return h ^ (h >> 32);
  };
  std::size_t slots = 16;
  while (slots < 2 * count) slots *= 2;
  constexpr uint32_t kEmpty = 0xFFFFFFFFu;
  std::vector<uint32_t> table(slots, kEmpty);  // ids, the first of their values
  for (std::size_t i = 0; i < count; ++i) {
    const std::array<uint32_t, 3> bits = bits_of(i);
    std::size_t slot = hash(bits) & (slots - 1);
    while (table[slot] != kEmpty && bits_of(table[slot]) != bits) slot = (slot + 1) & (slots - 1);
    if (table[slot] == kEmpty) table[slot] = static_cast<uint32_t>(i);
    cls[i] = table[slot];
  }
  return cls;
}

double uv_triangle_area(const float* a, const float* b, const float* c) {
  return 0.5 * ((double(b[0]) - a[0]) * (double(c[1]) - a[1]) -
                (double(b[1]) - a[1]) * (double(c[0]) - a[0]));
}

int sign(double x) { return (x > 0) - (x < 0); }

}  // namespace

CornerAttributes::CornerAttributes(const Mesh& input, FaceVertices corners,
                                   std::size_t faces, const float* points,
                                   std::size_t n_vertices, const uint32_t* input_face,
                                   const uint32_t* input_vertex, unsigned threads,
                                   const std::function<void()>& inputs_read) {
  auto input_face_of = [&](std::size_t f) {
    return input_face ? input_face[f] : static_cast<uint32_t>(f);
  };
  // The input corner each corner is: the face's vertices are distinct input vertices, so
  // the input vertex of the corner's copy names it.
  auto input_corner = [&](std::size_t f, int k) {
    const uint32_t face = input_face_of(f);
    const uint32_t w = input_vertex ? input_vertex[corners(f, k)] : corners(f, k);
    for (int j = 0; j < 3; ++j)
      if (input.triangles[3 * std::size_t{face} + j] == w) return 3 * std::size_t{face} + j;
    return 3 * std::size_t{face};  // unreachable for a face of distinct vertices
  };
  auto point = [&](uint32_t x) {
    const float* p = points + 3 * std::size_t{x};
    return Vec3(p[0], p[1], p[2]);
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
  }
  has_materials_ = !input.face_materials.empty();
  first_faces_ = faces;
  corners_ = corners;
  points_ = points;
  // Each face's record on its own: in slices, on `threads`.
  detail::assign_preferring_huge_pages(faces_, faces, {});
  if (has_materials_) detail::assign_preferring_huge_pages(materials_, faces, kNoAttribute);
  run_in_slices(faces, threads, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t f = lo; f < hi; ++f) {
      FaceCorners& face = faces_[f];
      for (int kind = 0; kind < kKinds; ++kind) {
        face.id[kind] = {kNoAttribute, kNoAttribute, kNoAttribute};
        face.wedge[kind] = {kNoWedge, kNoWedge, kNoWedge};
        if (kinds_[kind].present)
          for (int c = 0; c < 3; ++c) face.id[kind][c] = (*input_ids[kind])[input_corner(f, c)];
      }
      if (has_materials_) materials_[f] = input.face_materials[input_face_of(f)];
    }
  });
  if (inputs_read) inputs_read();

  // Scales that make an attribute deviation comparable to a distance. Texture: the
  // surface's model units per texture unit, the square root of the ratio of the surface's
  // area to its area in texture space. Normals: a fixed share of the diagonal.
  if (has_uvs()) {
    double area = 0, uv_area = 0;
    for (std::size_t f = 0; f < faces; ++f) {
      const auto& ids = faces_[f].id[kUv];
      if (ids[0] == kNoAttribute || ids[1] == kNoAttribute || ids[2] == kNoAttribute) continue;
      const Vec3 a = point(corners(f, 0)), b = point(corners(f, 1)), c = point(corners(f, 2));
      area += 0.5 * area_vector(a, b, c).norm();
      uv_area += std::abs(uv_triangle_area(kinds_[kUv].value(ids[0]), kinds_[kUv].value(ids[1]),
                                           kinds_[kUv].value(ids[2])));
    }
    kinds_[kUv].scale = uv_area > 0 && area > 0 ? std::sqrt(area / uv_area) : 0;
  }
  if (has_normals()) {
    Vec3 lo(HUGE_VAL, HUGE_VAL, HUGE_VAL), hi(-HUGE_VAL, -HUGE_VAL, -HUGE_VAL);
    for (std::size_t x = 0; x < n_vertices; ++x) {
      lo.minimize(point(static_cast<uint32_t>(x)));
      hi.maximize(point(static_cast<uint32_t>(x)));
    }
    kinds_[kNormal].scale = n_vertices ? kNormalScaleOfDiagonal * (hi - lo).norm() : 0;
  }
  if (!has_uvs() && !has_normals()) return;
  // Each vertex's corners (face and corner index), in face order, for both kinds.
  std::vector<uint32_t> begin(n_vertices + 1, 0), vertex_corners(3 * faces);
  for (std::size_t f = 0; f < faces; ++f)
    for (int c = 0; c < 3; ++c) ++begin[corners(f, c) + 1];
  for (std::size_t x = 0; x < n_vertices; ++x) begin[x + 1] += begin[x];
  {
    std::vector<uint32_t> fill(begin.begin(), begin.end() - 1);
    for (std::size_t f = 0; f < faces; ++f)
      for (int c = 0; c < 3; ++c)
        vertex_corners[fill[corners(f, c)]++] = static_cast<uint32_t>(3 * f + c);
  }
  for (int kind = 0; kind < kKinds; ++kind)
    if (kinds_[kind].present)
      number_wedges(kind, value_classes(*tables[kind], dims[kind]), begin, vertex_corners);
}

// One wedge per vertex and value.
void CornerAttributes::number_wedges(int kind, const std::vector<uint32_t>& value_class,
                                     const std::vector<uint32_t>& begin,
                                     const std::vector<uint32_t>& corners) {
  const std::size_t n_vertices = begin.size() - 1;
  uint32_t wedges = 0;
  std::vector<std::pair<uint32_t, uint32_t>> seen;  // (class, wedge) around one vertex
  for (std::size_t x = 0; x < n_vertices; ++x) {
    seen.clear();
    for (uint32_t i = begin[x]; i < begin[x + 1]; ++i) {
      const uint32_t f = corners[i] / 3;
      const int c = static_cast<int>(corners[i] % 3);
      const uint32_t id = faces_[f].id[kind][c];
      if (id == kNoAttribute) continue;
      const uint32_t cls = value_class[id];
      auto it = std::find_if(seen.begin(), seen.end(), [&](auto& s) { return s.first == cls; });
      if (it == seen.end()) it = seen.insert(seen.end(), {cls, wedges++});
      faces_[f].wedge[kind][c] = it->second;
    }
  }
}

bool CornerAttributes::is_seam_of_kind(int kind, uint32_t f, uint32_t g, uint32_t a,
                                       uint32_t b) const {
  if (g == CollapseStar::kNoFace || f == CollapseStar::kNoFace) return false;
  if (kind == kKinds) return materials_[f] != materials_[g];
  return wedge_at(kind, f, a) != wedge_at(kind, g, a) || wedge_at(kind, f, b) != wedge_at(kind, g, b);
}

bool CornerAttributes::is_seam(uint32_t f, uint32_t g, uint32_t a, uint32_t b) const {
  for (int kind = 0; kind < kKinds; ++kind)
    if (kinds_[kind].present && is_seam_of_kind(kind, f, g, a, b)) return true;
  return has_materials() && is_seam_of_kind(kKinds, f, g, a, b);
}

bool CornerAttributes::kind_allows(int kind, const CollapseStar& c) const {
  int seams = 0;
  bool along = false;
  for (int i = 0; i < c.n_edges; ++i) {
    const CollapseStar::Edge& e = c.edges[i];
    if (!is_seam_of_kind(kind, e.f, e.g, c.v, e.w)) continue;
    ++seams;
    along |= e.w == c.u;
  }
  if (seams == 0) return true;  // v-u is no seam: u's two sides of it agree too
  if (seams != 2 || !along) return false;
  if (kind == kKinds) return true;
  // v's two sides must differ, so that its corners split between u's two sides; a seam
  // that differs only at u would open a new seam there.
  return wedge_at(kind, c.fl, c.v) != wedge_at(kind, c.fr, c.v) ||
         wedge_at(kind, c.fl, c.u) == wedge_at(kind, c.fr, c.u);
}

std::pair<uint32_t, int> CornerAttributes::target_corner(int kind, const CollapseStar& c,
                                                         uint32_t v_wedge) const {
  const bool has_l = c.fl != CollapseStar::kNoFace, has_r = c.fr != CollapseStar::kNoFace;
  const bool left = has_l && (!has_r || wedge_at(kind, c.fl, c.v) == v_wedge);
  const uint32_t f = left ? c.fl : c.fr;
  return {f, corner_of(f, c.u)};
}

bool CornerAttributes::keeps_uv_winding(const CollapseStar& c) const {
  const Kind& k = kinds_[kUv];
  for (int i = 0; i < c.n_faces; ++i) {
    const uint32_t g = c.faces[i];
    if (g == c.fl || g == c.fr) continue;
    const auto& ids = faces_[g].id[kUv];
    if (ids[0] == kNoAttribute || ids[1] == kNoAttribute || ids[2] == kNoAttribute) continue;
    const int corner = corner_of(g, c.v);
    const auto [tf, tc] = target_corner(kUv, c, faces_[g].wedge[kUv][corner]);
    const uint32_t target = faces_[tf].id[kUv][tc];
    if (target == kNoAttribute) return false;
    const float* value[3] = {k.value(ids[0]), k.value(ids[1]), k.value(ids[2])};
    const int before = sign(uv_triangle_area(value[0], value[1], value[2]));
    value[corner] = k.value(target);
    const int after = sign(uv_triangle_area(value[0], value[1], value[2]));
    if (before != 0 && after != before) return false;
  }
  return true;
}

bool CornerAttributes::collapse_keeps_attributes(const CollapseStar& c) const {
  if (!c.seamless) {  // seamless: no seam edge at v, which every kind_allows()
    for (int kind = 0; kind < kKinds; ++kind)
      if (kinds_[kind].present && !kind_allows(kind, c)) return false;
    if (has_materials() && !kind_allows(kKinds, c)) return false;
  }
  return !has_uvs() || keeps_uv_winding(c);
}

double CornerAttributes::collapse_cost(const CollapseStar& c) const {
  StarFields fields;
  star_fields(c, fields);
  return collapse_cost(c, fields);
}

void CornerAttributes::star_fields(const CollapseStar& c, StarFields& out) const {
  static_assert(kKinds == 2, "StarFields holds two kinds");
  static_assert(StarFields::kMostDims >= 3, "a normal has three components");
  out.count[kUv] = out.count[kNormal] = 0;
  bool priced[kKinds];
  for (int kind = 0; kind < kKinds; ++kind)
    priced[kind] = kinds_[kind].present && kinds_[kind].scale != 0;
  if (!priced[kUv] && !priced[kNormal]) return;
  const float* at_v = points_ + 3 * std::size_t{c.v};
  const Vec3 pv(at_v[0], at_v[1], at_v[2]);
  const int n_faces = std::min(c.n_faces, StarFields::kMostFaces);
  // The corners' values are scattered in the input's tables: all asked for first, so that
  // their cache misses overlap.
  for (int i = 0; i < n_faces; ++i)
    for (int kind = 0; kind < kKinds; ++kind) {
      if (!priced[kind]) continue;
      for (const uint32_t id : faces_[c.faces[i]].id[kind])
        if (id != kNoAttribute) __builtin_prefetch(kinds_[kind].value(id));
    }
  for (int i = 0; i < n_faces; ++i) {
    const uint32_t f = c.faces[i];
    const FaceCorners& face = faces_[f];
    // About v: the positions' differences are exact, the fields' terms small (v's own is 0).
    const int corner = corner_of(f, c.v);
    Vec3 p[3];
    for (int j = 0; j < 3; ++j) {
      if (j == corner) {
        p[j] = Vec3(0, 0, 0);
        continue;
      }
      const float* q = points_ + 3 * std::size_t{corners_(f, j)};
      p[j] = Vec3(q[0], q[1], q[2]) - pv;
    }
    const Vec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
    const double g11 = e1 | e1, g12 = e1 | e2, g22 = e2 | e2;
    const double det = g11 * g22 - g12 * g12;  // |e1 x e2|^2
    const double area = 0.5 * (e1 % e2).norm();
    // A degenerate face has no gradient, and no area to weigh it: it counts for nothing.
    if (!(det > 0) || !(area > 0)) continue;
    // Hoppe 1999, §4: the attribute's gradient g lies in the face's plane with g . e1 = a1 -
    // a0 and g . e2 = a2 - a0, that is g = (a1 - a0) w1 + (a2 - a0) w2 with w1, w2 the dual
    // basis of e1, e2 in that plane (the gradients of the barycentric coordinates), made once
    // for every kind and component; then d = a0 - g . p0, so that a(p) = g . p + d on the
    // face. (Against a division per component, and v's own position read: the 950K-face
    // textured mesh's collapse sequence without the measure, one thread, medians of 6
    // alternating runs of 5, 3.35 -> 3.24 s. With the terms about v's corner instead, whose
    // value is the offset there, no g . p0: about 4% faster again, but the rounding moved the
    // textured sample at 2% of its faces from Hausdorff 0.88 to 1.01 times meshopt_simplify's,
    // attr_quality.md.)
    const double inverse = 1.0 / det;
    const Vec3 w1 = (g22 * inverse) * e1 - (g12 * inverse) * e2;
    const Vec3 w2 = (g11 * inverse) * e2 - (g12 * inverse) * e1;
    for (int kind = 0; kind < kKinds; ++kind) {
      if (!priced[kind]) continue;
      const auto& ids = face.id[kind];
      if (ids[0] == kNoAttribute || ids[1] == kNoAttribute || ids[2] == kNoAttribute) continue;
      const Kind& k = kinds_[kind];
      StarFields::Field& field = out.fields[kind][out.count[kind]++];
      field.area = area;
      field.wedge = face.wedge[kind][corner];
      const float* value[3] = {k.value(ids[0]), k.value(ids[1]), k.value(ids[2])};
      for (int j = 0; j < k.dims; ++j) {
        const double d1 = double(value[1][j]) - value[0][j];
        const double d2 = double(value[2][j]) - value[0][j];
        const Vec3 g = d1 * w1 + d2 * w2;
        field.gradient[j][0] = g[0], field.gradient[j][1] = g[1], field.gradient[j][2] = g[2];
        field.offset[j] = value[0][j] - (g | p[0]);
      }
    }
  }
}

double CornerAttributes::collapse_cost(const CollapseStar& c, const StarFields& fields) const {
  double cost = 0;
  const bool has_l = c.fl != CollapseStar::kNoFace, has_r = c.fr != CollapseStar::kNoFace;
  const Vec3 x = c.pu - c.pv;  // u about v, where the fields are
  for (int kind = 0; kind < kKinds; ++kind) {
    const Kind& k = kinds_[kind];
    if (fields.count[kind] == 0) continue;
    // target_corner() for each of v's corners: u's corner in fl when v's wedge there is
    // that corner's, else u's corner in fr.
    const uint32_t left_wedge = has_l && has_r ? wedge_at(kind, c.fl, c.v) : kNoWedge;
    const uint32_t left = has_l ? faces_[c.fl].id[kind][corner_of(c.fl, c.u)] : kNoAttribute;
    const uint32_t right = has_r ? faces_[c.fr].id[kind][corner_of(c.fr, c.u)] : kNoAttribute;
    const float* left_value = left != kNoAttribute ? k.value(left) : nullptr;
    const float* right_value = right != kNoAttribute ? k.value(right) : nullptr;
    double error = 0, weight = 0;
    for (int i = 0; i < fields.count[kind]; ++i) {
      const StarFields::Field& field = fields.fields[kind][i];
      const float* s = has_l && (!has_r || left_wedge == field.wedge) ? left_value : right_value;
      if (!s) continue;
      // The face's value at u against the one its corner at v takes there.
      double e = 0;
      for (int j = 0; j < k.dims; ++j) {
        const double r = field.gradient[j][0] * x[0] + field.gradient[j][1] * x[1] +
                         field.gradient[j][2] * x[2] + field.offset[j] - s[j];
        e += r * r;
      }
      error += field.area * e;
      weight += field.area;
    }
    if (weight > 0) cost += k.cost_weight * k.scale * k.scale * error / weight;
  }
  return cost;
}

void CornerAttributes::collapse(const CollapseStar& c, CollapseAttributes& record) {
  // The removed faces as the split re-creates them.
  auto record_face = [&](uint32_t f, uint32_t a, uint32_t b, uint32_t d) {
    uint32_t uvs[3], normals[3];
    corner_ids(f, {a, b, d}, uvs, normals);
    for (int i = 0; i < 3; ++i) {
      if (has_uvs()) record.new_face_uvs.push_back(uvs[i]);
      if (has_normals()) record.new_face_normals.push_back(normals[i]);
    }
  };
  if (c.fl != CollapseStar::kNoFace) record_face(c.fl, c.v, c.u, c.vl);
  if (c.fr != CollapseStar::kNoFace) record_face(c.fr, c.u, c.v, c.vr);

  // The moved corners take u's ids and wedges. Targets are read from fl and fr, which do
  // not move.
  for (int i = 0; i < c.n_faces; ++i) {
    const uint32_t g = c.faces[i];
    if (g == c.fl || g == c.fr) continue;
    const int corner = corner_of(g, c.v);
    for (int kind = 0; kind < kKinds; ++kind) {
      Kind& k = kinds_[kind];
      if (!k.present) continue;
      RecordList& moved = kind == kUv ? record.moved_uvs : record.moved_normals;
      uint32_t& id = faces_[g].id[kind][corner];
      moved.push_back(id);
      const auto [tf, tc] = target_corner(kind, c, faces_[g].wedge[kind][corner]);
      id = faces_[tf].id[kind][tc];
      faces_[g].wedge[kind][corner] = faces_[tf].wedge[kind][tc];
    }
  }
}

void CornerAttributes::corner_ids(uint32_t f, const uint32_t (&at)[3], uint32_t (&uvs)[3],
                                  uint32_t (&normals)[3]) const {
  // After finish(), face f's record is where its id is among the live ones.
  const std::size_t at_f =
      finished_ ? static_cast<std::size_t>(
                      std::lower_bound(live_ids_.begin(), live_ids_.end(), f) - live_ids_.begin())
                : f;
  const FaceCorners& face = faces_[at_f];
  for (int i = 0; i < 3; ++i) {
    const int c = finished_
                      ? corner_among(live_vertices_[3 * at_f], live_vertices_[3 * at_f + 1], at[i])
                      : corner_of(f, at[i]);
    uvs[i] = has_uvs() ? face.id[kUv][c] : kNoAttribute;
    normals[i] = has_normals() ? face.id[kNormal][c] : kNoAttribute;
  }
}

void CornerAttributes::compact(const FaceRenumbering& faces, const uint32_t* given_face) {
  if (has_materials_) {
    if (given_materials_.empty())
      detail::assign_preferring_huge_pages(given_materials_, first_faces_, kNoAttribute);
    for (std::size_t f = 0; f < materials_.size(); ++f)
      if (faces.new_id[f] == FaceRenumbering::kGone) given_materials_[given_face[f]] = materials_[f];
    faces.compact(materials_, 1);
  }
  faces.compact(faces_, 1);
}

void CornerAttributes::finish(const std::vector<uint32_t>& face_of,
                              const std::vector<uint32_t>& vertex_of,
                              const std::vector<uint8_t>& face_dead) {
  if (has_materials_) {
    if (given_materials_.empty()) given_materials_.resize(first_faces_);
    for (std::size_t f = 0; f < materials_.size(); ++f) given_materials_[face_of[f]] = materials_[f];
    materials_.swap(given_materials_);
    std::vector<uint32_t>().swap(given_materials_);
  }
  std::vector<std::pair<uint32_t, uint32_t>> live;  // (caller's id, own id)
  for (std::size_t f = 0; f < faces_.size(); ++f)
    if (!face_dead[f]) live.push_back({face_of[f], static_cast<uint32_t>(f)});
  std::sort(live.begin(), live.end());
  std::vector<FaceCorners> kept(live.size());
  live_ids_.resize(live.size());
  live_vertices_.resize(3 * live.size());
  for (std::size_t i = 0; i < live.size(); ++i) {
    live_ids_[i] = live[i].first;
    kept[i] = faces_[live[i].second];
    for (int k = 0; k < 3; ++k) live_vertices_[3 * i + k] = vertex_of[corners_(live[i].second, k)];
  }
  faces_.swap(kept);
  std::vector<FaceCorners>().swap(kept);
  corners_ = {};
  finished_ = true;
}

}  // namespace pm
