// The sections of format 2.x besides the header, the tables and the chunks, each written
// and read side by side (pm-format.md §5.2, §5.7 to §5.9): the base mesh with its positions,
// materials and corners' ids (BASE: M0 of Hoppe 1996, "Progressive meshes", §3, which a
// reader shows before any split arrives), the welds (WELD), the carried faces (CARY), the
// loose vertices (LOOS) and the input's order (ORDR).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "byte_io.h"
#include "pm/pm_codec.h"
#include "v2/format.h"
#include "v2/positions.h"
#include "v2/reader.h"
#include "v2/writer.h"

namespace pm::detail::v2 {

void Writer::put_positions(ByteWriter& out, uint32_t first, uint32_t count) {
  for (std::size_t i = 3 * std::size_t{first}; i < 3 * (std::size_t{first} + count); ++i) {
    if (position_grid.bits != 0 || significant.digits != 0) {
      out.put_varint(positions.units[i]);
    } else {
      out.put_f32(pm.positions[i]);
    }
  }
  for (std::size_t i = colors.components * first; i < colors.components * (first + count); ++i) {
    out.put_f32(pm.colors[i]);
  }
}

std::string Writer::base() {
  std::string raw;
  ByteWriter out(raw);
  if (position_grid.bits != 0) put_grid(out, position_grid);
  if (significant.digits != 0) put_significant(out, significant);  // 2.3 (§5.3)
  put_positions(out, 0, pm.base_vertex_count);
  for (uint32_t vertex : pm.base_faces) out.put_varint(vertex);
  if (pm.has_materials()) {
    for (std::size_t f = 0; f < pm.base_face_count(); ++f) put_optional_id(out, pm.face_materials[f]);
  }
  std::string uv_raw, normal_raw;
  ByteWriter uv_out(uv_raw), normal_out(normal_raw);
  for (std::size_t slot = 0; slot < pm.base_faces.size(); ++slot) {
    put_corner(uv_out, normal_out, pm.base_faces[slot], slot);
  }
  return raw + uv_raw + normal_raw;
}

std::string Writer::carried() {
  std::string raw, uv_raw, normal_raw;
  ByteWriter out(raw), uv_out(uv_raw), normal_out(normal_raw);
  for (uint32_t vertex : pm.carried_faces) out.put_varint(vertex);
  const std::size_t first = pm.total_face_count() - pm.carried_faces.size() / 3;
  if (pm.has_materials()) {
    for (std::size_t f = first; f < pm.total_face_count(); ++f) put_optional_id(out, pm.face_materials[f]);
  }
  for (std::size_t k = 0; k < pm.carried_faces.size(); ++k) {
    put_corner(uv_out, normal_out, pm.carried_faces[k], 3 * first + k);
  }
  return raw + uv_raw + normal_raw;
}

std::string Writer::welds() {
  std::string raw;
  ByteWriter out(raw);
  for (const Weld& weld : pm.welds) {
    out.put_varint(weld.copy);
    out.put_varint(weld.canonical);
  }
  return raw;
}

// The input's order (§5.9): the vertex id of each input vertex, the face id of each input
// triangle.
std::string Writer::order() {
  std::string raw;
  ByteWriter out(raw);
  for (uint32_t v : pm.input_vertices) out.put_varint(v);
  for (uint32_t f : pm.input_faces) out.put_varint(f);
  return raw;
}

std::string Writer::loose() {
  std::string raw;
  ByteWriter out(raw);
  put_positions(out, pm.base_vertex_count + static_cast<uint32_t>(pm.splits.size()),
                pm.loose_vertex_count);
  return raw;
}

}  // namespace pm::detail::v2

