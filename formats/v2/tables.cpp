// TABL and the wedge coders' start (pm-format.md §5.4, §5.11, §7), written and read side by
// side: the texture-coordinate and normal tables (f32, on a grid, or 2.3's significant
// decimals), since 2.2 listing only the entries that the base and carried faces use (and
// those no corner uses), the others being introduced by the splits' corners (wedge_codes.h);
// the material strings; and, for a prefix of a 2.2 stream, its tables without the entries
// that have not arrived.
#include <cstdint>
#include <string>
#include <vector>

#include "byte_io.h"
#include "pm/pm_codec.h"
#include "pm_layout.h"
#include "significant_decimals.h"
#include "stream_order/attribute_renumbering.h"
#include "v2/format.h"
#include "v2/positions.h"
#include "v2/reader.h"
#include "v2/writer.h"
#include "wedge_codes.h"

namespace pm::detail::v2 {
namespace {

// One table value, component c: f32, or its grid index (§5.4).
void put_table_value(ByteWriter& out, const Grid* grid, float x, std::size_t c) {
  if (grid == nullptr) {
    out.put_f32(x);
  } else {
    out.put_varint(quantize(*grid, x, c));
  }
}

// A value table (UVs or normals), f32 or on a grid (§5.4).
void put_table(ByteWriter& out, const std::vector<float>& values, std::size_t components,
               const Grid* grid) {
  if (grid != nullptr) put_grid(out, *grid);
  for (std::size_t i = 0; i < values.size(); ++i) put_table_value(out, grid, values[i], i % components);
}

}  // namespace

void Writer::plan_tables() {
  const std::size_t base_corners = pm.base_faces.size();
  const std::size_t carried_first = 3 * (pm.total_face_count() - pm.carried_faces.size() / 3);
  for (int kind = 0; kind < 2; ++kind) {
    const std::size_t count = table_count(kind);
    std::vector<uint8_t> early(count, 0), used(count, 0);
    if (has_ids(kind)) {
      const std::vector<uint32_t>& ids = mesh_face_ids(pm, kind);
      const std::vector<uint32_t>& moved = mesh_moved_ids(pm, kind);
      for (std::size_t slot = 0; slot < ids.size(); ++slot) {
        if (ids[slot] == kNoAttribute) continue;
        used[ids[slot]] = 1;
        if (slot < base_corners || slot >= carried_first) early[ids[slot]] = 1;
      }
      for (uint32_t id : moved) {
        if (id != kNoAttribute) used[id] = 1;
      }
    }
    listed[kind].assign(count, 0);
    for (std::size_t id = 0; id < count; ++id) listed[kind][id] = early[id] != 0 || used[id] == 0;
  }
}

// 2.2 (§5.4): the listed entries, each with the gap from the previous one's id.
void Writer::put_listed(ByteWriter& out, int kind) {
  const std::size_t components = kind_components(kind);
  if (listed[kind].empty()) return;  // no table: no grid, no count
  if (grid(kind).bits != 0) put_grid(out, grid(kind));
  const SignificantDecimals& significant = table_significant[kind];
  if (significant.digits != 0) put_significant(out, significant);  // 2.3 (§5.4)
  uint32_t listed_count = 0;
  for (uint8_t x : listed[kind]) listed_count += x;
  out.put_varint(listed_count);
  int64_t previous = -1;
  for (std::size_t id = 0; id < listed[kind].size(); ++id) {
    if (listed[kind][id] == 0) continue;
    out.put_varint(static_cast<uint32_t>(int64_t(id) - previous - 1));
    previous = int64_t(id);
    // The values as units_of gives them to the wedge coder: grid indices and (2.3)
    // numbers of significant decimals are varints, float bits are f32.
    uint32_t units[3];
    units_of(kind, static_cast<uint32_t>(id), units);
    for (std::size_t c = 0; c < components; ++c) {
      if (grid(kind).bits != 0 || significant.digits != 0) {
        out.put_varint(units[c]);
      } else {
        out.put_f32(mesh_table(pm, kind)[components * id + c]);
      }
    }
  }
}

// 2.2: the wedge coders, having seen the listed values and the corners before the splits.
void Writer::start_wedges() {
  const std::size_t level_faces = pm.base_face_count() + h.split_face_count;
  const std::size_t carried_first = 3 * (pm.total_face_count() - pm.carried_faces.size() / 3);
  for (int kind = 0; kind < 2; ++kind) {
    if (!has_ids(kind)) continue;
    const uint32_t count = static_cast<uint32_t>(table_count(kind));
    const uint64_t top = grid(kind).bits != 0 ? (uint64_t{1} << grid(kind).bits) - 1 : 0xFFFFFFFFull;
    WedgeCoder& coder = wedges[kind];
    coder.reset(kind_components(kind), count, top, h.split_vertices(), level_faces);
    if (h.minor >= 4) {  // 2.4 (§5.11)
      coder.predict_by_values(positions.significant, in_use(table_significant[kind]));
    }
    uint32_t units[3];
    for (uint32_t id = 0; id < count; ++id) {
      if (listed[kind][id] == 0) continue;
      units_of(kind, id, units);
      coder.learn(id, units);
    }
    const std::vector<uint32_t>& ids = mesh_face_ids(pm, kind);
    for (std::size_t slot = 0; slot < pm.base_faces.size(); ++slot) {
      coder.pass(pm.base_faces[slot], ids[slot], true);
    }
    for (std::size_t k = 0; k < pm.carried_faces.size(); ++k) {
      coder.pass(pm.carried_faces[k], ids[carried_first + k], false);
    }
  }
}

std::string Writer::tables() {
  std::string raw;
  ByteWriter out(raw);
  if (h.minor >= 2) {
    put_listed(out, 0);
    put_listed(out, 1);
  } else {
    put_table(out, pm.uvs, 2, uv_grid.bits != 0 ? &uv_grid : nullptr);
    put_table(out, pm.normals, 3, normal_grid.bits != 0 ? &normal_grid : nullptr);
  }
  for (const std::string& library : pm.material_libraries) put_string(out, library);
  for (const std::string& name : pm.material_names) put_string(out, name);
  return raw;
}

namespace {

// One table value, component c (§5.4): f32 (grid and significant null), a grid index, which
// MUST be on the grid, or (2.3) a number of significant decimals, which MUST be a decimal's;
// `unit` gets it in the integers residuals are taken in (§5.11).
bool read_table_value(ByteReader& in, const Grid* grid, const SignificantDecimals* significant,
                      std::size_t c, float& x, uint32_t& unit) {
  if (grid == nullptr && significant == nullptr) {
    if (!in.read_f32(x)) return false;
    unit = ordered_from_float(x);
    return true;
  }
  if (!in.read_varint(unit)) return false;
  if (grid != nullptr && unit > (uint32_t{1} << grid->bits) - 1) {
    return in.fail(ErrorCode::kCorruptStream, in.where() + ": grid index beyond the grid");
  }
  if (!float_of_unit(grid, significant, unit, c, x)) {
    return in.fail(ErrorCode::kCorruptStream, in.where() + ": a table value that is no decimal's");
  }
  return true;
}

bool read_table(ByteReader& in, uint32_t count, std::size_t components, int bits,
                std::vector<float>& values) {
  values.resize(components * std::size_t{count});
  Grid grid;
  if (bits != 0 && !read_grid(in, bits, components, grid)) return false;
  uint32_t unit;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!read_table_value(in, bits != 0 ? &grid : nullptr, nullptr, i % components, values[i], unit)) {
      return false;
    }
  }
  return true;
}

}  // namespace
}  // namespace pm::detail::v2

