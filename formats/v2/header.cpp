// Format 2.x's header and chunk index (pm-format.md §3, §4, §5.5, §7): the 96-byte header,
// written and parsed with its checks (§3.3); the sections a header calls for, in order, and
// the bounds of their sizes (§4.3, §4.4); the memory a decode may take (§7.1). The reader's
// half: its start (what the checked counts let it reserve), its check of each section header
// before the payload is decompressed, the index (INDX, written with the chunks:
// chunks.cpp), and read_pm_info, which reads the header and the index alone.
#include <zstd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include "byte_io.h"
#include "core/memory_pages.h"
#include "core/no_throw.h"
#include "pm/pm_codec.h"
#include "pm_layout.h"
#include "v2/format.h"
#include "v2/reader.h"

namespace pm::detail::v2 {

void append_header2(const Header2& h, std::string& out) {
  const std::size_t start = out.size();
  ByteWriter w(out);
  w.put_bytes(std::string_view(kMagic, sizeof kMagic));
  w.put_u16(h.major);
  w.put_u16(h.minor);
  w.put_u32(h.flags);
  for (uint32_t count : {h.base_vertex_count, h.base_face_count, h.split_count,
                         h.loose_vertex_count, h.weld_count, h.carried_face_count,
                         h.moved_face_count, h.split_face_count, h.chunk_count}) {
    w.put_u32(count);
  }
  w.put_f32(h.max_error);
  for (uint32_t field : {h.attributes, h.color_components, h.uv_count, h.normal_count,
                         h.material_count, h.material_library_count, h.material_string_bytes}) {
    w.put_u32(field);
  }
  w.put_u8(h.position_bits);  // offset 84 (§3.1): the fields that differ from 1.x
  w.put_u8(h.uv_bits);
  w.put_u8(h.normal_bits);
  w.put_u8(0);
  w.put_u32(h.options);
  w.put_u32(crc32(std::string_view(out).substr(start, kHeaderCrcOffset)));
}

// §3.3: the header, once 96 bytes have arrived and the caller has seen major 2.
Status parse_header2(std::string_view bytes, Header2& h) {
  ByteReader in(bytes.substr(0, kHeaderSize), "header", ErrorCode::kTruncatedStream);
  in.skip(sizeof kMagic);
  Header2 r;
  in.read_u16(r.major);
  in.read_u16(r.minor);
  in.read_u32(r.flags);
  for (uint32_t* count : {&r.base_vertex_count, &r.base_face_count, &r.split_count,
                          &r.loose_vertex_count, &r.weld_count, &r.carried_face_count,
                          &r.moved_face_count, &r.split_face_count, &r.chunk_count}) {
    in.read_u32(*count);
  }
  in.read_f32(r.max_error);
  for (uint32_t* field : {&r.attributes, &r.color_components, &r.uv_count, &r.normal_count,
                          &r.material_count, &r.material_library_count,
                          &r.material_string_bytes}) {
    in.read_u32(*field);
  }
  uint8_t reserved = 0;
  in.read_u8(r.position_bits);
  in.read_u8(r.uv_bits);
  in.read_u8(r.normal_bits);
  in.read_u8(reserved);
  in.read_u32(r.options);
  uint32_t stored_crc = 0;
  in.read_u32(stored_crc);
  if (!in.status()) return in.status();
  const uint32_t crc = crc32(bytes.substr(0, kHeaderCrcOffset));
  if (crc != stored_crc) {
    return Status(ErrorCode::kChecksumMismatch, "header: checksum mismatch (stored " +
                                                    std::to_string(stored_crc) + ", computed " +
                                                    std::to_string(crc) + ")");
  }
  const std::string version = std::to_string(r.major) + "." + std::to_string(r.minor);
  // §3.2: flags and unknown option bits are must-understand; the reserved byte may be used
  // by a later minor. In a version this reader knows, all of them are damage.
  const bool later = r.minor > kNewestMinor;
  const uint32_t known_options = r.minor >= 3 ? kKnownOptions : kOptionKeepsOrder;
  if (r.flags != 0 || (r.options & ~known_options) != 0) {
    return Status(later ? ErrorCode::kUnsupportedVersion : ErrorCode::kCorruptStream,
                  "header: flag or option bits this reader does not know (version " + version + ")");
  }
  if (reserved != 0 && !later) return corrupt("header: reserved byte 87 is not zero");
  if ((r.attributes & ~kKnownAttributeBits) != 0 && !later) {
    return corrupt("header: reserved attribute bits are set");
  }
  r.attributes &= kKnownAttributeBits;
  // §7.2 limits, then §3.3's consistency rules.
  for (const auto& [count, what] :
       {std::pair{r.base_vertex_count, "base vertices"}, {r.base_face_count, "base faces"},
        {r.split_count, "splits"}, {r.loose_vertex_count, "loose vertices"},
        {r.weld_count, "welds"}, {r.carried_face_count, "carried faces"},
        {r.moved_face_count, "moved faces"}, {r.split_face_count, "split faces"},
        {r.chunk_count, "chunks"}, {r.uv_count, "texture coordinates"},
        {r.normal_count, "normals"}, {r.material_string_bytes, "material string bytes"}}) {
    if (count > kMaxCount) {
      return Status(ErrorCode::kResourceLimit, std::string("header: ") + std::to_string(count) +
                                                   " " + what + " (at most " +
                                                   std::to_string(kMaxCount) + ")");
    }
  }
  if (r.material_count > kMaxMaterials || r.material_library_count > kMaxMaterials) {
    return Status(ErrorCode::kResourceLimit, "header: too many materials or material libraries");
  }
  if (r.split_face_count < r.split_count || r.split_face_count > 2 * uint64_t{r.split_count}) {
    return corrupt("header: " + std::to_string(r.split_count) + " splits cannot add " +
                   std::to_string(r.split_face_count) + " faces");
  }
  if ((r.chunk_count == 0) != (r.split_count == 0) || r.chunk_count > r.split_count) {
    return corrupt("header: " + std::to_string(r.chunk_count) + " chunks for " +
                   std::to_string(r.split_count) + " splits");
  }
  if (r.weld_count > r.base_vertex_count) return corrupt("header: more welds than base vertices");
  if (r.split_count == 0 && r.moved_face_count != 0) return corrupt("header: moved faces without splits");
  if (!std::isfinite(r.max_error) || r.max_error < 0) return corrupt("header: bad max_error");
  if (r.split_count == 0 && (r.max_error != 0 || std::signbit(r.max_error))) {
    return corrupt("header: max_error is not +0 without splits");
  }
  if (r.color_components != 0 && r.color_components != 3 && r.color_components != 4) {
    return corrupt("header: " + std::to_string(r.color_components) + " colour components");
  }
  if (r.attributes != 0 && r.faces() == 0) return corrupt("header: attribute ids without faces");
  if (r.material_string_bytes >
      uint64_t{kMaxStringBytes} * (uint64_t{r.material_count} + r.material_library_count)) {
    return corrupt("header: material strings longer than the names allow");
  }
  if (!valid_bits(r.position_bits) || !valid_bits(r.uv_bits) || !valid_bits(r.normal_bits)) {
    // 2.3: a decimal grid of positions may have up to 30 bits (§5.3).
    const bool decimal = (r.options & kOptionDecimalPositions) != 0;
    if (!decimal || r.position_bits > kMaxDecimalBits || !valid_bits(r.uv_bits) ||
        !valid_bits(r.normal_bits)) {
      return corrupt("header: quantization bits must be 0 or 4 to 24 (positions on a decimal grid: 4 to 30)");
    }
  }
  if ((r.options & kOptionDecimalPositions) != 0 && r.position_bits == 0) {
    return corrupt("header: positions on a decimal grid without grid bits");
  }
  if ((r.options & kOptionSignificantPositions) != 0 && r.position_bits != 0) {
    return corrupt("header: positions as significant decimals on a grid");
  }
  if (((r.options & kOptionSignificantUvs) != 0 && (r.uv_bits != 0 || r.uv_count == 0)) ||
      ((r.options & kOptionSignificantNormals) != 0 && (r.normal_bits != 0 || r.normal_count == 0))) {
    return corrupt("header: a table as significant decimals that is on a grid or empty");
  }
  if (uint64_t{r.base_vertex_count} + r.split_count + r.loose_vertex_count >= 0xFFFFFFFFull) {
    return corrupt("header: too many vertices for 32-bit ids");
  }
  h = r;
  return Status::ok();
}

// The known sections of a stream with this header, in the order it must hold them (§4.3):
// each is present exactly when it has entries.
std::vector<uint32_t> expected_sections(const Header2& h) {
  std::vector<uint32_t> tags;
  // BASE also holds the position grid, which loose vertices need without a base mesh.
  if (h.base_vertex_count > 0 || h.base_face_count > 0 ||
      ((h.position_bits != 0 || (h.options & kOptionSignificantPositions) != 0) &&
       h.loose_vertex_count > 0)) {
    tags.push_back(kTagBase);
  }
  if (h.weld_count > 0) tags.push_back(kTagWelds);
  if (h.carried_face_count > 0) tags.push_back(kTagCarried);
  if (h.uv_count > 0 || h.normal_count > 0 || h.material_count > 0 || h.material_library_count > 0) {
    tags.push_back(kTagTables);
  }
  if (h.chunk_count > 0) {
    tags.push_back(kTagIndex);
    tags.insert(tags.end(), h.chunk_count, kTagChunk);
  }
  if (h.loose_vertex_count > 0) tags.push_back(kTagLoose);
  if ((h.options & kOptionKeepsOrder) != 0) tags.push_back(kTagOrder);
  return tags;
}

bool is_v2_tag(uint32_t tag) {
  for (uint32_t known : {kTagBase, kTagWelds, kTagCarried, kTagTables, kTagIndex, kTagChunk,
                         kTagLoose, kTagOrder}) {
    if (tag == known) return true;
  }
  return false;
}

// The largest raw size the counts allow a section (§4.4), chunks aside (their bound needs
// the index: chunk_raw_bound).
uint64_t raw_bound(const Header2& h, uint32_t tag) {
  const uint64_t B = h.base_vertex_count, F = h.base_face_count, C = h.carried_face_count;
  const uint64_t Q = h.color_components, strings = uint64_t{h.material_count} + h.material_library_count;
  // Grid indices up to 30 bits (2.3) are varints of up to 5 bytes; a decimal grid is 25.
  if (tag == kTagBase) return 25 + (15 + 4 * Q) * B + 15 * F + 5 * F + 30 * F;
  if (tag == kTagWelds) return 10 * uint64_t{h.weld_count};
  if (tag == kTagCarried) return 15 * C + 5 * C + 30 * C;
  if (tag == kTagTables) {
    // 2.2: each entry listed with its id's gap (§5.4).
    const uint64_t gap = h.minor >= 2 ? 5 : 0;
    return 32 + 10 + (10 + gap) * uint64_t{h.uv_count} + (15 + gap) * uint64_t{h.normal_count} +
           h.material_string_bytes + 3 * strings;
  }
  if (tag == kTagIndex) return 19 * uint64_t{h.chunk_count};
  if (tag == kTagLoose) return (15 + 4 * Q) * uint64_t{h.loose_vertex_count};
  if (tag == kTagOrder) return 5 * (h.vertices() + h.faces());  // varints of ids below 3 * 2^30
  return kMaxZstdRatio * std::numeric_limits<uint32_t>::max();  // chunks: see chunk_raw_bound
}

uint64_t chunk_raw_bound(const Header2& h, const ChunkEntry& c) {
  const uint64_t n = c.splits, m = c.moved_faces, a = c.new_faces;
  // 2.1: a range-coded decision costs at most 6.05 bits (probabilities stay within
  // [31, 2017] / 2048), and u, vl, vr and each position take at most 66 decisions: 400 bytes
  // per split cover them, and 30 the four codes' ends.
  // 2.2: a corner's id takes at most 8 decisions and a 40-bit exp-Golomb code, and a new
  // id's value up to three more: 80 bytes per corner cover them, 10 each kind's code's end.
  if (h.minor >= 2) {
    return 5 * kChunkStreams + 50 + n * (400 + 10 * uint64_t{h.color_components}) +
           (15 * n + 5 * m) + 5 * a + 2 * 80 * (m + 3 * a);
  }
  if (h.minor >= 1) {
    return 5 * kChunkStreams + 30 + n * (400 + 10 * uint64_t{h.color_components}) +
           (15 * n + 5 * m) + 5 * a + 2 * 5 * (m + 3 * a);
  }
  return 5 * kChunkStreams + n * (15 + 10 + 30 + 10 * uint64_t{h.color_components}) +
         (15 * n + 5 * m) + 5 * a + 2 * 5 * (m + 3 * a);
}

MemoryPlan plan_memory(const Header2& h) {
  const uint64_t V = h.vertices(), T = h.faces(), M = h.moved_face_count;
  const uint64_t split_faces = uint64_t{h.base_face_count} + h.split_face_count;
  const uint64_t strings = uint64_t{h.material_count} + h.material_library_count;
  MemoryPlan plan;
  plan.mesh = 12 * V + 12 * uint64_t{h.base_face_count} +
              sizeof(VertexSplit) * uint64_t{h.split_count} + 4 * M +
              sizeof(Weld) * uint64_t{h.weld_count} + 12 * uint64_t{h.carried_face_count} +
              4 * uint64_t{h.color_components} * V + 8 * uint64_t{h.uv_count} +
              12 * uint64_t{h.normal_count} + sizeof(std::string) * strings +
              h.material_string_bytes + strings;
  const uint64_t corner_ids = 4 * (3 * T + M);
  plan.mesh += (h.uv_ids() ? corner_ids : 0) + (h.normal_ids() ? corner_ids : 0) +
               (h.material_ids() ? 4 * T : 0);
  // The fans (3 corners and 3 links per face, a first corner per vertex), the values the
  // residuals are taken against, the corner-id predictors, the chunk index, zstd.
  plan.decoding =
      24 * split_faces + 4 * h.split_vertices() + 4 * (3 + uint64_t{h.color_components}) * V +
      (h.uv_ids() ? 4 * h.split_vertices() : 0) + (h.normal_ids() ? 4 * h.split_vertices() : 0) +
      sizeof(ChunkEntry) * uint64_t{h.chunk_count} + kZstdContextBytes + 65536 +
      sizeof(ChunkModels);
  // 2.2's wedge coders (§5.11): per kind, the values and known flags of the ids, a Fenwick
  // tree, three recent ids per vertex, the ids of the level's corners, the models.
  if (h.minor >= 2) {
    for (const auto& [present, count, components] :
         {std::tuple{h.uv_ids(), uint64_t{h.uv_count}, uint64_t{2}},
          std::tuple{h.normal_ids(), uint64_t{h.normal_count}, uint64_t{3}}}) {
      if (present) {
        plan.decoding += (4 * components + 9) * count + 12 * h.split_vertices() +
                         12 * split_faces + sizeof(WedgeModels);
      }
    }
  }
  if ((h.options & kOptionKeepsOrder) != 0) plan.mesh += 4 * (V + T);
  plan.validating = 16 * split_faces + 8 * ((uint64_t{h.base_vertex_count} + 63) / 64) +
                    ((h.options & kOptionKeepsOrder) != 0 ? (V + T) / 8 + 16 : 0);
  return plan;
}

Status memory_status(uint64_t needed, uint64_t limit) {
  if (limit == 0 || needed <= limit) return Status::ok();
  return Status(ErrorCode::kResourceLimit, "decoding needs " + byte_count_text(needed) +
                                               " of memory, the limit is " + byte_count_text(limit));
}

std::string section_name(uint32_t tag, std::size_t chunk) {
  return "section " + tag_name(tag) + (tag == kTagChunk ? " " + std::to_string(chunk) : "");
}

}  // namespace pm::detail::v2

