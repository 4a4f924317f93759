// Format 2.x's vocabulary, shared by the writer and the reader of every section (each file of
// formats/v2/ holds both halves of one part of the stream): the header's fields and option
// bits (pm-format.md §3), the sections' tags, order and size bounds (§4), the chunk plan, the
// index's entries and a chunk's streams (§5.5), the primitive codings (§5.1, §5.7) and the
// range coder's models (§5.10), and the memory a decode takes (§7.1). Internal to formats/.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "byte_io.h"
#include "pm/advanced/stream_order.h"
#include "pm/pm_codec.h"
#include "pm_layout.h"
#include "range_coder.h"

namespace pm::detail::v2 {

constexpr uint16_t kMajor2 = 2;
constexpr uint16_t kNewestMinor = 4;        // the newest minor this reader knows (2.4)
constexpr uint32_t kOptionKeepsOrder = 1u;  // header `options` bit 0: an ORDR section
// Header `options` bit 1 (2.3): the positions are on a decimal grid (§5.3), lossless.
constexpr uint32_t kOptionDecimalPositions = 2u;
// Header `options` bit 2 (2.3): lossless positions as decimals of a few significant digits
// (§5.3).
constexpr uint32_t kOptionSignificantPositions = 4u;
// Header `options` bits 3 and 4 (2.3): the texture-coordinate (normal) table as significant
// decimals, lossless (§5.4).
constexpr uint32_t kOptionSignificantUvs = 8u, kOptionSignificantNormals = 16u;
constexpr uint32_t kKnownOptions = kOptionKeepsOrder | kOptionDecimalPositions |
                                   kOptionSignificantPositions | kOptionSignificantUvs |
                                   kOptionSignificantNormals;
// The option bit of a table kind's significant decimals (0: texture coordinates, 1: normals).
constexpr uint32_t significant_table_option(int kind) {
  return kind == 0 ? kOptionSignificantUvs : kOptionSignificantNormals;
}
constexpr int kMinBits = 4, kMaxBits = 24;  // quantization bits, when not 0
// A decimal grid (2.3, §5.3): at most this many bits, and places after the point.
constexpr int kMaxDecimalBits = 30, kMaxDecimals = 15;

// Corner attributes come in two kinds, 0 texture coordinates and 1 normals, each with a value
// table and its corners' ids. Code for both loops over the kind and asks accessors for what
// differs, each beside its data: these (the mesh's arrays), Header2's, corner_code_stream,
// significant_table_option, the Writer's and PmStreamReader::State's.

// A kind's components: an entry of its table is this many floats.
constexpr std::size_t kind_components(int kind) {
  return kind == 0 ? 2 : 3;
}
// A kind's name in messages ("a corner has texture coordinate 7").
constexpr const char* kind_name(int kind) {
  return kind == 0 ? "texture coordinate" : "normal";
}
// A mesh's arrays of a kind: its table, its faces' corners' ids (3 a face, in creation
// order) and its splits' moved corners' ids. `Mesh` is ProgressiveMesh, const or not: the
// array is as const as the mesh.
template <typename Mesh>
auto& mesh_table(Mesh& pm, int kind) {
  return kind == 0 ? pm.uvs : pm.normals;
}
template <typename Mesh>
auto& mesh_face_ids(Mesh& pm, int kind) {
  return kind == 0 ? pm.face_uvs : pm.face_normals;
}
template <typename Mesh>
auto& mesh_moved_ids(Mesh& pm, int kind) {
  return kind == 0 ? pm.moved_uvs : pm.moved_normals;
}

constexpr uint32_t kTagTables = make_tag("TABL");
constexpr uint32_t kTagIndex = make_tag("INDX");
constexpr uint32_t kTagChunk = make_tag("CHNK");
constexpr uint32_t kTagOrder = make_tag("ORDR");

struct Header2 {
  uint16_t major = kMajor2, minor = kNewestMinor;
  uint32_t flags = 0;
  uint32_t base_vertex_count = 0, base_face_count = 0, split_count = 0;
  uint32_t loose_vertex_count = 0, weld_count = 0, carried_face_count = 0;
  uint32_t moved_face_count = 0, split_face_count = 0;
  uint32_t chunk_count = 0;
  float max_error = 0.0f;
  uint32_t attributes = 0, color_components = 0, uv_count = 0, normal_count = 0;
  uint32_t material_count = 0, material_library_count = 0, material_string_bytes = 0;
  uint8_t position_bits = 0, uv_bits = 0, normal_bits = 0;
  uint32_t options = 0;

