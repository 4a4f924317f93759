// Format 1.x's section payloads (pm-format-1.md §5), each section's encoder beside its
// decoder: the base mesh (BASE), the vertex splits as struct of arrays (SPLT: u, vl, vr,
// the moved faces, the new position and the error of each split of Hoppe 1996, "Progressive
// meshes", §3), welds, carried faces and loose vertices (WELD, CARY, LOOS), and since 1.1 the
// attributes (COLR, UVS0, NRML with corner codes in the corner order of §5.10, MATL).
#include "v1/sections.h"

#include <cstdint>
#include <string>
#include <vector>

#include "byte_io.h"
#include "corner_codes.h"
#include "pm/pm_codec.h"
#include "pm_layout.h"

namespace pm::detail::v1 {
namespace {

// ---------------------------------------------------------------------------------------
// Section payloads (§5). Encoders and decoders in matching pairs. The decoders write into
// arrays read_pm has sized from the (checked) header counts, so nothing they do allocates
// more than the memory bound of §7.1.

void put_floats(ByteWriter& out, const std::vector<float>& values, std::size_t first,
                std::size_t count) {
  for (std::size_t i = first; i < first + count; ++i) out.put_f32(values[i]);
}

// Appends `count` floats. Positions come in three sections, into the capacity read_pm
// reserved; the other arrays are reserved here, exactly.
bool read_floats(ByteReader& in, std::size_t count, std::vector<float>& values) {
  if (values.capacity() - values.size() < count) values.reserve(values.size() + count);
  for (std::size_t i = 0; i < count; ++i) {
    float value;
    if (!in.read_f32(value)) return false;
    values.push_back(value);
  }
  return true;
}

bool read_varints(ByteReader& in, std::size_t count, std::vector<uint32_t>& values) {
  values.resize(count);
  for (uint32_t& value : values) {
    if (!in.read_varint(value)) return false;
  }
  return true;
}

// vl, vr: value + 1, with 0 for kNoVertex.
uint32_t encode_optional_vertex(uint32_t vertex) {
  return vertex == kNoVertex ? 0 : vertex + 1;
}
uint32_t decode_optional_vertex(uint32_t code) {
  return code == 0 ? kNoVertex : code - 1;
}

// Face indices below `limit`, checked as they are read (the same rule and message as
// validate()): the attribute sections walk the faces by vertex id (§5.10), so ids must be
// in range before then.
bool check_face_indices(ByteReader& in, const std::vector<uint32_t>& indices, uint32_t limit,
                        const char* what, const char* of_what) {
  for (std::size_t i = 0; i < indices.size(); ++i) {
    if (indices[i] >= limit) {
      return in.fail(ErrorCode::kCorruptStream,
                     in.where() + ": " + what + " " + std::to_string(i / 3) + " uses vertex " +
                         std::to_string(indices[i]) + " of " + std::to_string(limit) + of_what);
    }
  }
  return true;
}

std::string encode_base(const ProgressiveMesh& pm) {
  std::string raw;
  ByteWriter out(raw);
  put_floats(out, pm.positions, 0, 3 * std::size_t{pm.base_vertex_count});
  for (uint32_t index : pm.base_faces) out.put_varint(index);
  return raw;
}

bool decode_base(ByteReader& in, const Header& h, ProgressiveMesh& pm) {
  return read_floats(in, 3 * std::size_t{h.base_vertex_count}, pm.positions) &&
         read_varints(in, 3 * std::size_t{h.base_face_count}, pm.base_faces) &&
         check_face_indices(in, pm.base_faces, h.base_vertex_count, "base face", "");
}

// Struct of arrays: like fields side by side compress better than interleaved records.
std::string encode_splits(const ProgressiveMesh& pm) {
  std::string raw;
  ByteWriter out(raw);
  const std::size_t base = pm.base_vertex_count;
  // u < v always, and u is usually a recent vertex: v - 1 - u is small.
  for (std::size_t i = 0; i < pm.splits.size(); ++i) {
    out.put_varint(static_cast<uint32_t>(base + i - 1 - pm.splits[i].u));
  }
  for (const VertexSplit& split : pm.splits) out.put_varint(encode_optional_vertex(split.vl));
  for (const VertexSplit& split : pm.splits) out.put_varint(encode_optional_vertex(split.vr));
  for (const VertexSplit& split : pm.splits) out.put_varint(split.moved_count);
  for (uint32_t face : pm.moved_faces) out.put_varint(face);
  put_floats(out, pm.positions, 3 * base, 3 * pm.splits.size());
  for (const VertexSplit& split : pm.splits) out.put_f32(split.error);
  return raw;
}

// vl or vr of split i, which creates vertex v: none, or below v (validate()'s rule).
bool read_side_vertex(ByteReader& in, std::size_t i, uint64_t v, const char* name,
                      uint32_t& vertex) {
  uint32_t code;
  if (!in.read_varint(code)) return false;
  vertex = decode_optional_vertex(code);
  if (vertex != kNoVertex && vertex >= v) {
    return in.fail(ErrorCode::kCorruptStream, in.where() + ": split " + std::to_string(i) +
                                                  " has " + name + " " + std::to_string(vertex) +
                                                  " of " + std::to_string(v) + " vertices");
  }
  return true;
}

bool decode_splits(ByteReader& in, const Header& h, ProgressiveMesh& pm) {
  pm.splits.resize(h.split_count);
  for (std::size_t i = 0; i < pm.splits.size(); ++i) {
    const uint64_t v = uint64_t{h.base_vertex_count} + i;
    uint32_t offset;
    if (!in.read_varint(offset)) return false;
    if (offset >= v) {
      return in.fail(ErrorCode::kCorruptStream, in.where() + ": split " + std::to_string(i) +
                                                    " has u offset " + std::to_string(offset) +
                                                    " but creates vertex " + std::to_string(v));
    }
    pm.splits[i].u = static_cast<uint32_t>(v - 1 - offset);
  }
  uint64_t split_faces = 0;
  for (std::size_t i = 0; i < pm.splits.size(); ++i) {
    if (!read_side_vertex(in, i, uint64_t{h.base_vertex_count} + i, "vl", pm.splits[i].vl)) {
      return false;
    }
    split_faces += pm.splits[i].vl != kNoVertex;
  }
  for (std::size_t i = 0; i < pm.splits.size(); ++i) {
    if (!read_side_vertex(in, i, uint64_t{h.base_vertex_count} + i, "vr", pm.splits[i].vr)) {
      return false;
    }
    split_faces += pm.splits[i].vr != kNoVertex;
  }
  if (split_faces != h.split_face_count) {
    return in.fail(ErrorCode::kCorruptStream,
                   in.where() + ": the splits add " + std::to_string(split_faces) +
                       " faces, the header says " + std::to_string(h.split_face_count));
  }
  uint64_t moved_total = 0;
  for (VertexSplit& split : pm.splits) {
    if (!in.read_varint(split.moved_count)) return false;
    // Bounded by the header's moved face count (checked below), so never wraps.
    split.moved_begin = static_cast<uint32_t>(std::min<uint64_t>(moved_total, UINT32_MAX));
    moved_total += split.moved_count;
  }
  // Checked before the ids are read, so the allocation below is the header's count.
  if (moved_total != h.moved_face_count) {
    return in.fail(ErrorCode::kCorruptStream,
                   in.where() + ": the splits move " + std::to_string(moved_total) +
                       " faces, the header says " + std::to_string(h.moved_face_count));
  }
  if (!read_varints(in, h.moved_face_count, pm.moved_faces)) return false;
  if (!read_floats(in, 3 * std::size_t{h.split_count}, pm.positions)) return false;
  for (VertexSplit& split : pm.splits) {
    if (!in.read_f32(split.error)) return false;
  }
  return true;
}

std::string encode_welds(const ProgressiveMesh& pm) {
  std::string raw;
  ByteWriter out(raw);
  for (const Weld& weld : pm.welds) {
    out.put_varint(weld.copy);
    out.put_varint(weld.canonical);
  }
  return raw;
}

bool decode_welds(ByteReader& in, const Header& h, ProgressiveMesh& pm) {
  pm.welds.resize(h.weld_count);
  for (Weld& weld : pm.welds) {
    if (!in.read_varint(weld.copy) || !in.read_varint(weld.canonical)) return false;
  }
  return true;
}

std::string encode_carried(const ProgressiveMesh& pm) {
  std::string raw;
  ByteWriter out(raw);
  for (uint32_t index : pm.carried_faces) out.put_varint(index);
  return raw;
}

bool decode_carried(ByteReader& in, const Header& h, ProgressiveMesh& pm) {
  return read_varints(in, 3 * std::size_t{h.carried_face_count}, pm.carried_faces) &&
         check_face_indices(in, pm.carried_faces, h.base_vertex_count, "carried face",
                            " base vertices");
}

std::string encode_loose(const ProgressiveMesh& pm) {
  std::string raw;
  ByteWriter out(raw);
  put_floats(out, pm.positions, 3 * (pm.base_vertex_count + pm.splits.size()),
             3 * std::size_t{pm.loose_vertex_count});
  return raw;
}

bool decode_loose(ByteReader& in, const Header& h, ProgressiveMesh& pm) {
  return read_floats(in, 3 * std::size_t{h.loose_vertex_count}, pm.positions);
}

// --- Attributes (1.1) ------------------------------------------------------------------

std::string encode_colors(const ProgressiveMesh& pm) {
  std::string raw;
  ByteWriter out(raw);
  put_floats(out, pm.colors, 0, pm.colors.size());
  return raw;
}

bool decode_colors(ByteReader& in, const Header& h, ProgressiveMesh& pm) {
  return read_floats(in, std::size_t{h.color_components} * all_vertices(h), pm.colors);
}

// The corner order of §5.10: every attribute corner once, as extract_level() meets them.
// Calls visit(vertex, slot), where slot < 3 * face count is an index into the per-face
// array (3 * face + corner, faces in creation order) and 3 * face count + k is moved corner
// k. Stops at the first visit that returns false. The vertex ids come from decoded (or
// valid) geometry: base and carried face indices < B, split vertices < B + S.
template <typename Visit>
bool for_each_corner(const ProgressiveMesh& pm, std::size_t face_count, Visit&& visit) {
  std::size_t slot = 0;
  for (uint32_t vertex : pm.base_faces) {
    if (!visit(vertex, slot++)) return false;
  }
  const std::size_t first_moved = 3 * face_count;
  for (std::size_t i = 0; i < pm.splits.size(); ++i) {
    const VertexSplit& split = pm.splits[i];
    const uint32_t v = pm.base_vertex_count + static_cast<uint32_t>(i);
    for (uint32_t k = split.moved_begin; k < split.moved_begin + split.moved_count; ++k) {
      if (!visit(v, first_moved + k)) return false;
    }
    if (split.vl != kNoVertex) {
      for (uint32_t vertex : {v, split.u, split.vl}) {
        if (!visit(vertex, slot++)) return false;
      }
    }
    if (split.vr != kNoVertex) {
      for (uint32_t vertex : {split.u, v, split.vr}) {
        if (!visit(vertex, slot++)) return false;
      }
    }
  }
  for (uint32_t vertex : pm.carried_faces) {
    if (!visit(vertex, slot++)) return false;
  }
  return true;
}

void put_corner_ids(ByteWriter& out, const ProgressiveMesh& pm,
                    const std::vector<uint32_t>& face_ids, const std::vector<uint32_t>& moved_ids) {
  if (face_ids.empty()) return;
  CornerPredictor predictor(pm.base_vertex_count + pm.splits.size());
  for_each_corner(pm, face_ids.size() / 3, [&](uint32_t vertex, std::size_t slot) {
    const uint32_t id = slot < face_ids.size() ? face_ids[slot] : moved_ids[slot - face_ids.size()];
    out.put_varint(predictor.encode(vertex, id));
    return true;
  });
}

// Reads the corner codes into face_ids (3 per face) and moved_ids (1 per moved face), each
// id below `count`; every code must be the one the writer would have chosen.
bool read_corner_ids(ByteReader& in, const Header& h, const ProgressiveMesh& pm, uint32_t count,
                     std::vector<uint32_t>& face_ids, std::vector<uint32_t>& moved_ids) {
  const std::size_t face_slots = 3 * static_cast<std::size_t>(all_faces(h));
  face_ids.resize(face_slots);
  moved_ids.resize(h.moved_face_count);
  CornerPredictor predictor(std::size_t{h.base_vertex_count} + h.split_count);
  std::size_t corner = 0;  // in corner order, for messages
  return for_each_corner(pm, face_slots / 3, [&](uint32_t vertex, std::size_t slot) {
    uint32_t code;
    if (!in.read_varint(code)) return false;
    uint32_t id;
    std::string problem;
    if (!predictor.decode(code, vertex, count, id, problem)) {
      return in.fail(ErrorCode::kCorruptStream,
                     in.where() + ": corner " + std::to_string(corner) + " " + problem);
    }
    (slot < face_slots ? face_ids[slot] : moved_ids[slot - face_slots]) = id;
    ++corner;
    return true;
  });
}

std::string encode_uvs(const ProgressiveMesh& pm) {
  std::string raw;
  ByteWriter out(raw);
  put_floats(out, pm.uvs, 0, pm.uvs.size());
  put_corner_ids(out, pm, pm.face_uvs, pm.moved_uvs);
  return raw;
}

bool decode_uvs(ByteReader& in, const Header& h, ProgressiveMesh& pm) {
  if (!read_floats(in, 2 * std::size_t{h.uv_count}, pm.uvs)) return false;
  return (h.attributes & kAttributeUvIds) == 0 ||
         read_corner_ids(in, h, pm, h.uv_count, pm.face_uvs, pm.moved_uvs);
}

std::string encode_normals(const ProgressiveMesh& pm) {
  std::string raw;
  ByteWriter out(raw);
  put_floats(out, pm.normals, 0, pm.normals.size());
  put_corner_ids(out, pm, pm.face_normals, pm.moved_normals);
  return raw;
}

bool decode_normals(ByteReader& in, const Header& h, ProgressiveMesh& pm) {
  if (!read_floats(in, 3 * std::size_t{h.normal_count}, pm.normals)) return false;
  return (h.attributes & kAttributeNormalIds) == 0 ||
         read_corner_ids(in, h, pm, h.normal_count, pm.face_normals, pm.moved_normals);
}

std::string encode_materials(const ProgressiveMesh& pm) {
  std::string raw;
  ByteWriter out(raw);
  for (const std::string& library : pm.material_libraries) put_string(out, library);
  for (const std::string& name : pm.material_names) put_string(out, name);
  for (uint32_t id : pm.face_materials) out.put_varint(id == kNoAttribute ? 0 : id + 1);
  return raw;
}

bool decode_materials(ByteReader& in, const Header& h, ProgressiveMesh& pm) {
  uint64_t budget = h.material_string_bytes;
  if (!read_strings(in, h.material_library_count, "material library", budget,
                    pm.material_libraries) ||
      !read_strings(in, h.material_count, "material name", budget, pm.material_names)) {
    return false;
  }
  if (budget != 0) {
    return in.fail(ErrorCode::kCorruptStream, in.where() + ": the strings hold " +
                                                  std::to_string(h.material_string_bytes - budget) +
                                                  " bytes, the header says " +
                                                  std::to_string(h.material_string_bytes));
  }
  if ((h.attributes & kAttributeMaterialIds) == 0) return true;
  if (!read_varints(in, static_cast<std::size_t>(all_faces(h)), pm.face_materials)) return false;
  for (std::size_t f = 0; f < pm.face_materials.size(); ++f) {
    uint32_t& id = pm.face_materials[f];
    if (id > h.material_count) {
      return in.fail(ErrorCode::kCorruptStream, in.where() + ": face " + std::to_string(f) +
                                                    " has material " + std::to_string(id - 1) +
                                                    " of " + std::to_string(h.material_count));
    }
    id = id == 0 ? kNoAttribute : id - 1;
  }
  return true;
}

}  // namespace

const std::array<SectionEncoder, kKnownSectionCount> kEncoders = {
    encode_base,   encode_splits, encode_welds,   encode_carried,  encode_loose,
    encode_colors, encode_uvs,    encode_normals, encode_materials};
const std::array<SectionDecoder, kKnownSectionCount> kDecoders = {
    decode_base,   decode_splits, decode_welds,   decode_carried,  decode_loose,
    decode_colors, decode_uvs,    decode_normals, decode_materials};

}  // namespace pm::detail::v1
