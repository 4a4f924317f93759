// Format 2.x's reader, PmStreamReader::State: what it has decoded so far and what it needs
// to go on (the header, the index, grids, values, fans, range-coder models, wedge coders),
// and its sections' readers, each defined beside the section's writer: header.cpp (the
// header, section checks, INDX), base_mesh.cpp (BASE, WELD, CARY, LOOS, ORDR), tables.cpp
// (TABL), chunks.cpp (CHNK). pm_codec_v2.cpp takes the bytes as they come and hands each
// section to its reader. Internal to formats/.
#pragma once

#include <zstd.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "byte_io.h"
#include "corner_codes.h"
#include "pm/pm_codec.h"
#include "pm_layout.h"
#include "significant_decimals.h"
#include "split_fans.h"
#include "v2/format.h"
#include "v2/positions.h"
#include "wedge_codes.h"

namespace pm {

using namespace detail;      // NOLINT: the layout helpers are the reader's vocabulary
using namespace detail::v2;  // NOLINT: and so is format 2.x's

struct PmStreamReader::State {
  ReadOptions options;
  Status status;                // the first error: final
  std::string buffer;           // bytes received and not yet consumed
  uint64_t consumed = 0;        // stream offset of buffer[0]
  enum Stage { kHeader, kVersion1, kSections, kDone } stage = kHeader;
  bool stopped = false;         // done at options.max_splits, before the end of the stream
  Header2 h;
  std::vector<uint32_t> expected;
  std::size_t next = 0;         // index into expected
  MemoryPlan memory;
  std::vector<ChunkEntry> index;
  std::size_t chunks_decoded = 0;
  bool base_done = false;       // every section before the first chunk decoded
  bool finished = false;        // finish() succeeded: take() may hand the mesh over
  bool taken = false;           // take() did

  ProgressiveMesh pm;
  ProgressiveMesh trimmed;  // mesh()'s copy of pm without unknown entries (2.2, mid-stream)
  std::size_t trimmed_chunks = SIZE_MAX;  // the chunks decoded when `trimmed` was made
  // Carried faces' attribute ids: the mesh's per-face arrays hold them last (creation order),
  // after the faces of the splits decoded so far; they are attached when mesh() is read.
  std::vector<uint32_t> carried_uvs, carried_normals, carried_materials;
  bool carried_attached = false;
  uint64_t decoded_faces = 0;

  Grid position_grid, uv_grid, normal_grid;  // uv and normal grids: 2.2 (§5.11)
  SignificantDecimals significant;            // 2.3 (§5.3), from BASE
  SignificantDecimals table_significant[2];   // 2.3 (§5.4), from TABL, per kind
  VertexValues positions, colors;
  std::unique_ptr<CornerPredictor> uv_codes, normal_codes;
  // 2.2 (§5.11): the splits' corners, per kind; set up by TABL, or by the first chunk when
  // there is no TABL.
  WedgeCoder wedges[2];
  bool wedges_ready = false;
  SplitFans fans;
  std::vector<uint32_t> chunk_u;        // 2.1: the u of each split of the chunk being decoded
  std::unique_ptr<ChunkModels> models;  // 2.1's range-coder models, from chunk to chunk
  std::unique_ptr<ZSTD_DCtx, size_t (*)(ZSTD_DCtx*)> dctx{nullptr, ZSTD_freeDCtx};
  std::string raw;

  // Per kind (0: texture coordinates, 1: normals; the mesh's arrays are format.h's
  // mesh_table() and the like, the header's counts and bits Header2's): the carried faces'
  // corners' ids, the table's grid, and the coder of corner codes (§5.7: BASE, CARY and the
  // chunks before 2.2), null when the corners have no ids of the kind.
  std::vector<uint32_t>& carried_ids(int kind) { return kind == 0 ? carried_uvs : carried_normals; }
  Grid& grid(int kind) { return kind == 0 ? uv_grid : normal_grid; }
  CornerPredictor* codes(int kind) { return (kind == 0 ? uv_codes : normal_codes).get(); }

  Status fail(Status s) {
    if (status.is_ok()) status = std::move(s);
    return status;
  }

  void detach_carried() {
    if (!carried_attached) return;
    const std::size_t keep = 3 * (pm.base_face_count() + (decoded_faces - pm.base_face_count() -
                                                          pm.carried_faces.size() / 3));
    if (pm.has_uvs()) pm.face_uvs.resize(keep);
    if (pm.has_normals()) pm.face_normals.resize(keep);
    if (pm.has_materials()) pm.face_materials.resize(keep / 3);
    carried_attached = false;
  }
  void attach_carried() {
    if (carried_attached) return;
    if (h.uv_ids()) pm.face_uvs.insert(pm.face_uvs.end(), carried_uvs.begin(), carried_uvs.end());
    if (h.normal_ids()) {
      pm.face_normals.insert(pm.face_normals.end(), carried_normals.begin(), carried_normals.end());
    }
    if (h.material_ids()) {
      pm.face_materials.insert(pm.face_materials.end(), carried_materials.begin(),
                               carried_materials.end());
    }
    carried_attached = true;
  }

  Status process(std::string_view bytes, std::size_t& used);
  Status finish(ReadResult* result);
  Status start(std::string_view header_bytes, bool reserve = true);
  Status check_section(uint32_t tag, uint32_t flags, uint64_t stored, uint64_t raw_size) const;
  Status decode(uint32_t tag, ByteReader& in);
  bool decode_base(ByteReader& in);
  bool decode_welds(ByteReader& in);
  bool decode_carried(ByteReader& in);
  bool decode_tables(ByteReader& in);
  bool read_listed(ByteReader& in, int kind);
  bool has_unknown_entries() const;
  void drop_unknown_entries(ProgressiveMesh& target) const;
  void reset_wedges();
  bool start_wedges(ByteReader& in);
  bool decode_index(ByteReader& in);
  bool decode_chunk(ByteReader& in);
  bool decode_loose(ByteReader& in);
  bool decode_order(ByteReader& in);
  bool read_vertex_values(ByteReader& in, uint32_t count);
  bool read_corner(ByteReader& in, int kind, uint32_t vertex, uint32_t& id);
  bool read_corners(ByteReader& in, const std::vector<uint32_t>& vertices,
                    const std::array<std::vector<uint32_t>*, 2>& ids);
};

// One corner's id of `kind` (0 texture coordinates, 1 normals), from its code (§5.7).
inline bool PmStreamReader::State::read_corner(ByteReader& in, int kind, uint32_t vertex, uint32_t& id) {
  uint32_t code;
  std::string problem;
  if (!in.read_varint(code)) return false;
  if (!codes(kind)->decode(code, vertex, h.table_count(kind), id, problem)) {
    return in.fail(ErrorCode::kCorruptStream,
                   in.where() + ": a corner of vertex " + std::to_string(vertex) + " " + problem);
  }
  return true;
}

}  // namespace pm