namespace pm {

Status PmStreamReader::State::start(std::string_view header_bytes, bool reserve) {
  if (Status s = parse_header2(header_bytes, h); !s) return s;
  expected = expected_sections(h);
  memory = plan_memory(h);
  dctx.reset(ZSTD_createDCtx());
  if (!dctx) return Status(ErrorCode::kInternal, "zstd: cannot create a decompression context");
  stage = expected.empty() ? kDone : kSections;
  base_done = h.chunk_count == 0;
  if (!reserve) return Status::ok();
  if (Status s = memory_status(memory.needed(0), options.max_memory); !s) return s;
  // Everything below is bounded by the checked counts (§7.1).
  const uint64_t V = h.vertices(), split_faces = uint64_t{h.base_face_count} + h.split_face_count;
  pm.base_vertex_count = h.base_vertex_count;
  pm.color_components = h.color_components;
  pm.positions.reserve(3 * V);
  pm.colors.reserve(uint64_t{h.color_components} * V);
  pm.base_faces.reserve(3 * uint64_t{h.base_face_count});
  pm.splits.reserve(h.split_count);
  pm.moved_faces.reserve(h.moved_face_count);
  pm.welds.reserve(h.weld_count);
  pm.carried_faces.reserve(3 * uint64_t{h.carried_face_count});
  const uint64_t corners = 3 * h.faces();
  if (h.uv_ids()) {
    pm.face_uvs.reserve(corners);
    pm.moved_uvs.reserve(h.moved_face_count);
    uv_codes = std::make_unique<CornerPredictor>(h.split_vertices());
  }
  if (h.normal_ids()) {
    pm.face_normals.reserve(corners);
    pm.moved_normals.reserve(h.moved_face_count);
    normal_codes = std::make_unique<CornerPredictor>(h.split_vertices());
  }
  if (h.material_ids()) pm.face_materials.reserve(h.faces());
  positions.components = 3;
  positions.grid = h.position_bits != 0 ? &position_grid : nullptr;
  positions.units.reserve(3 * V);
  prefer_huge_pages(positions.units);  // each split reads its neighbours' (memory_pages.h)
  colors.components = h.color_components;
  colors.units.reserve(uint64_t{h.color_components} * V);
  fans.reset(h.split_vertices(), split_faces);
  return Status::ok();
}

Status PmStreamReader::State::check_section(uint32_t tag, uint32_t flags, uint64_t stored,
                                            uint64_t raw_size) const {
  const std::string where = section_name(tag, chunks_decoded);
  if ((flags & ~kSectionRequired) != 0 || (flags & kSectionRequired) == 0) {
    return Status(h.minor > kNewestMinor && (flags & ~kSectionRequired) != 0 ? ErrorCode::kUnsupportedVersion
                                                                         : ErrorCode::kCorruptStream,
                  where + ": flags " + std::to_string(flags) + " (a known section has exactly bit 0)");
  }
  if (tag != expected[next]) {
    return corrupt(where + ": out of order or not expected here (expected " +
                   section_name(expected[next], chunks_decoded) + ")");
  }
  uint64_t bound = raw_bound(h, tag);
  if (tag == kTagChunk) bound = chunk_raw_bound(h, index[chunks_decoded]);
  if (raw_size == 0 || raw_size > bound || raw_size > kMaxZstdRatio * stored) {
    return corrupt(where + ": raw size " + std::to_string(raw_size) + " is impossible here");
  }
  return memory_status(memory.needed(raw_size), options.max_memory);
}

bool PmStreamReader::State::decode_index(ByteReader& in) {
  index.resize(h.chunk_count);
  uint64_t splits = 0, new_faces = 0, moved = 0;
  float previous = h.max_error;
  for (uint32_t k = 0; k < h.chunk_count; ++k) {
    ChunkEntry& e = index[k];
    if (!in.read_varint(e.splits) || !in.read_varint(e.new_faces) || !in.read_varint(e.moved_faces) ||
        !in.read_f32(e.error_after)) {
      return false;
    }
    splits += e.splits;
    new_faces += e.new_faces;
    moved += e.moved_faces;
    const bool last = k + 1 == h.chunk_count;
    if (e.splits == 0 || e.new_faces < e.splits || e.new_faces > 2 * uint64_t{e.splits} ||
        !std::isfinite(e.error_after) || e.error_after < 0 || e.error_after > previous ||
        (last && (e.error_after != 0 || std::signbit(e.error_after)))) {
      return in.fail(ErrorCode::kCorruptStream, in.where() + ": chunk " + std::to_string(k) +
                                                    " is impossible (splits, faces or error)");
    }
    previous = e.error_after;
  }
  if (splits != h.split_count || new_faces != h.split_face_count || moved != h.moved_face_count) {
    return in.fail(ErrorCode::kCorruptStream,
                   in.where() + ": the chunks' splits, faces or moved faces disagree with the header");
  }
  base_done = true;
  return true;
}

Status read_pm_info(std::string_view bytes, PmInfo& info) {
  return detail::no_throw([&]() -> Status {
    if (bytes.size() >= 12 && std::memcmp(bytes.data(), kMagic, sizeof kMagic) == 0 &&
        (static_cast<uint8_t>(bytes[8]) | static_cast<uint8_t>(bytes[9]) << 8) != kMajor2) {
      return read_pm_info_v1(bytes, info);
    }
    if (bytes.size() < kHeaderSize) {
      const std::size_t magic = std::min(bytes.size(), sizeof kMagic);
      if (std::memcmp(bytes.data(), kMagic, magic) != 0) return corrupt("not a .pm stream (bad magic)");
      return Status(ErrorCode::kTruncatedStream, "truncated in the header (" +
                                                     std::to_string(bytes.size()) + " of 96 bytes)");
    }
    if (std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) return corrupt("not a .pm stream (bad magic)");
    Header2 h;
    if (Status status = parse_header2(bytes, h); !status) return status;
    PmInfo r = info_from_header(h);
    r.section_count = static_cast<uint32_t>(expected_sections(h).size());
    r.position_bits = h.position_bits;
    r.uv_bits = h.uv_bits;
    r.normal_bits = h.normal_bits;
    r.keeps_order = (h.options & kOptionKeepsOrder) != 0;
    r.positions_decimal = (h.options & kOptionDecimalPositions) != 0;
    r.positions_significant = (h.options & kOptionSignificantPositions) != 0;
    r.uvs_significant = (h.options & kOptionSignificantUvs) != 0;
    r.normals_significant = (h.options & kOptionSignificantNormals) != 0;
    // The chunk index: skip the sections before it, decompress it, and walk the chunks'
    // section headers for their ends.
    if (h.chunk_count > 0) {
      ReadOptions options;
      options.max_splits = 0;
      options.allow_truncated = true;
      PmStreamReader::State s;
      s.options = options;
      if (Status status = s.start(bytes, false); !status) return status;
      // Section headers from `offset`: tag and stored size, or false at the end of `bytes`.
      std::size_t offset = kHeaderSize;
      const auto section_at = [&](uint32_t& tag, uint32_t& flags, uint64_t& stored, uint64_t& raw_size) {
        SectionHeader section;
        if (offset > bytes.size() || !read_section_header(bytes.substr(offset), section)) return false;
        tag = section.tag;
        flags = section.flags;
        stored = section.stored_size;
        raw_size = section.raw_size;
        return true;
      };
      uint32_t tag = 0, flags = 0;
      uint64_t stored = 0, raw_size = 0;
      while (s.index.empty()) {
        if (!section_at(tag, flags, stored, raw_size) ||
            bytes.size() - offset - kSectionHeaderSize < stored) {
          return Status(ErrorCode::kTruncatedStream, "truncated before the chunk index");
        }
        if (tag == kTagIndex) {
          if (Status status = s.check_section(tag, flags, stored, raw_size); !status) return status;
          if (Status status = decompress_frame("section INDX", bytes.substr(offset + kSectionHeaderSize, stored),
                                               raw_size, s.dctx.get(), s.raw);
              !status) {
            return status;
          }
          ByteReader payload(s.raw, "section INDX", ErrorCode::kCorruptStream);
          if (!s.decode_index(payload)) return payload.status();
          if (!payload.at_end()) return corrupt("section INDX: bytes left over");
        } else if (is_v2_tag(tag)) {
          if (tag != s.expected[s.next]) return corrupt("section " + tag_name(tag) + ": out of order");
          ++s.next;
        }
        offset += kSectionHeaderSize + static_cast<std::size_t>(stored);
      }
      uint64_t splits = 0, faces = uint64_t{h.base_face_count} + h.carried_face_count;
      for (const ChunkEntry& e : s.index) {
        PmInfo::Chunk chunk;
        chunk.splits = e.splits;
        splits += e.splits;
        faces += e.new_faces;
        chunk.vertices_after = h.base_vertex_count + splits - h.weld_count +
                               (splits == h.split_count ? h.loose_vertex_count : 0);
        chunk.faces_after = faces;
        chunk.error_after = e.error_after;
        // Where the chunk ends, when its section header is in `bytes` (optional sections of
        // other tools may come between chunks).
        while (section_at(tag, flags, stored, raw_size) && tag != kTagChunk && stored <= bytes.size()) {
          offset += kSectionHeaderSize + static_cast<std::size_t>(stored);
        }
        if (section_at(tag, flags, stored, raw_size) && stored <= bytes.size()) {
          offset += kSectionHeaderSize + static_cast<std::size_t>(stored);
          chunk.stream_end = offset;
        } else {
          offset = bytes.size() + 1;  // the rest is not in `bytes`
        }
        r.chunks.push_back(chunk);
      }
    }
    info = r;
    return Status::ok();
  });
}

}  // namespace pm