namespace pm {

// 2.2 (§5.11): the wedge coders of the kinds the corners have.
void PmStreamReader::State::reset_wedges() {
  const uint64_t level_faces = uint64_t{h.base_face_count} + h.split_face_count;
  for (int kind = 0; kind < 2; ++kind) {
    if (!h.has_ids(kind)) continue;
    const int bits = h.table_bits(kind);
    wedges[kind].reset(kind_components(kind), h.table_count(kind),
                       bits != 0 ? (uint64_t{1} << bits) - 1 : 0xFFFFFFFFull, h.split_vertices(),
                       level_faces);
  }
}

// 2.2: the corners before the splits, whose ids TABL must have listed.
bool PmStreamReader::State::start_wedges(ByteReader& in) {
  wedges_ready = true;
  for (int kind = 0; kind < 2 && h.minor >= 4; ++kind) {  // 2.4 (§5.11)
    wedges[kind].predict_by_values(positions.significant, in_use(table_significant[kind]));
  }
  for (int kind = 0; kind < 2; ++kind) {
    if (!h.has_ids(kind)) continue;
    const std::vector<uint32_t>& base = mesh_face_ids(pm, kind);
    const std::vector<uint32_t>& carried = carried_ids(kind);
    for (int part = 0; part < 2; ++part) {
      const std::vector<uint32_t>& vertices = part == 0 ? pm.base_faces : pm.carried_faces;
      const std::vector<uint32_t>& ids = part == 0 ? base : carried;
      for (std::size_t k = 0; k < vertices.size(); ++k) {
        if (ids[k] != kNoAttribute && !wedges[kind].known(ids[k])) {
          return in.fail(ErrorCode::kCorruptStream,
                         in.where() + ": a " + (part == 0 ? "base" : "carried") +
                             " face's corner has " + kind_name(kind) + " " +
                             std::to_string(ids[k]) + ", which the table does not list");
        }
        wedges[kind].pass(vertices[k], ids[k], part == 0);
      }
    }
  }
  return true;
}

// 2.2 (§7): a prefix's tables keep the entries it knows (listed or introduced by its
// splits); the others, whose values have not arrived, go from `target` (the decoded mesh or
// a copy of it), and the ids are renumbered in order. The wedge coders keep the stream's
// ids, so decoding can go on after a copy is trimmed.
bool PmStreamReader::State::has_unknown_entries() const {
  if (!wedges_ready) return false;
  for (int kind = 0; kind < 2; ++kind)
    if (h.has_ids(kind) && wedges[kind].unknown() > 0) return true;
  return false;
}

void PmStreamReader::State::drop_unknown_entries(ProgressiveMesh& target) const {
  for (int kind = 0; kind < 2; ++kind) {
    if (!wedges_ready || !h.has_ids(kind)) continue;
    const uint32_t count = h.table_count(kind);
    const std::size_t components = kind_components(kind);
    std::vector<uint32_t> new_id(count, kNoAttribute);
    uint32_t next = 0;
    for (uint32_t id = 0; id < count; ++id) {
      if (wedges[kind].known(id)) new_id[id] = next++;
    }
    if (next == count) continue;
    // Every id a corner has is known.
    renumber_entries(mesh_table(target, kind), components, new_id, next,
                     {&mesh_face_ids(target, kind), &mesh_moved_ids(target, kind)});
  }
}

// 2.2 (§5.4): the entries listed with their ids' gaps; the others are 0 until a split
// introduces them (§5.11).
bool PmStreamReader::State::read_listed(ByteReader& in, int kind) {
  const uint32_t count = h.table_count(kind);
  const int bits = h.table_bits(kind);
  const std::size_t components = kind_components(kind);
  std::vector<float>& values = mesh_table(pm, kind);
  values.assign(components * std::size_t{count}, 0.0f);
  if (count == 0) return true;
  if (bits != 0 && !read_grid(in, bits, components, grid(kind))) return false;
  SignificantDecimals& significant = table_significant[kind];
  if ((h.options & significant_table_option(kind)) != 0 && !read_significant(in, significant)) {
    return false;  // 2.3 (§5.4)
  }
  uint32_t listed = 0;
  if (!in.read_varint(listed)) return false;
  if (listed > count) {
    return in.fail(ErrorCode::kCorruptStream, in.where() + ": lists " + std::to_string(listed) +
                                                  " entries of " + std::to_string(count));
  }
  const bool ids = h.has_ids(kind);
  if (!ids && listed != count) {
    return in.fail(ErrorCode::kCorruptStream, in.where() + ": a table no corner uses must list every entry");
  }
  int64_t previous = -1;
  uint32_t units[3];
  for (uint32_t k = 0; k < listed; ++k) {
    uint32_t gap;
    if (!in.read_varint(gap)) return false;
    const int64_t id = previous + 1 + int64_t{gap};
    if (id >= int64_t{count}) {
      return in.fail(ErrorCode::kCorruptStream, in.where() + ": lists entry " + std::to_string(id) +
                                                    " of " + std::to_string(count));
    }
    previous = id;
    for (std::size_t c = 0; c < components; ++c) {
      if (!read_table_value(in, bits != 0 ? &grid(kind) : nullptr, in_use(significant), c,
                            values[components * std::size_t(id) + c], units[c])) {
        return false;
      }
    }
    if (ids) wedges[kind].learn(static_cast<uint32_t>(id), units);
  }
  return true;
}

bool PmStreamReader::State::decode_tables(ByteReader& in) {
  if (h.minor >= 2) {
    reset_wedges();
    if (!read_listed(in, 0) || !read_listed(in, 1) || !start_wedges(in)) return false;
  } else {
    if (!read_table(in, h.uv_count, 2, h.uv_bits, pm.uvs)) return false;
    if (!read_table(in, h.normal_count, 3, h.normal_bits, pm.normals)) return false;
  }
  uint64_t budget = h.material_string_bytes;
  if (!read_strings(in, h.material_library_count, "material library", budget, pm.material_libraries) ||
      !read_strings(in, h.material_count, "material name", budget, pm.material_names)) {
    return false;
  }
  if (budget != 0) {
    return in.fail(ErrorCode::kCorruptStream, in.where() + ": the material strings are " +
                                                  std::to_string(budget) +
                                                  " bytes shorter than the header says");
  }
  return true;
}

}  // namespace pm
