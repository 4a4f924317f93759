// Format 2.x's writer: what it knows of the mesh it writes (its grids and decimals, its
// values in the integers residuals are taken in, the corner coders), and its sections'
// writers, each defined beside the section's reader: base_mesh.cpp (BASE, CARY, WELD, LOOS,
// ORDR), tables.cpp (TABL and the wedge coders), chunks.cpp (CHNK and INDX). write_pm_v2
// (pm_codec_v2.cpp) sets it up and compresses what it writes. Internal to formats/.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "byte_io.h"
#include "corner_codes.h"
#include "pm/pm_codec.h"
#include "significant_decimals.h"
#include "v2/format.h"
#include "v2/positions.h"
#include "wedge_codes.h"

namespace pm::detail::v2 {

struct Writer {
  const ProgressiveMesh& pm;
  const WriteOptions& options;
  Header2 h;
  Grid position_grid, uv_grid, normal_grid;
  SignificantDecimals significant;  // 2.3 (§5.3)
  VertexValues positions, colors;
  CornerPredictor uv_codes, normal_codes;
  // 2.2 (§5.11): per kind (texture coordinates, normals), the ids TABL lists (those of the
  // base and carried faces, and those no corner uses), and the coder of the splits' corners.
  std::vector<uint8_t> listed[2];
  WedgeCoder wedges[2];
  // 2.3 (§5.4): per kind, the table as significant decimals (digits 0: not), and each
  // component's number.
  SignificantDecimals table_significant[2];
  std::vector<uint32_t> table_numbers[2];

  // Per kind (0: texture coordinates, 1: normals; the mesh's arrays are format.h's
  // mesh_table() and the like): its table's entries, its grid, whether corners have its ids.
  // table_count() and has_ids() ask the mesh, not h: plan_tables() runs before h has them.
  std::size_t table_count(int kind) const { return kind == 0 ? pm.uv_count() : pm.normal_count(); }
  const Grid& grid(int kind) const { return kind == 0 ? uv_grid : normal_grid; }
  bool has_ids(int kind) const { return kind == 0 ? pm.has_uvs() : pm.has_normals(); }
  // The error bound of the level before split i as stored (WriteOptions::error_bits): split
  // i's, the full mesh's 0 after the last; the header, the index and the errors stream alike.
  float error_before(std::size_t i) const {
    return i < pm.splits.size() ? stored_error(pm.splits[i].error, options.error_bits) : 0.0f;
  }
  // Entry `id`'s values in the integers residuals are taken in: grid indices or float bits.
  void units_of(int kind, uint32_t id, uint32_t* out) const {
    const std::vector<float>& table = mesh_table(pm, kind);
    for (std::size_t c = 0; c < kind_components(kind); ++c) {
      const std::size_t at = kind_components(kind) * std::size_t{id} + c;
      if (table_significant[kind].digits != 0) {
        out[c] = table_numbers[kind][at];  // 2.3 (§5.4)
      } else {
        out[c] = grid(kind).bits != 0 ? quantize(grid(kind), table[at], c)
                                      : ordered_from_float(table[at]);
      }
    }
  }

  // Asks for entry `id`'s values as units_of() reads them, and for the wedge coder's place
  // of it. Inlined always (UnknownIds::prefetch says why).
  [[gnu::always_inline]] void prefetch_units(int kind, uint32_t id) const {
    if (id == kNoAttribute) return;
    const std::size_t at = kind_components(kind) * std::size_t{id};
    const std::vector<float>& table = mesh_table(pm, kind);
    if (table_significant[kind].digits != 0) {
      if (at < table_numbers[kind].size()) __builtin_prefetch(&table_numbers[kind][at]);
    } else if (at < table.size()) {
      __builtin_prefetch(&table[at]);
    }
    wedges[kind].prefetch(id);
  }

  Writer(const ProgressiveMesh& mesh, const WriteOptions& o)
      : pm(mesh),
        options(o),
        uv_codes(pm.base_vertex_count + pm.splits.size()),
        normal_codes(pm.base_vertex_count + pm.splits.size()) {}

  void put_corner(ByteWriter& uv_out, ByteWriter& normal_out, uint32_t vertex, std::size_t slot) {
    if (pm.has_uvs()) uv_out.put_varint(uv_codes.encode(vertex, pm.face_uvs[slot]));
    if (pm.has_normals()) normal_out.put_varint(normal_codes.encode(vertex, pm.face_normals[slot]));
  }

  // BASE, CARY, WELD, ORDR, LOOS (base_mesh.cpp).
  void put_positions(ByteWriter& out, uint32_t first, uint32_t count);
  std::string base();
  std::string carried();
  std::string welds();
  std::string order();
  std::string loose();
  // TABL and, 2.2, the wedge coders (tables.cpp).
  void plan_tables();
  void put_listed(ByteWriter& out, int kind);
  void start_wedges();
  std::string tables();
  // CHNK and INDX (chunks.cpp): each chunk's raw bytes go to `emit` as soon as they are
  // made, in order (the writer compresses them while the next ones are made).
  void chunks(const std::function<void(std::string&&)>& emit, std::string& index);
};

}  // namespace pm::detail::v2