  uint64_t vertices() const { return uint64_t{base_vertex_count} + split_count + loose_vertex_count; }
  uint64_t faces() const { return uint64_t{base_face_count} + split_face_count + carried_face_count; }
  uint64_t split_vertices() const { return uint64_t{base_vertex_count} + split_count; }
  bool uv_ids() const { return (attributes & kAttributeUvIds) != 0; }
  bool normal_ids() const { return (attributes & kAttributeNormalIds) != 0; }
  bool material_ids() const { return (attributes & kAttributeMaterialIds) != 0; }
  // Per corner-attribute kind: its table's entries, its quantization bits (0: not on a grid),
  // whether the faces' corners have ids of it.
  uint32_t table_count(int kind) const { return kind == 0 ? uv_count : normal_count; }
  int table_bits(int kind) const { return kind == 0 ? uv_bits : normal_bits; }
  bool has_ids(int kind) const { return kind == 0 ? uv_ids() : normal_ids(); }
};

void append_header2(const Header2& h, std::string& out);
// §3.3: the header, once 96 bytes have arrived and the caller has seen major 2.
Status parse_header2(std::string_view bytes, Header2& h);

inline bool valid_bits(uint32_t bits) { return bits == 0 || (bits >= kMinBits && bits <= kMaxBits); }

inline Status corrupt(std::string message) { return Status(ErrorCode::kCorruptStream, std::move(message)); }

// ---------------------------------------------------------------------------------------
// Primitive codings (§5.1).

// A split's error as stored with WriteOptions::error_bits: the float's `bits` significant
// bits (the leading one and bits - 1 of its 23 stored ones), rounded up, so that it still
// bounds the level's distance to the input (a reader's choice of level by error only gets
// safer); 0 or 24 keep every bit. Rounding up keeps the errors' order, so they stay
// non-increasing along the stream (§5.6). A value that would round to infinity stays as is.
inline float stored_error(float error, int bits) {
  if (bits <= 0 || bits >= 24 || !(error > 0) || !std::isfinite(error)) return error;
  uint32_t b = 0;
  std::memcpy(&b, &error, sizeof b);
  const uint32_t below = (1u << (24 - bits)) - 1;  // the stored bits dropped
  if ((b & below) == 0) return error;
  b = (b | below) + 1;  // up to the next value with `bits` significant bits
  float rounded = 0;
  std::memcpy(&rounded, &b, sizeof rounded);
  return std::isfinite(rounded) ? rounded : error;
}

// Floats as unsigned integers in the order of their values (negative floats reversed), so
// that the difference of two near floats is a small integer whatever their signs and
// exponents. A bijection on bit patterns: NaN payloads and -0 survive.
inline uint32_t ordered_from_float(float value) {
  uint32_t bits;
  std::memcpy(&bits, &value, 4);
  return (bits & 0x80000000u) != 0 ? ~bits : bits | 0x80000000u;
}
inline float float_from_ordered(uint32_t ordered) {
  const uint32_t bits = (ordered & 0x80000000u) != 0 ? ordered & 0x7FFFFFFFu : ~ordered;
  float value;
  std::memcpy(&value, &bits, 4);
  return value;
}

// LEB128 of up to 64 bits (residuals, which may exceed 32 bits), canonical as varint.
inline void put_varint64(std::string& out, uint64_t value) {
  while (value >= 0x80) {
    out.push_back(static_cast<char>((value & 0x7F) | 0x80));
    value >>= 7;
  }
  out.push_back(static_cast<char>(value));
}
inline bool read_varint64(ByteReader& in, uint64_t& value) {
  uint64_t result = 0;
  for (int i = 0; i < 10; ++i) {
    uint8_t byte;
    if (!in.read_u8(byte)) return false;
    if (i == 9 && byte > 1) return in.fail(ErrorCode::kCorruptStream, in.where() + ": varint exceeds 64 bits");
    result |= uint64_t{byte & 0x7Fu} << (7 * i);
    if ((byte & 0x80) == 0) {
      if (byte == 0 && i > 0) return in.fail(ErrorCode::kCorruptStream, in.where() + ": overlong varint");
      value = result;
      return true;
    }
  }
  return false;
}

// Residual codes as byte planes (§5.7): a u8 plane count P, then the codes' lowest bytes,
// then their second bytes, ... P planes of count bytes each. Residuals of scanned or
// subdivided surfaces have random low bytes and skewed high ones: apart, zstd codes each
// plane with its own statistics, which varints would interleave. P is the fewest bytes
// that hold the largest code (at least 1), so that every list has one encoding.
inline void put_planes(std::string& out, const std::vector<uint64_t>& codes) {
  if (codes.empty()) return;
  uint64_t largest = 0;
  for (uint64_t code : codes) largest = std::max(largest, code);
  int planes = 1;
  while (planes < 8 && (largest >> (8 * planes)) != 0) ++planes;
  out.push_back(static_cast<char>(planes));
  for (int b = 0; b < planes; ++b) {
    for (uint64_t code : codes) out.push_back(static_cast<char>((code >> (8 * b)) & 0xFF));
  }
}
inline bool read_planes(ByteReader& in, std::size_t count, std::vector<uint64_t>& codes) {
  codes.assign(count, 0);
  if (count == 0) return true;
  uint8_t planes;
  if (!in.read_u8(planes)) return false;
  if (planes < 1 || planes > 8 || in.remaining() != planes * count) {
    return in.fail(ErrorCode::kCorruptStream, in.where() + ": " + std::to_string(planes) +
                                                  " byte planes of " + std::to_string(count) +
                                                  " codes do not fill its " +
                                                  std::to_string(in.remaining()) + " bytes");
  }
  bool top_used = planes == 1;
  for (int b = 0; b < planes; ++b) {
    std::string_view plane;
    in.read_bytes(count, plane);
    for (std::size_t i = 0; i < count; ++i) {
      const auto byte = static_cast<uint8_t>(plane[i]);
      codes[i] |= uint64_t{byte} << (8 * b);
      if (b == planes - 1 && byte != 0) top_used = true;
    }
  }
  if (!top_used) return in.fail(ErrorCode::kCorruptStream, in.where() + ": a byte plane more than the codes need");
  return true;
}

// A residual code as a difference, or false when it is beyond any difference of two u32
// values (so that adding it to one cannot overflow).
inline bool residual_of(uint64_t code, int64_t& difference) {
  if (code > (uint64_t{1} << 33)) return false;
  difference = unzigzag(code);
  return true;
}

// 2.1 (§5.10): the adaptive models of the chunks' range-coded streams, set up before the
// first chunk and carried from chunk to chunk (a reader decodes the chunks in order: each
// needs the mesh of the ones before; learning them afresh cost 1-3% more).
constexpr uint32_t kRingContexts = 21;    // ring sizes 1..19 apart, 20 and more together
constexpr uint32_t kSpreadContexts = 33;  // bit lengths 0..32 of the neighbours' spread
struct ChunkModels {
  BitModel restart;   // u: a new layer starts here
  EgModels u_gap[2];  // u: [0] a layer's first, [1] the others
  TreeModels vl[kRingContexts], vr[kRingContexts];
  EgModels vl_large, vr_large;  // rings of 63 faces or more
  // |residual| and sign, by the spread of the neighbours; [1]: the normal coordinate (§5.10)
  EgModels position[2][kSpreadContexts];
  BitModel sign[2][kSpreadContexts][3];  // and the side of the prediction from u: -, 0, +
};

// The number of bits of x (0 for 0): one instruction, not a loop (it sets contexts at every
// split).
inline uint32_t bit_length(uint64_t x) {
  return x == 0 ? 0 : 64 - static_cast<uint32_t>(__builtin_clzll(x));
}

// ---------------------------------------------------------------------------------------
// Chunk plan (§5.5): 256 splits, then doubling up to the writer's largest chunk, so that a
// stream cut early still refines, and big meshes have few chunks.
inline std::vector<uint32_t> plan_chunks(uint32_t splits, uint32_t largest) {
  return chunk_plan(splits, largest);
}

struct ChunkEntry {
  uint32_t splits = 0, new_faces = 0, moved_faces = 0;
  float error_after = 0;
};

// A chunk's fields (§5.5), each its own stream, in this order.
enum ChunkStream {
  kStreamU, kStreamVl, kStreamVr, kStreamExplicit, kStreamErrors, kStreamPositions,
  kStreamColors, kStreamMaterials, kStreamUvCodes, kStreamNormalCodes, kChunkStreams
};
constexpr const char* kStreamNames[kChunkStreams] = {
    "u", "vl", "vr", "explicit splits", "errors", "positions", "colours", "materials",
    "texture coordinate ids", "normal ids"};
// The stream of a corner-attribute kind's ids.
constexpr ChunkStream corner_code_stream(int kind) {
  return kind == 0 ? kStreamUvCodes : kStreamNormalCodes;
}

// The known sections of a stream with this header, in the order it must hold them (§4.3):
// each is present exactly when it has entries.
std::vector<uint32_t> expected_sections(const Header2& h);
bool is_v2_tag(uint32_t tag);
// The largest raw size the counts allow a section (§4.4), chunks aside (their bound needs
// the index: chunk_raw_bound).
uint64_t raw_bound(const Header2& h, uint32_t tag);
uint64_t chunk_raw_bound(const Header2& h, const ChunkEntry& c);

// §7.1: what decoding a stream with this header takes, beyond the raw buffer of the
// section being decoded.
struct MemoryPlan {
  uint64_t mesh = 0, decoding = 0, validating = 0;
  uint64_t needed(uint64_t largest_raw) const {
    return mesh + std::max(decoding + largest_raw, validating) + kDecodeMemorySlack;
  }
};
MemoryPlan plan_memory(const Header2& h);
Status memory_status(uint64_t needed, uint64_t limit);

// "section CHNK 3".
std::string section_name(uint32_t tag, std::size_t chunk);

// A face's material id, optional: 0 for none, else id + 1 (BASE, CARY, the chunks'
// materials stream).
inline void put_optional_id(ByteWriter& out, uint32_t id) {
  out.put_varint(id == kNoAttribute ? 0 : id + 1);
}
inline bool read_optional_id(ByteReader& in, uint32_t count, const char* what, uint32_t& id) {
  uint32_t code;
  if (!in.read_varint(code)) return false;
  if (code > count) {
    return in.fail(ErrorCode::kCorruptStream, in.where() + ": " + what + " " +
                                                  std::to_string(code - 1) + " of " +
                                                  std::to_string(count));
  }
  id = code == 0 ? kNoAttribute : code - 1;
  return true;
}

}  // namespace pm::detail::v2