namespace pm {

// Positions (f32 or grid indices) and colours of `count` vertices, appended.
bool PmStreamReader::State::read_vertex_values(ByteReader& in, uint32_t count) {
  const uint32_t top = h.position_bits != 0 ? (uint32_t{1} << h.position_bits) - 1 : 0xFFFFFFFFu;
  for (std::size_t i = 0; i < 3 * std::size_t{count}; ++i) {
    if (h.position_bits != 0 || positions.significant != nullptr) {  // grid indices, 2.3's numbers
      uint32_t q;
      float x = 0;
      if (!in.read_varint(q)) return false;
      if (q > top || !positions.to_float(q, i % 3, x)) {
        return in.fail(ErrorCode::kCorruptStream, in.where() + ": a position beyond the grid or no decimal's");
      }
      positions.units.push_back(q);
      pm.positions.push_back(x);
    } else {
      float x;
      if (!in.read_f32(x)) return false;
      positions.units.push_back(ordered_from_float(x));
      pm.positions.push_back(x);
    }
  }
  for (std::size_t i = 0; i < std::size_t{h.color_components} * count; ++i) {
    float x;
    if (!in.read_f32(x)) return false;
    colors.units.push_back(ordered_from_float(x));
    pm.colors.push_back(x);
  }
  return true;
}

bool PmStreamReader::State::decode_base(ByteReader& in) {
  if (h.position_bits != 0 &&
      !read_grid(in, h.position_bits, 3, position_grid, (h.options & kOptionDecimalPositions) != 0)) {
    return false;
  }
  if ((h.options & kOptionSignificantPositions) != 0) {  // 2.3 (§5.3)
    if (!read_significant(in, significant)) return false;
    positions.significant = &significant;
    positions.mean_of_values = h.minor >= 4;  // 2.4 (§5.3)
  }
  if (!read_vertex_values(in, h.base_vertex_count)) return false;
  for (uint32_t f = 0; f < h.base_face_count; ++f) {
    uint32_t v[3];
    for (uint32_t& vertex : v) {
      if (!in.read_varint(vertex)) return false;
      if (vertex >= h.base_vertex_count) {
        return in.fail(ErrorCode::kCorruptStream, in.where() + ": base face " + std::to_string(f) +
                                                      " uses vertex " + std::to_string(vertex) +
                                                      " of " + std::to_string(h.base_vertex_count));
      }
    }
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) {
      return in.fail(ErrorCode::kCorruptStream, in.where() + ": base face " + std::to_string(f) +
                                                    " repeats a vertex");
    }
    pm.base_faces.insert(pm.base_faces.end(), v, v + 3);
    fans.add_face(v[0], v[1], v[2]);
  }
  if (h.material_ids()) {
    for (uint32_t f = 0; f < h.base_face_count; ++f) {
      uint32_t id;
      if (!read_optional_id(in, h.material_count, "material", id)) return false;
      pm.face_materials.push_back(id);
    }
  }
  if (!read_corners(in, pm.base_faces, {&pm.face_uvs, &pm.face_normals})) return false;
  decoded_faces = h.base_face_count + uint64_t{h.carried_face_count};
  return true;
}

// The corner codes of faces whose vertices are `vertices` (3 per face): all texture
// coordinates' ids, then all normals' (§5.7), appended to the arrays the stream has (`ids`,
// per kind).
bool PmStreamReader::State::read_corners(ByteReader& in, const std::vector<uint32_t>& vertices,
                                         const std::array<std::vector<uint32_t>*, 2>& ids) {
  for (int kind = 0; kind < 2; ++kind) {
    if (codes(kind) == nullptr) continue;
    for (uint32_t vertex : vertices) {
      uint32_t id;
      if (!read_corner(in, kind, vertex, id)) return false;
      ids[kind]->push_back(id);
    }
  }
  return true;
}

bool PmStreamReader::State::decode_welds(ByteReader& in) {
  for (uint32_t k = 0; k < h.weld_count; ++k) {
    Weld weld;
    if (!in.read_varint(weld.copy) || !in.read_varint(weld.canonical)) return false;
    pm.welds.push_back(weld);  // their rules are validate()'s (§6), at finish()
  }
  return true;
}

bool PmStreamReader::State::decode_carried(ByteReader& in) {
  for (uint32_t k = 0; k < 3 * h.carried_face_count; ++k) {
    uint32_t vertex;
    if (!in.read_varint(vertex)) return false;
    if (vertex >= h.base_vertex_count) {
      return in.fail(ErrorCode::kCorruptStream, in.where() + ": carried face " + std::to_string(k / 3) +
                                                    " uses vertex " + std::to_string(vertex) + " of " +
                                                    std::to_string(h.base_vertex_count));
    }
    pm.carried_faces.push_back(vertex);
  }
  if (h.material_ids()) {
    for (uint32_t f = 0; f < h.carried_face_count; ++f) {
      uint32_t id;
      if (!read_optional_id(in, h.material_count, "material", id)) return false;
      carried_materials.push_back(id);
    }
  }
  return read_corners(in, pm.carried_faces, {&carried_uvs, &carried_normals});
}

bool PmStreamReader::State::decode_loose(ByteReader& in) {
  if (!read_vertex_values(in, h.loose_vertex_count)) return false;
  pm.loose_vertex_count = h.loose_vertex_count;
  return true;
}

// Ranges here; that each is a bijection is validate()'s (at finish()).
bool PmStreamReader::State::decode_order(ByteReader& in) {
  const uint64_t vertices = h.vertices(), faces = h.faces();
  pm.input_vertices.reserve(vertices - h.weld_count);
  pm.input_faces.reserve(faces);
  for (uint64_t i = 0; i < vertices - h.weld_count + faces; ++i) {
    uint32_t id;
    if (!in.read_varint(id)) return false;
    const bool vertex = i < vertices - h.weld_count;
    const uint64_t limit = vertex ? vertices : 3 * faces;  // faces: 3 * face id + rotation
    if (id >= limit) {
      return in.fail(ErrorCode::kCorruptStream, in.where() + ": input " + (vertex ? "vertex" : "face") +
                                                    " code " + std::to_string(id) + " of " +
                                                    std::to_string(limit));
    }
    (vertex ? pm.input_vertices : pm.input_faces).push_back(id);
  }
  return true;
}

}  // namespace pm
