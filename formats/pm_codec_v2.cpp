// The .pm stream of format 2.0: a fixed header with a CRC-32, then zstd-compressed
// sections: the base mesh and what every level shares (BASE, WELD, CARY, TABL), an index of
// the chunks (INDX), the vertex splits in chunks of a few thousand (CHNK), and what only
// full detail has (LOOS, ORDR). formats/pm-format.md is normative; section numbers in
// comments (§) refer to it.
//
// Progressive by construction (Hoppe 1996, §3, "progressive transmission"): a reader
// decodes the sections as they arrive, so a stream cut anywhere after the base mesh gives
// the finest level it holds whole, and a reader that wants a coarse level stops after the
// chunks that hold it.
//
// Compact: a split names vl and vr by their places in u's ring of faces, and its moved
// faces are those between them (split_fans.h; Hoppe 1998, "Efficient implementation of
// progressive meshes", §4); the new vertex's position is predicted by the mean of its
// neighbours in the refined mesh (the "Laplacian" prediction of Taubin, Guéziec, Horn and
// Lazarus 1998, "Progressive forest split compression", §5) and stored as the difference,
// in the order-preserving integers of the float bits (lossless) or on a quantization grid
// (Deering 1995, "Geometry compression", §4: uniform quantization over a bounding box).
// Each field is a stream of its own in the chunk, which zstd compresses better than
// interleaved records.
//
// 2.1 (§5.10) codes four of those streams with an adaptive binary range coder
// (range_coder.h) instead of leaving them to zstd: u as the gap from the previous u of its
// layer (the encoder orders each chunk in layers of independent splits, by u: Pajarola and
// Rossignac 2000, "Compressed progressive meshes", §3), vl and vr with models per ring size,
// and the position residuals with models per neighbourhood spread, on a grid in u's normal
// frame (the coordinate along the normal predicted from the other two): zstd sees bytes,
// not the distributions these fields have. 2.0 streams are still read (and written on request).
//
// The reader trusts nothing, as the 1.x reader: every count is capped, every section header
// is checked before its payload is decompressed, the memory a decode needs is computed from
// checked numbers before it is allocated, and the decoded mesh goes through validate()
// (less its replay of the moved faces, which decoding did: validate_decoded.h).
#include <zstd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <new>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include "byte_io.h"
#include "corner_codes.h"
#include "wedge_codes.h"
#include "stream_order/attribute_renumbering.h"
#include "core/huge_pages.h"
#include "core/in_turn.h"
#include "pm/pm_codec.h"
#include "pm_layout.h"
#include "range_coder.h"
#include "significant_decimals.h"
#include "split_fans.h"
#include "levels/validate_decoded.h"

namespace pm {
namespace detail {
namespace {

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
};

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

bool valid_bits(uint32_t bits) { return bits == 0 || (bits >= kMinBits && bits <= kMaxBits); }

Status corrupt(std::string message) { return Status(ErrorCode::kCorruptStream, std::move(message)); }

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

// ---------------------------------------------------------------------------------------
// Primitive codings (§5.1).

// A split's error as stored with WriteOptions::error_bits: the float's `bits` significant
// bits (the leading one and bits - 1 of its 23 stored ones), rounded up, so that it still
// bounds the level's distance to the input (a reader's choice of level by error only gets
// safer); 0 or 24 keep every bit. Rounding up keeps the errors' order, so they stay
// non-increasing along the stream (§5.6). A value that would round to infinity stays as is.
float stored_error(float error, int bits) {
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
uint32_t ordered_from_float(float value) {
  uint32_t bits;
  std::memcpy(&bits, &value, 4);
  return (bits & 0x80000000u) != 0 ? ~bits : bits | 0x80000000u;
}
float float_from_ordered(uint32_t ordered) {
  const uint32_t bits = (ordered & 0x80000000u) != 0 ? ordered & 0x7FFFFFFFu : ~ordered;
  float value;
  std::memcpy(&value, &bits, 4);
  return value;
}

// LEB128 of up to 64 bits (residuals, which may exceed 32 bits), canonical as varint.
void put_varint64(std::string& out, uint64_t value) {
  while (value >= 0x80) {
    out.push_back(static_cast<char>((value & 0x7F) | 0x80));
    value >>= 7;
  }
  out.push_back(static_cast<char>(value));
}
bool read_varint64(ByteReader& in, uint64_t& value) {
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
void put_planes(std::string& out, const std::vector<uint64_t>& codes) {
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
bool read_planes(ByteReader& in, std::size_t count, std::vector<uint64_t>& codes) {
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
bool residual_of(uint64_t code, int64_t& difference) {
  if (code > (uint64_t{1} << 33)) return false;
  difference = unzigzag(code);
  return true;
}

// ---------------------------------------------------------------------------------------
// Quantization grids (§5.3): origin + q * step, q in [0, 2^bits); or, lossless (2.3), the
// decimals with `decimals` places after the point from first / 10^decimals on.

constexpr int64_t kMaxDecimalFirst = int64_t{1} << 52;  // |first|: first + q exact in a double

struct Grid {
  int bits = 0;                 // 0: no quantization
  std::vector<float> origin;    // per component
  float step = 1.0f;
  int decimals = -1;            // a decimal grid when >= 0 (2.3)
  std::vector<int64_t> first;   // per component, of a decimal grid

  // The value of index q: as a float, (float)value(q, c) (§5.3). A decimal's division by an
  // exact power of 10 is correctly rounded, so every reader gets the same float.
  double value(uint32_t q, std::size_t component) const {
    if (decimals >= 0) return static_cast<double>(first[component] + q) / kPowersOf10[decimals];
    return double{origin[component]} + static_cast<double>(q) * double{step};
  }
};

// 2.3 (§5.3): how many bits coarser a decimal step of 2^log2_step is than the float step
// above |x| (+0's is the smallest subnormal), within +-16: the writer's estimate of what
// coding x as that decimal saves over its float bits.
double bits_coarser(double log2_step, float x) {
  const float a = std::fabs(x);
  const float ulp = std::nextafter(a, std::numeric_limits<float>::infinity()) - a;  // a power of 2
  return std::clamp(log2_step - std::ilogb(ulp), -16.0, 16.0);
}

// 2.3, lossless (§5.3): a decimal grid for the `components`-vectors `values`, when each is
// exactly the float of a decimal with a few places after the point (as text formats write
// them: "0.037830"), within kMaxDecimalBits of range, and coarser than the floats' own steps
// where most values lie (then the grid's residuals are smaller than those of the float bits;
// on the bunny, 6 places and 18 bits, about a third of the stream). False otherwise.
bool make_decimal_grid(const float* values, std::size_t count, std::size_t components, Grid& grid,
                       double& gain) {
  if (count == 0) return false;
  int decimals = 0;
  std::vector<int64_t> low(components), high(components);  // of the decimals, per component
  for (;; ++decimals) {
    if (decimals > kMaxDecimals) return false;
    const double scale = kPowersOf10[decimals];
    bool exact = true;
    for (std::size_t i = 0; i < count * components && exact; ++i) {
      const float x = values[i];
      const double k = std::nearbyint(double{x} * scale);
      exact = std::isfinite(x) && std::fabs(k) < double(kMaxDecimalFirst);
      if (!exact) break;
      const auto back = static_cast<float>(static_cast<double>(static_cast<int64_t>(k)) / scale);
      exact = std::memcmp(&back, &x, sizeof x) == 0;  // -0 is not a decimal's float
      const std::size_t c = i % components;
      const auto decimal = static_cast<int64_t>(k);
      if (i < components || decimal < low[c]) low[c] = decimal;
      if (i < components || decimal > high[c]) high[c] = decimal;
    }
    if (exact) break;
  }
  const double scale = kPowersOf10[decimals];
  uint64_t extent = 0;
  for (std::size_t c = 0; c < components; ++c) {
    extent = std::max(extent, static_cast<uint64_t>(high[c] - low[c]));
  }
  int bits = kMinBits;
  while (bits <= kMaxDecimalBits && (extent >> bits) != 0) ++bits;
  if (bits > kMaxDecimalBits) return false;
  // Worth it where the grid's step is coarser than the floats' (log2 of the ratio, each value
  // counted within +-16).
  const double log_step = -std::log2(scale);
  gain = 0;
  for (std::size_t i = 0; i < count * components; ++i) gain += bits_coarser(log_step, values[i]);
  if (!(gain > 0)) return false;
  grid.bits = bits;
  grid.decimals = decimals;
  grid.first = low;
  grid.origin.assign(components, 0.0f);
  grid.step = 1.0f;
  return true;
}

// The float a value's integer `unit` stands for (§5.6): a grid index (grid set), a number of
// significant decimals (2.3, significant set), else ordered float bits; false when it stands
// for none (significant decimals only).
bool float_of_unit(const Grid* grid, const SignificantDecimals* significant, uint32_t unit,
                   std::size_t c, float& out) {
  if (significant != nullptr) return significant->to_float(unit, out);
  out = grid != nullptr ? static_cast<float>(grid->value(unit, c)) : float_from_ordered(unit);
  return true;
}

// The decimal of `digits` significant digits whose float is x (m, k), or false.
bool significant_decimal(float x, int digits, int64_t& m, int& k) {
  if (!std::isfinite(x) || x == 0) return false;
  const double a = std::fabs(double{x});
  const auto low = static_cast<int64_t>(kPowersOf10[digits - 1]), high = 10 * low;
  k = static_cast<int>(std::floor(std::log10(a))) - digits + 1;
  for (int attempt = 0; attempt < 3; ++attempt) {
    if (k < kMinExponent || k > kMaxExponent) return false;
    m = static_cast<int64_t>(std::nearbyint(a * std::pow(10.0, -k)));  // a guess: checked below
    if (m >= high) {
      ++k;
    } else if (m < low) {
      --k;
    } else {
      const double value = scaled_decimal(double(m), k);
      const auto back = static_cast<float>(x < 0 ? -value : value);
      return std::memcmp(&back, &x, sizeof x) == 0;
    }
  }
  return false;
}

// 2.3, lossless (§5.3): the fewest significant digits whose decimals give every value back
// bit for bit (+0 has a number, -0 none), and each value's unit, when those decimals are
// coarser than the floats' own steps where most values lie (as make_decimal_grid decides).
// False otherwise.
bool make_significant_decimals(const float* values, std::size_t count, SignificantDecimals& out,
                               std::vector<uint32_t>& units, double& gain) {
  if (count == 0) return false;
  std::vector<int> exponents(count);
  std::vector<int64_t> mantissas(count);
  int digits = 1;
  // 9 digits give back every float, in steps finer than the float's own: they never pay
  // (and trying them would read every value once more, where nothing is a short decimal).
  for (;; ++digits) {
    if (digits >= kMaxSignificantDigits) return false;
    bool exact = true;
    for (std::size_t i = 0; i < count && exact; ++i) {
      const float x = values[i];
      if (x == 0) {
        exact = !std::signbit(x);
        continue;
      }
      exact = significant_decimal(x, digits, mantissas[i], exponents[i]);
    }
    if (exact) break;
  }
  int first = kMaxExponent;
  gain = 0;
  for (std::size_t i = 0; i < count; ++i) {
    if (values[i] == 0) {
      gain += bits_coarser(0, values[i]);  // +0: 16, as on a grid
      continue;
    }
    first = std::min(first, exponents[i]);
    gain += bits_coarser(double(exponents[i]) * std::log2(10.0), values[i]);
  }
  if (!(gain > 0)) return false;
  const auto low = static_cast<int64_t>(kPowersOf10[digits - 1]);
  units.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    int64_t n = 0;
    if (values[i] != 0) n = (exponents[i] - first) * 9 * low + (mantissas[i] - low) + 1;
    if (n >= (int64_t{1} << 31)) return false;  // decades too far apart
    units[i] = static_cast<uint32_t>((int64_t{1} << 31) + (values[i] < 0 ? -n : n));
  }
  out.digits = digits;
  out.first_exponent = first;
  return true;
}

// The grid of `components`-vectors `values` (count of them), over their bounding box's
// longest side. False when a value is not finite.
bool make_grid(const float* values, std::size_t count, std::size_t components, int bits,
               Grid& grid) {
  grid.bits = bits;
  grid.origin.assign(components, 0.0f);
  std::vector<float> top(components, 0.0f);
  for (std::size_t i = 0; i < count; ++i) {
    for (std::size_t c = 0; c < components; ++c) {
      const float x = values[components * i + c];
      if (!std::isfinite(x)) return false;
      if (i == 0 || x < grid.origin[c]) grid.origin[c] = x;
      if (i == 0 || x > top[c]) top[c] = x;
    }
  }
  double extent = 0;
  for (std::size_t c = 0; c < components; ++c) {
    extent = std::max(extent, double{top[c]} - double{grid.origin[c]});
  }
  const double steps = double((uint32_t{1} << bits) - 1);
  grid.step = extent > 0 ? static_cast<float>(extent / steps) : 1.0f;
  if (!(grid.step > 0) || !std::isfinite(grid.step)) grid.step = 1.0f;
  return true;
}

uint32_t quantize(const Grid& grid, float x, std::size_t component) {
  const double top = double((uint32_t{1} << grid.bits) - 1);
  if (grid.decimals >= 0) {  // exact: make_decimal_grid checked every value
    const double k = std::nearbyint(double{x} * kPowersOf10[grid.decimals]);
    return static_cast<uint32_t>(std::clamp(k - double(grid.first[component]), 0.0, top));
  }
  const double q = std::nearbyint((double{x} - double{grid.origin[component]}) / double{grid.step});
  return static_cast<uint32_t>(std::clamp(q, 0.0, top));
}

void put_grid(ByteWriter& out, const Grid& grid) {
  if (grid.decimals >= 0) {  // 2.3 (§5.3)
    out.put_u8(static_cast<uint8_t>(grid.decimals));
    for (int64_t k : grid.first) out.put_u64(static_cast<uint64_t>(k));
    return;
  }
  for (float x : grid.origin) out.put_f32(x);
  out.put_f32(grid.step);
}
bool read_grid(ByteReader& in, int bits, std::size_t components, Grid& grid, bool decimal = false) {
  grid.bits = bits;
  if (decimal) {  // 2.3 (§5.3)
    uint8_t decimals = 0;
    if (!in.read_u8(decimals)) return false;
    if (decimals > kMaxDecimals) {
      return in.fail(ErrorCode::kCorruptStream, in.where() + ": a decimal grid of " +
                                                    std::to_string(decimals) + " places (at most 15)");
    }
    grid.decimals = decimals;
    grid.first.assign(components, 0);
    grid.origin.assign(components, 0.0f);
    for (int64_t& k : grid.first) {
      uint64_t bits64 = 0;
      if (!in.read_u64(bits64)) return false;
      k = static_cast<int64_t>(bits64);
      if (k <= -kMaxDecimalFirst || k >= kMaxDecimalFirst) {
        return in.fail(ErrorCode::kCorruptStream, in.where() + ": a decimal grid's first value is beyond 2^52");
      }
    }
    return true;
  }
  grid.origin.assign(components, 0.0f);
  for (float& x : grid.origin) {
    if (!in.read_f32(x)) return false;
  }
  if (!in.read_f32(grid.step)) return false;
  for (float x : grid.origin) {
    if (!std::isfinite(x)) return in.fail(ErrorCode::kCorruptStream, in.where() + ": grid origin is not finite");
  }
  if (!(grid.step > 0) || !std::isfinite(grid.step)) {
    return in.fail(ErrorCode::kCorruptStream, in.where() + ": grid step is not a positive number");
  }
  return true;
}

// 2.3 (§5.3, §5.4): significant decimals' record, u8 digits and i8 first exponent.
void put_significant(ByteWriter& out, const SignificantDecimals& significant) {
  out.put_u8(static_cast<uint8_t>(significant.digits));
  out.put_u8(static_cast<uint8_t>(static_cast<int8_t>(significant.first_exponent)));
}
bool read_significant(ByteReader& in, SignificantDecimals& out) {
  uint8_t digits = 0, exponent = 0;
  if (!in.read_u8(digits) || !in.read_u8(exponent)) return false;
  const int first_exponent = static_cast<int8_t>(exponent);
  if (digits < 1 || digits > kMaxSignificantDigits || first_exponent < kMinExponent ||
      first_exponent > kMaxExponent) {
    return in.fail(ErrorCode::kCorruptStream, in.where() + ": significant decimals of " +
                                                  std::to_string(digits) + " digits from 10^" +
                                                  std::to_string(first_exponent));
  }
  out.digits = digits;
  out.first_exponent = first_exponent;
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
uint32_t bit_length(uint64_t x) {
  return x == 0 ? 0 : 64 - static_cast<uint32_t>(__builtin_clzll(x));
}

// A ring code (vl's or vr's, 0 .. n + 1 for a fan of n faces): a binary tree of
// bit_length(n + 1) bits with the models of its ring size, or exp-Golomb for rings of 63
// faces or more.
void put_ring_code(RangeEncoder& rc, TreeModels* trees, EgModels& large, std::size_t n,
                   uint32_t code) {
  const uint32_t bits = bit_length(uint64_t{n} + 1);
  if (bits <= kTreeBits) {
    put_tree(rc, trees[std::min<std::size_t>(n, kRingContexts - 1)], static_cast<int>(bits), code);
  } else {
    put_eg(rc, large, code);
  }
}

bool get_ring_code(RangeDecoder& rc, TreeModels* trees, EgModels& large, std::size_t n,
                   uint32_t& code) {
  const uint32_t bits = bit_length(uint64_t{n} + 1);
  if (bits <= kTreeBits) {
    code = get_tree(rc, trees[std::min<std::size_t>(n, kRingContexts - 1)], static_cast<int>(bits));
    return true;
  }
  uint64_t value = 0;
  if (!get_eg(rc, large, value) || value > 0xFFFFFFFFu) return false;
  code = static_cast<uint32_t>(value);
  return true;
}

// ---------------------------------------------------------------------------------------
// Values per vertex (positions, colours) in the integers their residuals are taken in
// (§5.6): the ordered float bits when lossless, the grid index when quantized.

struct VertexValues {
  std::size_t components = 3;
  const Grid* grid = nullptr;       // quantized when set
  const SignificantDecimals* significant = nullptr;  // 2.3: lossless decimals' numbers when set
  bool mean_of_values = false;  // 2.4: significant decimals predicted by their values' mean

  // Whether the normal frame applies (§5.10): on a grid (2.1), of significant decimals (2.4).
  bool has_frames() const { return grid != nullptr || (significant != nullptr && mean_of_values); }
  std::vector<uint32_t> units;      // components per vertex, as decoded or encoded so far

  // False when `unit` stands for no value (significant decimals only).
  bool to_float(uint32_t unit, std::size_t c, float& out) const {
    return float_of_unit(grid, significant, unit, c, out);
  }
  uint32_t from_float(float x, std::size_t c) const {
    return grid != nullptr ? quantize(*grid, x, c) : ordered_from_float(x);
  }

  // 2.1 (§5.10): the context of a residual, the bit length of the neighbours' mean absolute
  // deviation from the prediction in that coordinate: where the ring is wide, residuals are
  // large, so each scale of the surface gets its own statistics.
  uint32_t spread_context(const uint32_t* neighbours, std::size_t count, uint32_t predicted,
                          std::size_t c) const {
    uint64_t sum = 0;
    for (std::size_t k = 0; k < count; ++k) {
      const int64_t d = int64_t{units[components * neighbours[k] + c]} - int64_t{predicted};
      sum += static_cast<uint64_t>(d < 0 ? -d : d);
    }
    return std::min<uint32_t>(bit_length(sum / count), kSpreadContexts - 1);
  }

  // The prediction of a new vertex from its neighbours in the refined mesh (Taubin et al.
  // 1998, §5): their mean, in the grid's integers, or in double then rounded to float (when
  // the mean is not finite, the first neighbour's value, which is u's); significant decimals
  // (2.4) as the number nearest to their values' mean (2.3: their numbers' mean).
  void predict(const uint32_t* neighbours, std::size_t count, uint32_t* out) const {
    for (std::size_t c = 0; c < components; ++c) {
      const auto unit_at = [&](std::size_t k) { return units[components * neighbours[k] + c]; };
      if (significant != nullptr && mean_of_values) {
        const int64_t scale = significant->scale_of(count, unit_at);
        __int128 sum = 0;
        for (std::size_t k = 0; k < count; ++k) sum += significant->linear(unit_at(k), scale);
        out[c] = significant->nearest(rounded_quotient(sum, static_cast<__int128>(count)), scale);
      } else if (grid != nullptr || significant != nullptr) {  // 2.3's significant decimals too
        uint64_t sum = 0;
        for (std::size_t k = 0; k < count; ++k) sum += unit_at(k);
        out[c] = static_cast<uint32_t>((2 * sum + count) / (2 * count));
      } else {
        double sum = 0;
        for (std::size_t k = 0; k < count; ++k) {
          sum += double{float_from_ordered(units[components * neighbours[k] + c])};
        }
        const auto mean = static_cast<float>(sum / double(count));
        out[c] = std::isfinite(mean) ? ordered_from_float(mean)
                                     : units[components * neighbours[0] + c];
      }
    }
  }
};

// 2.1, positions on a grid (§5.10): u's normal, from its fan of faces in the grid's integers
// (the sum of the faces' cross products at u, scaled down to 15 bits), and the coordinate
// most along it. A split's new vertex lies close to the tangent plane at u, while the mean of
// its neighbours lies off it where the surface is curved, so the residuals across the
// surface are about three times those along the normal (measured on the bunny: 59 against
// 20 grid steps at 14 bits). The two tangential coordinates are coded first; the normal one
// is then predicted from them, so that the residual vector's normal component is a quarter
// of the prediction's offset from u's plane, with the sign reversed (the least squares fit
// on the shared meshes is -0.6 to -0.75). Integers only, so that every reader gets the same.
struct NormalFrame {
  int64_t n[3] = {0, 0, 0};
  int order[3] = {0, 1, 2};  // tangential, tangential, normal
};

constexpr std::size_t kMaxNormalFan = 1024;  // larger fans (none in practice) go without

// The offsets (ring vertex - u) that lopsided_place and normal_frame read, as offset(k, c)
// for ring[k] (k up to n, so that a closed fan's last face finds its second vertex), in
// integers that are linear in the positions' values: on a grid its indices' differences
// (2.3's decimal grids of more than 24 bits divided by 2^(bits - 24), truncating towards
// zero, so that products stay as small as on 24-bit grids); lossless float bits' differences
// divided by 256 (lopsided_place only); and 2.4's significant decimals (§5.3) as their
// values, u's and the ring's on one scale, then halved together (truncating towards zero)
// until each is below 2^24, computed into `scratch`. `use` gets the offsets as a function
// object, one type per case, so that the common ones read the values directly and divide by
// constants (a division by a variable is slow).
template <typename Use>
auto with_fan_offsets(const VertexValues& positions, uint32_t u, const SplitFans::Fan& fan,
                      std::vector<int64_t>& scratch, Use use) {
  const uint32_t* units = positions.units.data();
  const uint32_t* at_u = units + 3 * std::size_t{u};
  const uint32_t* ring = fan.ring.data();
  if (positions.significant != nullptr && positions.mean_of_values) {
    const std::size_t n = fan.ring.size();
    scratch.resize(3 * n);
    const SignificantDecimals& numbers = *positions.significant;
    const auto unit_at = [&](std::size_t k) {
      return k < 3 ? at_u[k] : units[3 * std::size_t{ring[k / 3 - 1]} + k % 3];
    };
    const int64_t scale = numbers.scale_of(3 * (n + 1), unit_at);
    int64_t origin[3];
    for (int c = 0; c < 3; ++c) origin[c] = numbers.linear(at_u[c], scale);
    for (std::size_t k = 0; k < 3 * n; ++k) scratch[k] = numbers.linear(unit_at(k + 3), scale) - origin[k % 3];
    halve_below(scratch.data(), scratch.size(), kMaxBits);
    const int64_t* table = scratch.data();
    return use([table](std::size_t k, int c) { return table[3 * k + c]; });
  }
  const auto difference = [units, at_u, ring](std::size_t k, int c) {
    return int64_t{units[3 * std::size_t{ring[k]} + c]} - int64_t{at_u[c]};
  };
  if (positions.grid == nullptr) {
    return use([difference](std::size_t k, int c) { return difference(k, c) / 256; });
  }
  const int64_t divisor = int64_t{1} << std::max(0, positions.grid->bits - kMaxBits);
  if (divisor == 1) return use(difference);
  return use([difference, divisor](std::size_t k, int c) { return difference(k, c) / divisor; });
}

// On a grid (2.1) or of significant decimals (2.4): u's normal and its order of coordinates.
template <typename Offset>
bool normal_frame_of(const Offset& offset, const SplitFans::Fan& fan, NormalFrame& out) {
  int64_t n[3] = {0, 0, 0};
  int64_t e1[3], e2[3];  // face k's edges from u: to ring[k] and ring[k + 1]
  for (int c = 0; c < 3; ++c) e1[c] = offset(0, c);
  for (std::size_t k = 0; k < fan.faces.size(); ++k) {
    for (int c = 0; c < 3; ++c) e2[c] = offset(k + 1, c);
    // Each product is below 2^48 (each offset below 2^24), each sum of 1024 below 2^60.
    n[0] += e1[1] * e2[2] - e1[2] * e2[1];
    n[1] += e1[2] * e2[0] - e1[0] * e2[2];
    n[2] += e1[0] * e2[1] - e1[1] * e2[0];
    for (int c = 0; c < 3; ++c) e1[c] = e2[c];
  }
  const auto magnitude = [](int64_t x) { return x < 0 ? -x : x; };
  halve_below(n, 3, 15);
  int normal = 0;
  for (int c = 1; c < 3; ++c) {
    if (magnitude(n[c]) > magnitude(n[normal])) normal = c;
  }
  if (n[normal] == 0) return false;
  for (int c = 0; c < 3; ++c) out.n[c] = n[c];
  out.order[0] = normal == 0 ? 1 : 0;
  out.order[1] = normal == 2 ? 1 : 2;
  out.order[2] = normal;
  return true;
}

bool normal_frame(const VertexValues& positions, uint32_t u, const SplitFans::Fan& fan,
                  std::vector<int64_t>& scratch, NormalFrame& out) {
  if (fan.faces.empty() || fan.faces.size() > kMaxNormalFan) return false;
  return with_fan_offsets(positions, u, fan, scratch,
                          [&](const auto& offset) { return normal_frame_of(offset, fan, out); });
}

// The normal coordinate's prediction offset, from the tangential residuals r[order[0]],
// r[order[1]] and d = prediction - u: the nearest integer to
// -(3 (d . n) + 4 (n_a r_a + n_b r_b)) / (4 n_c), halves away from minus infinity.
int64_t normal_offset(const NormalFrame& f, const int64_t* d, const int64_t* r, int bits) {
  const int a = f.order[0], b = f.order[1], c = f.order[2];
  // |d|, |r| < 2^30 (2^24 but on 2.3's decimal grids) and |n| < 2^15: every term below 2^49.
  int64_t num =
      -(3 * (d[0] * f.n[0] + d[1] * f.n[1] + d[2] * f.n[2]) + 4 * (f.n[a] * r[a] + f.n[b] * r[b]));
  int64_t den = 4 * f.n[c];
  if (den < 0) num = -num, den = -den;
  const int64_t twice = 2 * num + den, q = twice / (2 * den);
  const int64_t offset = (twice % (2 * den) != 0 && twice < 0) ? q - 1 : q;  // floor
  const int64_t limit = int64_t{1} << std::max(bits, kMaxBits);  // beyond any grid: clamped
  return std::clamp(offset, -limit, limit);
}

// 2.4 (§5.10), significant decimals: the normal coordinate c's prediction, the number nearest
// to predicted[c]'s value plus normal_offset's of the values: d = predicted - u and the
// tangential residuals r = v - predicted, all (u's, predicted's and v's two coded coordinates)
// on one scale (§5.3); the offset's terms in 128 bits, it clamped to +-10^18.
uint32_t normal_prediction_of_values(const SignificantDecimals& numbers, const NormalFrame& f,
                                     const uint32_t* u, const uint32_t* predicted, const uint32_t* v) {
  const int a = f.order[0], b = f.order[1], c = f.order[2];
  const uint32_t eight[8] = {u[0], u[1], u[2], predicted[0], predicted[1], predicted[2], v[a], v[b]};
  const int64_t scale = numbers.scale_of(8, [&](std::size_t k) { return eight[k]; });
  const auto linear = [&](uint32_t unit) { return static_cast<__int128>(numbers.linear(unit, scale)); };
  __int128 num = 0;
  for (int k = 0; k < 3; ++k) num += 3 * (linear(predicted[k]) - linear(u[k])) * f.n[k];
  num += 4 * (f.n[a] * (linear(v[a]) - linear(predicted[a])) + f.n[b] * (linear(v[b]) - linear(predicted[b])));
  num = -num;
  __int128 den = 4 * static_cast<__int128>(f.n[c]);
  if (den < 0) num = -num, den = -den;
  constexpr __int128 kLimit = 1000000000000000000;  // 10^18
  const __int128 offset = std::clamp(rounded_quotient(num, den), -kLimit, kLimit);
  return numbers.nearest(linear(predicted[c]) + offset, scale);
}

// 2.1 (§5.10): where a closed fan's places start. A collapse v -> u hands v's faces to u, so
// u's ring is lopsided towards where v was: the ring vertex furthest along the mean of
// (ring vertex - u) is near the middle of the arc the split takes back, and vl's place
// counted from it is far from uniform (on the bunny at 14 bits, 2.4 bits instead of 2.9).
// Integers only (differences of values, divided by 256 when lossless, where the values are
// 32-bit), the first of equal scores.
template <typename Offset>
std::size_t lopsided_place_of(const Offset& diff, const SplitFans::Fan& fan) {
  const std::size_t n = fan.faces.size();
  // The offsets of a fan of up to kKept faces (nearly all) are kept for the second pass.
  constexpr std::size_t kKept = 16;
  int64_t kept[3 * kKept];
  const bool keep = n <= kKept;
  int64_t direction[3] = {0, 0, 0};  // below 2^34
  for (std::size_t k = 0; k < n; ++k) {
    for (int c = 0; c < 3; ++c) {
      const int64_t d = diff(k, c);
      if (keep) kept[3 * k + c] = d;
      direction[c] += d;
    }
  }
  std::size_t best = 0;
  int64_t best_score = 0;
  for (std::size_t k = 0; k < n; ++k) {
    int64_t score = 0;  // three products below 2^58
    for (int c = 0; c < 3; ++c) score += (keep ? kept[3 * k + c] : diff(k, c)) * direction[c];
    if (k == 0 || score > best_score) best = k, best_score = score;
  }
  return best;
}

std::size_t lopsided_place(const VertexValues& positions, uint32_t u, const SplitFans::Fan& fan,
                           std::vector<int64_t>& scratch) {
  if (fan.faces.size() > kMaxNormalFan) return 0;
  return with_fan_offsets(positions, u, fan, scratch,
                          [&](const auto& offset) { return lopsided_place_of(offset, fan); });
}

// ---------------------------------------------------------------------------------------
// Chunk plan (§5.5): 256 splits, then doubling up to the writer's largest chunk, so that a
// stream cut early still refines, and big meshes have few chunks.

// 2.4 (§5.11): the split's moved faces with u's place in each, for the wedge coders.
void arc_faces(const SplitFans& fans, uint32_t u, const std::vector<uint32_t>& arc,
               std::vector<WedgeCoder::ArcFace>& out) {
  out.clear();
  for (uint32_t f : arc) out.push_back({f, fans.face(f), fans.slot_of(f, u)});
}

std::vector<uint32_t> plan_chunks(uint32_t splits, uint32_t largest) {
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

// §7.1: what decoding a stream with this header takes, beyond the raw buffer of the
// section being decoded.
struct MemoryPlan {
  uint64_t mesh = 0, decoding = 0, validating = 0;
  uint64_t needed(uint64_t largest_raw) const {
    return mesh + std::max(decoding + largest_raw, validating) + kDecodeMemorySlack;
  }
};
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

// ---------------------------------------------------------------------------------------
// Writer.

void put_optional_id(ByteWriter& out, uint32_t id) {
  out.put_varint(id == kNoAttribute ? 0 : id + 1);
}

// A value table (UVs or normals), f32 or on a grid (§5.4).
// One table value, component c: f32, or its grid index (§5.4).
void put_table_value(ByteWriter& out, const Grid* grid, float x, std::size_t c) {
  if (grid == nullptr) {
    out.put_f32(x);
  } else {
    out.put_varint(quantize(*grid, x, c));
  }
}

void put_table(ByteWriter& out, const std::vector<float>& values, std::size_t components,
               const Grid* grid) {
  if (grid != nullptr) put_grid(out, *grid);
  for (std::size_t i = 0; i < values.size(); ++i) put_table_value(out, grid, values[i], i % components);
}

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

  const std::vector<float>& table(int kind) const { return kind == 0 ? pm.uvs : pm.normals; }
  const Grid& grid(int kind) const { return kind == 0 ? uv_grid : normal_grid; }
  bool has_ids(int kind) const { return kind == 0 ? pm.has_uvs() : pm.has_normals(); }
  // The error bound of the level before split i as stored (WriteOptions::error_bits): split
  // i's, the full mesh's 0 after the last; the header, the index and the errors stream alike.
  float error_before(std::size_t i) const {
    return i < pm.splits.size() ? stored_error(pm.splits[i].error, options.error_bits) : 0.0f;
  }
  // Entry `id`'s values in the integers residuals are taken in: grid indices or float bits.
  void units_of(int kind, uint32_t id, uint32_t* out) const {
    const std::size_t components = kind == 0 ? 2 : 3;
    for (std::size_t c = 0; c < components; ++c) {
      const std::size_t at = components * std::size_t{id} + c;
      if (table_significant[kind].digits != 0) {
        out[c] = table_numbers[kind][at];  // 2.3 (§5.4)
      } else {
        out[c] = grid(kind).bits != 0 ? quantize(grid(kind), table(kind)[at], c)
                                      : ordered_from_float(table(kind)[at]);
      }
    }
  }

  void plan_tables() {
    const std::size_t base_corners = pm.base_faces.size();
    const std::size_t carried_first = 3 * (pm.total_face_count() - pm.carried_faces.size() / 3);
    for (int kind = 0; kind < 2; ++kind) {
      const std::size_t count = kind == 0 ? pm.uv_count() : pm.normal_count();
      std::vector<uint8_t> early(count, 0), used(count, 0);
      if (has_ids(kind)) {
        const std::vector<uint32_t>& ids = kind == 0 ? pm.face_uvs : pm.face_normals;
        const std::vector<uint32_t>& moved = kind == 0 ? pm.moved_uvs : pm.moved_normals;
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
  void put_listed(ByteWriter& out, int kind) {
    const std::size_t components = kind == 0 ? 2 : 3;
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
          out.put_f32(table(kind)[components * id + c]);
        }
      }
    }
  }

  // 2.2: the wedge coders, having seen the listed values and the corners before the splits.
  void start_wedges() {
    const std::size_t level_faces = pm.base_face_count() + h.split_face_count;
    const std::size_t carried_first = 3 * (pm.total_face_count() - pm.carried_faces.size() / 3);
    for (int kind = 0; kind < 2; ++kind) {
      if (!has_ids(kind)) continue;
      const std::size_t components = kind == 0 ? 2 : 3;
      const uint32_t count = static_cast<uint32_t>(kind == 0 ? pm.uv_count() : pm.normal_count());
      const uint64_t top = grid(kind).bits != 0 ? (uint64_t{1} << grid(kind).bits) - 1 : 0xFFFFFFFFull;
      WedgeCoder& coder = wedges[kind];
      coder.reset(components, count, top, h.split_vertices(), level_faces);
      if (h.minor >= 4) {  // 2.4 (§5.11)
        coder.predict_by_values(positions.significant, in_use(table_significant[kind]));
      }
      uint32_t units[3];
      for (uint32_t id = 0; id < count; ++id) {
        if (listed[kind][id] == 0) continue;
        units_of(kind, id, units);
        coder.learn(id, units);
      }
      const std::vector<uint32_t>& ids = kind == 0 ? pm.face_uvs : pm.face_normals;
      for (std::size_t slot = 0; slot < pm.base_faces.size(); ++slot) {
        coder.pass(pm.base_faces[slot], ids[slot], true);
      }
      for (std::size_t k = 0; k < pm.carried_faces.size(); ++k) {
        coder.pass(pm.carried_faces[k], ids[carried_first + k], false);
      }
    }
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

  void put_positions(ByteWriter& out, uint32_t first, uint32_t count) {
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

  std::string base() {
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

  std::string carried() {
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

  std::string welds() {
    std::string raw;
    ByteWriter out(raw);
    for (const Weld& weld : pm.welds) {
      out.put_varint(weld.copy);
      out.put_varint(weld.canonical);
    }
    return raw;
  }

  std::string tables() {
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

  // The input's order (§5.9): the vertex id of each input vertex, the face id of each input
  // triangle.
  std::string order() {
    std::string raw;
    ByteWriter out(raw);
    for (uint32_t v : pm.input_vertices) out.put_varint(v);
    for (uint32_t f : pm.input_faces) out.put_varint(f);
    return raw;
  }

  std::string loose() {
    std::string raw;
    ByteWriter out(raw);
    put_positions(out, pm.base_vertex_count + static_cast<uint32_t>(pm.splits.size()),
                  pm.loose_vertex_count);
    return raw;
  }

  // The chunks and their index (§5.5, §5.6), replaying the splits on the fans.
  void chunks(std::vector<std::string>& raws, std::string& index) {
    SplitFans fans;
    fans.reset(h.split_vertices(), uint64_t{h.base_face_count} + h.split_face_count);
    for (std::size_t f = 0; f < pm.base_face_count(); ++f) {
      fans.add_face(pm.base_faces[3 * f], pm.base_faces[3 * f + 1], pm.base_faces[3 * f + 2]);
    }
    SplitFans::Fan fan;
    SplitFans::Prefetch prefetch(fans, &positions.units);
    for (std::size_t k = 0; k < SplitFans::Prefetch::kAhead; ++k)
      prefetch.step(k < pm.splits.size() ? pm.splits[k].u : SplitFans::kNone);
    std::vector<uint32_t> arc, record, sorted_arc, sorted_record, neighbours;
    std::vector<WedgeCoder::ArcFace> arc_sides;
    std::vector<int64_t> offsets;  // with_fan_offsets' scratch
    std::vector<uint32_t> predicted(3), color_predicted(colors.components);
    ByteWriter index_out(index);
    float previous_error = h.max_error;
    uint32_t next_face = static_cast<uint32_t>(pm.base_face_count());
    std::size_t i = 0;
    std::vector<uint64_t> position_codes, color_codes;
    const bool ranged = h.minor >= 1, wedged = h.minor >= 2;
    // The moved corners' ids, when the mesh has any (2.2: their faces, for the wedges).
    const bool moved_ids = has_ids(0) || has_ids(1);
    // The models carry over from chunk to chunk (§5.10): chunks are decoded in order anyway.
    auto models = std::make_unique<ChunkModels>();
    if (wedged) start_wedges();
    uint32_t wedge_units[3];
    for (uint32_t size : plan_chunks(h.split_count, options.chunk_splits)) {
      std::string streams[kChunkStreams];
      RangeEncoder u_rc(streams[kStreamU]), vl_rc(streams[kStreamVl]), vr_rc(streams[kStreamVr]),
          position_rc(streams[kStreamPositions]), uv_rc(streams[kStreamUvCodes]),
          normal_rc(streams[kStreamNormalCodes]);
      RangeEncoder* wedge_rc[2] = {&uv_rc, &normal_rc};
      int64_t previous_u = -1;
      position_codes.clear();
      color_codes.clear();
      ChunkEntry entry;
      entry.splits = size;
      ByteWriter u_out(streams[kStreamU]), vl_out(streams[kStreamVl]), vr_out(streams[kStreamVr]),
          explicit_out(streams[kStreamExplicit]), material_out(streams[kStreamMaterials]),
          uv_out(streams[kStreamUvCodes]), normal_out(streams[kStreamNormalCodes]);
      previous_error = error_before(i);  // the index's error before this chunk
      for (const std::size_t end = i + size; i < end; ++i) {
        const VertexSplit& split = pm.splits[i];
        const auto v = static_cast<uint32_t>(pm.base_vertex_count + i);
        if (ranged) {
          // u as the gap from the previous u of its layer (§5.10); a new layer starts
          // wherever u does not grow.
          const bool first = i + size == end;
          const bool restart = !first && int64_t{split.u} <= previous_u;
          if (!first) u_rc.bit(models->restart, restart ? 1 : 0);
          if (first || restart) previous_u = -1;
          put_eg(u_rc, models->u_gap[previous_u < 0 ? 0 : 1],
                 static_cast<uint64_t>(split.u - previous_u - 1));
          previous_u = split.u;
        } else {
          u_out.put_varint(v - 1 - split.u);
        }
        const float error = error_before(i);
        const int64_t error_step = int64_t{ordered_from_float(previous_error)} -
                                   int64_t{ordered_from_float(error)};
        put_varint64(streams[kStreamErrors], zigzag(error_step));
        previous_error = error;
        record.assign(pm.moved_faces.begin() + split.moved_begin,
                      pm.moved_faces.begin() + split.moved_begin + split.moved_count);
        const std::size_t ahead = i + SplitFans::Prefetch::kAhead;
        prefetch.step(ahead < pm.splits.size() ? pm.splits[ahead].u : SplitFans::kNone);
        // One-ring coding when the moved faces are the arc from vl to vr around u.
        bool coded = false;
        std::size_t place_l = 0, place_r = 0;
        const bool has_fan = fans.fan(split.u, fan);
        if (has_fan) {
          const std::size_t places = fan.closed ? fan.faces.size() : fan.ring.size();
          const auto place = [&](uint32_t vertex, std::size_t none) {
            if (vertex == kNoVertex) return fan.closed ? places : none;
            const auto it = std::find(fan.ring.begin(), fan.ring.begin() + places, vertex);
            return static_cast<std::size_t>(it - fan.ring.begin());
          };
          place_l = place(split.vl, 0);
          place_r = place(split.vr, fan.faces.size());
          if (place_l < places && place_r <= places && SplitFans::arc(fan, place_l, place_r, arc)) {
            sorted_arc = arc;
            std::sort(sorted_arc.begin(), sorted_arc.end());
            sorted_record = record;
            std::sort(sorted_record.begin(), sorted_record.end());
            coded = sorted_arc == sorted_record;
          }
        }
        neighbours.assign(1, split.u);
        if (coded) {
          uint32_t vl_code = split.vl == kNoVertex ? 0 : static_cast<uint32_t>(place_l) + 1;
          const uint32_t vr_code =
              split.vr == kNoVertex ? 0 : static_cast<uint32_t>(arc.size()) + 1;
          if (ranged) {
            // 2.1: a closed fan's places counted from its lopsided place (§5.10).
            if (fan.closed) {
              const std::size_t n = fan.faces.size();
              vl_code = static_cast<uint32_t>(
                            (place_l + n - lopsided_place(positions, split.u, fan, offsets)) % n) +
                        1;
            }
            put_ring_code(vl_rc, models->vl, models->vl_large, fan.faces.size(), vl_code);
            put_ring_code(vr_rc, models->vr, models->vr_large, fan.faces.size(), vr_code);
          } else {
            vl_out.put_varint(vl_code);
            vr_out.put_varint(vr_code);
          }
          const std::size_t n = fan.faces.size();
          for (std::size_t k = 0; k <= arc.size(); ++k) {
            neighbours.push_back(fan.ring[fan.closed ? (place_l + k) % n : place_l + k]);
          }
        } else {
          if (!ranged) {
            vl_out.put_varint(0);
            vr_out.put_varint(0);
          } else if (has_fan) {  // a fan, but not an arc of it: both codes 0
            put_ring_code(vl_rc, models->vl, models->vl_large, fan.faces.size(), 0);
            put_ring_code(vr_rc, models->vr, models->vr_large, fan.faces.size(), 0);
          }
          explicit_out.put_varint(split.vl == kNoVertex ? 0 : split.vl + 1);
          explicit_out.put_varint(split.vr == kNoVertex ? 0 : split.vr + 1);
          explicit_out.put_varint(split.moved_count);
          for (uint32_t f : record) explicit_out.put_varint(f);
          arc = record;
        }
        // The new vertex's position and colour, against the mean of its neighbours.
        positions.predict(neighbours.data(), neighbours.size(), predicted.data());
        // On a grid (2.1) or of significant decimals (2.4), the coordinate along u's normal
        // last, predicted from the others.
        NormalFrame frame;
        const bool framed = ranged && positions.has_frames() && has_fan &&
                            normal_frame(positions, split.u, fan, offsets, frame);
        int64_t r[3], d[3];
        const uint32_t* at_u = &positions.units[3 * std::size_t{split.u}];
        const uint32_t* at_v = &positions.units[3 * std::size_t{v}];
        for (int c = 0; c < 3; ++c) {
          r[c] = int64_t{at_v[c]} - predicted[c];
          d[c] = int64_t{predicted[c]} - at_u[c];
        }
        for (int k = 0; k < 3; ++k) {
          const int c = frame.order[k];
          const bool along_normal = framed && k == 2;
          int64_t residual = r[c];
          if (along_normal && positions.grid == nullptr) {  // 2.4: significant decimals
            residual = int64_t{at_v[c]} - normal_prediction_of_values(*positions.significant, frame,
                                                                      at_u, predicted.data(), at_v);
          } else if (along_normal) {
            residual -= normal_offset(frame, d, r, position_grid.bits);
          }
          if (ranged) {
            // |residual| and its sign, with the models of its neighbours' spread (§5.10).
            const uint32_t context =
                positions.spread_context(neighbours.data(), neighbours.size(), predicted[c], c);
            put_eg(position_rc, models->position[along_normal][context],
                   static_cast<uint64_t>(residual < 0 ? -residual : residual));
            const int side = d[c] < 0 ? 0 : d[c] == 0 ? 1 : 2;
            if (residual != 0)
              position_rc.bit(models->sign[along_normal][context][side], residual < 0 ? 1 : 0);
          } else {
            position_codes.push_back(zigzag(residual));
          }
        }
        if (colors.components != 0) {
          colors.predict(neighbours.data(), neighbours.size(), color_predicted.data());
          for (std::size_t c = 0; c < colors.components; ++c) {
            color_codes.push_back(zigzag(int64_t{colors.units[colors.components * v + c]} - color_predicted[c]));
          }
        }
        // Attributes: the moved corners in the order stored (the arc's), then fl and fr.
        if (wedged && moved_ids) arc_faces(fans, split.u, arc, arc_sides);
        for (std::size_t m = 0; moved_ids && m < arc.size(); ++m) {
          const uint32_t f = arc[m];
          const std::size_t k = split.moved_begin +
                                (std::find(record.begin(), record.end(), f) - record.begin());
          if (wedged) {  // 2.2 (§5.11)
            const int slot = arc_sides[m].slot;
            const WedgeCoder::Corner at{kRoleMoved, v, v, arc_sides.data(), arc_sides.size(), m};
            for (int kind = 0; kind < 2; ++kind) {
              if (!has_ids(kind)) continue;
              const uint32_t id = (kind == 0 ? pm.moved_uvs : pm.moved_normals)[k];
              if (id != kNoAttribute) units_of(kind, id, wedge_units);
              wedges[kind].encode(*wedge_rc[kind], positions.units, at, id, wedge_units);
              wedges[kind].move(f, slot, id);
            }
            continue;
          }
          if (pm.has_uvs()) uv_out.put_varint(uv_codes.encode(v, pm.moved_uvs[k]));
          if (pm.has_normals()) normal_out.put_varint(normal_codes.encode(v, pm.moved_normals[k]));
        }
        for (int side = 0; side < 2; ++side) {
          const uint32_t other = side == 0 ? split.vl : split.vr;
          if (other == kNoVertex) continue;
          const uint32_t corners[3] = {side == 0 ? v : split.u, side == 0 ? split.u : v, other};
          for (int c = 0; c < 3; ++c) {
            const std::size_t slot = 3 * std::size_t{next_face} + c;
            if (!wedged) {
              put_corner(uv_out, normal_out, corners[c], slot);
              continue;
            }
            const WedgeCoder::Corner at{new_face_role(c, corners[c], v), corners[c]};
            for (int kind = 0; kind < 2; ++kind) {
              if (!has_ids(kind)) continue;
              const uint32_t id = (kind == 0 ? pm.face_uvs : pm.face_normals)[slot];
              if (id != kNoAttribute) units_of(kind, id, wedge_units);
              wedges[kind].encode(*wedge_rc[kind], positions.units, at, id, wedge_units);
            }
          }
          if (pm.has_materials()) put_optional_id(material_out, pm.face_materials[next_face]);
          ++next_face;
          ++entry.new_faces;
        }
        entry.moved_faces += split.moved_count;
        fans.split(split.u, v, split.vl, split.vr, arc.data(), arc.size(), coded ? &fan : nullptr,
                   place_l);
      }
      entry.error_after = error_before(i);
      index_out.put_varint(entry.splits);
      index_out.put_varint(entry.new_faces);
      index_out.put_varint(entry.moved_faces);
      index_out.put_f32(entry.error_after);
      if (wedged) {
        for (int kind = 0; kind < 2; ++kind) {
          if (has_ids(kind)) wedge_rc[kind]->finish();
        }
      }
      if (ranged) {
        for (RangeEncoder* rc : {&u_rc, &vl_rc, &vr_rc, &position_rc}) rc->finish();
      } else {
        put_planes(streams[kStreamPositions], position_codes);
      }
      put_planes(streams[kStreamColors], color_codes);
      std::string raw;
      for (const std::string& stream : streams) put_varint64(raw, stream.size());
      for (const std::string& stream : streams) raw += stream;
      raws.push_back(std::move(raw));
    }
  }
};

Status check_writable_v2(const ProgressiveMesh& pm, const WriteOptions& options) {
  for (const auto& [count, what] :
       {std::pair{uint64_t{pm.base_vertex_count}, "base vertices"},
        {pm.base_face_count(), "base faces"}, {pm.splits.size(), "splits"},
        {uint64_t{pm.loose_vertex_count}, "loose vertices"}, {pm.welds.size(), "welds"},
        {pm.carried_faces.size() / 3, "carried faces"}, {pm.moved_faces.size(), "moved faces"},
        {pm.uv_count(), "texture coordinates"}, {pm.normal_count(), "normals"}}) {
    if (count > kMaxCount) {
      return Status(ErrorCode::kResourceLimit, std::to_string(count) + " " + what +
                                                   " (the format holds at most " +
                                                   std::to_string(kMaxCount) + ")");
    }
  }
  if (Status status = check_material_strings_impl(pm.material_names, pm.material_libraries); !status) {
    return status;
  }
  if (options.zstd_level < 1 || options.zstd_level > ZSTD_maxCLevel()) {
    return Status(ErrorCode::kInvalidArgument, "zstd level " + std::to_string(options.zstd_level) +
                                                   " is outside 1.." + std::to_string(ZSTD_maxCLevel()));
  }
  for (const auto& [bits, what] : {std::pair{options.position_bits, "position"},
                                   {options.uv_bits, "texture coordinate"},
                                   {options.normal_bits, "normal"}}) {
    if (!valid_bits(static_cast<uint32_t>(bits)) || bits < 0) {
      return Status(ErrorCode::kInvalidArgument, std::string(what) + " quantization of " +
                                                     std::to_string(bits) +
                                                     " bits (0 for none, or 4 to 24)");
    }
  }
  if (options.error_bits < 0 || options.error_bits > 24) {
    return Status(ErrorCode::kInvalidArgument, "errors of " + std::to_string(options.error_bits) +
                                                   " significant bits (0 for every bit, or 1 to 24)");
  }
  if (options.minor_version > kNewestMinor) {
    return Status(ErrorCode::kInvalidArgument, "format 2." + std::to_string(options.minor_version) +
                                                   " (this writer writes 2.0 to 2.4)");
  }
  if (options.chunk_splits < 1 || options.chunk_splits > (1u << 20)) {
    return Status(ErrorCode::kInvalidArgument, "chunks of " + std::to_string(options.chunk_splits) +
                                                   " splits (1 to 1048576)");
  }
  return Status::ok();
}

Status write_pm_v2(const ProgressiveMesh& pm, const WriteOptions& options, std::string& bytes) {
  std::string message;
  if (!validate(pm, &message)) {
    return Status(ErrorCode::kInvalidArgument, "cannot write an invalid progressive mesh: " + message);
  }
  if (Status status = check_writable_v2(pm, options); !status) return status;
  Writer w(pm, options);
  Header2& h = w.h;
  h.base_vertex_count = pm.base_vertex_count;
  h.base_face_count = static_cast<uint32_t>(pm.base_face_count());
  h.split_count = static_cast<uint32_t>(pm.splits.size());
  h.loose_vertex_count = pm.loose_vertex_count;
  h.weld_count = static_cast<uint32_t>(pm.welds.size());
  h.carried_face_count = static_cast<uint32_t>(pm.carried_faces.size() / 3);
  h.moved_face_count = static_cast<uint32_t>(pm.moved_faces.size());
  for (const VertexSplit& split : pm.splits) h.split_face_count += split.new_face_count();
  h.chunk_count = static_cast<uint32_t>(plan_chunks(h.split_count, options.chunk_splits).size());
  h.minor = options.minor_version;
  if (h.minor >= 2) w.plan_tables();
  h.max_error = w.error_before(0);
  h.attributes = (pm.has_uvs() ? kAttributeUvIds : 0) | (pm.has_normals() ? kAttributeNormalIds : 0) |
                 (pm.has_materials() ? kAttributeMaterialIds : 0);
  h.options = pm.keeps_order() ? kOptionKeepsOrder : 0;
  h.color_components = pm.color_components;
  h.uv_count = static_cast<uint32_t>(pm.uv_count());
  h.normal_count = static_cast<uint32_t>(pm.normal_count());
  h.material_count = static_cast<uint32_t>(pm.material_names.size());
  h.material_library_count = static_cast<uint32_t>(pm.material_libraries.size());
  for (const auto* strings : {&pm.material_names, &pm.material_libraries}) {
    for (const std::string& text : *strings) h.material_string_bytes += static_cast<uint32_t>(text.size());
  }
  // Quantization (§5.3): the grids first, so that every value is known on its grid.
  const auto grid_of = [](const std::vector<float>& values, std::size_t components, int bits,
                          Grid& grid, const char* what) {
    if (bits == 0) return Status::ok();
    if (!make_grid(values.data(), values.size() / components, components, bits, grid)) {
      return Status(ErrorCode::kInvalidArgument, std::string("cannot quantize ") + what +
                                                     " that are not finite numbers");
    }
    return Status::ok();
  };
  if (Status s = grid_of(pm.positions, 3, options.position_bits, w.position_grid, "positions"); !s) return s;
  if (Status s = grid_of(pm.uvs, 2, options.uv_bits, w.uv_grid, "texture coordinates"); !s) return s;
  if (Status s = grid_of(pm.normals, 3, options.normal_bits, w.normal_grid, "normals"); !s) return s;
  h.position_bits = static_cast<uint8_t>(options.position_bits);
  // 2.3, lossless (§5.3): the positions on their decimal grid, or as significant decimals,
  // when they are such decimals: whichever is the coarser where most of them lie (fixed
  // places, "-0.037830", make a grid; "%g" makes significant digits: fandisk's "15.3644" and
  // "1e-06" would need a grid of 10^-6 steps, 40.3 KB as significant decimals against 47.6).
  double grid_gain = 0, significant_gain = 0;
  const bool lossless = options.position_bits == 0 && h.minor >= 3;
  Grid decimal_grid;
  SignificantDecimals significant;
  std::vector<uint32_t> significant_units;
  const bool gridded = lossless && make_decimal_grid(pm.positions.data(), pm.positions.size() / 3, 3,
                                                     decimal_grid, grid_gain);
  const bool numbered =
      lossless && make_significant_decimals(pm.positions.data(), pm.positions.size(), significant,
                                            significant_units, significant_gain);
  if (gridded && !(numbered && significant_gain > grid_gain)) {
    w.position_grid = std::move(decimal_grid);
    h.position_bits = static_cast<uint8_t>(w.position_grid.bits);
    h.options |= kOptionDecimalPositions;
  } else if (numbered) {
    w.significant = significant;
  }
  h.uv_bits = static_cast<uint8_t>(pm.uvs.empty() ? 0 : options.uv_bits);
  h.normal_bits = static_cast<uint8_t>(pm.normals.empty() ? 0 : options.normal_bits);
  if (pm.uvs.empty()) w.uv_grid.bits = 0;
  if (pm.normals.empty()) w.normal_grid.bits = 0;
  // 2.3, lossless tables (§5.4): as significant decimals when they are.
  for (int kind = 0; kind < 2 && h.minor >= 3; ++kind) {
    const std::vector<float>& values = kind == 0 ? pm.uvs : pm.normals;
    double gain = 0;
    if ((kind == 0 ? options.uv_bits : options.normal_bits) == 0 && !values.empty() &&
        make_significant_decimals(values.data(), values.size(), w.table_significant[kind],
                                  w.table_numbers[kind], gain)) {
      h.options |= significant_table_option(kind);
    }
  }
  w.positions.components = 3;
  w.positions.grid = h.position_bits != 0 ? &w.position_grid : nullptr;
  if (w.significant.digits != 0) {
    h.options |= kOptionSignificantPositions;
    w.positions.significant = &w.significant;
    w.positions.mean_of_values = h.minor >= 4;  // 2.4 (§5.3)
    w.positions.units = std::move(significant_units);
  } else {
    w.positions.units.resize(pm.positions.size());
    for (std::size_t i = 0; i < pm.positions.size(); ++i) {
      w.positions.units[i] = w.positions.from_float(pm.positions[i], i % 3);
    }
  }
  w.colors.components = pm.color_components;
  w.colors.units.resize(pm.colors.size());
  for (std::size_t i = 0; i < pm.colors.size(); ++i) w.colors.units[i] = ordered_from_float(pm.colors[i]);

  std::vector<std::pair<uint32_t, std::string>> sections;
  for (uint32_t tag : expected_sections(h)) {
    if (tag == kTagBase) sections.emplace_back(tag, w.base());
    if (tag == kTagWelds) sections.emplace_back(tag, w.welds());
    if (tag == kTagCarried) sections.emplace_back(tag, w.carried());
    if (tag == kTagTables) sections.emplace_back(tag, w.tables());
    if (tag == kTagIndex) {
      std::vector<std::string> chunks;
      std::string index;
      w.chunks(chunks, index);
      sections.emplace_back(tag, std::move(index));
      for (std::string& chunk : chunks) sections.emplace_back(kTagChunk, std::move(chunk));
    }
    if (tag == kTagLoose) sections.emplace_back(tag, w.loose());
    if (tag == kTagOrder) sections.emplace_back(tag, w.order());
  }
  // Each section compressed on its own (zstd at level 19 is the writer's largest cost after
  // the fans), several at once, then written in order.
  std::vector<std::string> compressed(sections.size());
  std::vector<Status> statuses(sections.size());
  run_in_turn(sections.size(), thread_count(options.threads), [&](std::size_t i, bool) {
    statuses[i] = append_section(sections[i].first, kSectionRequired, sections[i].second,
                                 sections[i].second.size(), options.zstd_level, compressed[i]);
    std::string().swap(sections[i].second);
  });
  std::string out;
  append_header2(h, out);
  for (std::size_t i = 0; i < sections.size(); ++i) {
    if (!statuses[i]) return statuses[i];
    out += compressed[i];
    std::string().swap(compressed[i]);
  }
  bytes = std::move(out);
  return Status::ok();
}

// ---------------------------------------------------------------------------------------
// Reader.

std::string section_name(uint32_t tag, std::size_t chunk) {
  return "section " + tag_name(tag) + (tag == kTagChunk ? " " + std::to_string(chunk) : "");
}

bool read_optional_id(ByteReader& in, uint32_t count, const char* what, uint32_t& id) {
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
}  // namespace detail

using namespace detail;  // NOLINT: the layout helpers are this file's vocabulary

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
                    std::vector<uint32_t>* uvs, std::vector<uint32_t>* normals);
};

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
  prefer_huge_pages(positions.units);  // each split reads its neighbours' (huge_pages.h)
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

Status PmStreamReader::State::process(std::string_view bytes, std::size_t& used) {
  used = 0;
  while (true) {
    const std::string_view rest = bytes.substr(used);
    if (stage == kHeader) {
      // The magic is checked as soon as its bytes arrive: a stream that is not one fails
      // at once, not when 96 bytes have come.
      const std::size_t magic = std::min(rest.size(), sizeof kMagic);
      if (std::memcmp(rest.data(), kMagic, magic) != 0) return corrupt("not a .pm stream (bad magic)");
      if (rest.size() < 12) return Status::ok();
      const uint16_t major = static_cast<uint16_t>(static_cast<uint8_t>(rest[8]) |
                                                   static_cast<uint8_t>(rest[9]) << 8);
      if (major != kMajor2) {
        stage = kVersion1;  // decoded whole, at finish()
        continue;
      }
      if (rest.size() < kHeaderSize) return Status::ok();
      if (Status s = start(rest); !s) return s;
      used += kHeaderSize;
      continue;
    }
    if (stage == kVersion1) return Status::ok();  // nothing used: finish() reads it all
    if (stage == kDone) {
      // Only optional sections of other tools may follow the last known one (§4.3).
      SectionHeader section;
      if (rest.empty() || stopped || !read_section_header(rest, section)) return Status::ok();
      if (!is_valid_tag(section.tag) || is_v2_tag(section.tag) ||
          (section.flags & kSectionRequired) != 0) {
        return corrupt(std::to_string(rest.size()) + " bytes follow the last section");
      }
      if (rest.size() - kSectionHeaderSize < section.stored_size) return Status::ok();
      used += kSectionHeaderSize + static_cast<std::size_t>(section.stored_size);
      continue;
    }
    // A reader that has the splits it wants stops before the next chunk.
    if (expected[next] == kTagChunk && pm.splits.size() >= options.max_splits) {
      stage = kDone;
      stopped = true;
      raw = std::string();
      fans = SplitFans();
      continue;
    }
    // A section: its 24-byte header, then its frame.
    SectionHeader section;
    if (!read_section_header(rest, section)) return Status::ok();
    const uint32_t tag = section.tag, flags = section.flags;
    const uint64_t stored = section.stored_size, raw_size = section.raw_size;
    if (!is_valid_tag(tag)) return corrupt("section header: bad tag " + tag_name(tag));
    if (!is_v2_tag(tag)) {
      if ((flags & kSectionRequired) != 0) {
        return Status(h.minor > kNewestMinor ? ErrorCode::kUnsupportedVersion : ErrorCode::kCorruptStream,
                      "section " + tag_name(tag) + ": required, and unknown to this reader");
      }
      if (rest.size() - kSectionHeaderSize < stored) return Status::ok();  // wait, then skip
      used += kSectionHeaderSize + static_cast<std::size_t>(stored);
      continue;
    }
    if (Status s = check_section(tag, flags, stored, raw_size); !s) return s;
    if (rest.size() - kSectionHeaderSize < stored) return Status::ok();  // the frame has not arrived
    const std::string where = section_name(tag, chunks_decoded);
    if (Status s = decompress_frame(where, rest.substr(kSectionHeaderSize, stored), raw_size,
                                    dctx.get(), raw);
        !s) {
      return s;
    }
    ByteReader payload(raw, where, ErrorCode::kCorruptStream);
    if (Status s = decode(tag, payload); !s) return s;
    if (!payload.at_end()) {
      return corrupt(where + ": " + std::to_string(payload.remaining()) + " bytes left over");
    }
    used += kSectionHeaderSize + static_cast<std::size_t>(stored);
    ++next;
    if (next < expected.size() && expected[next] == kTagChunk && !base_done) base_done = true;
    if (next == expected.size()) {
      stage = kDone;
      base_done = true;
    } else if (tag == kTagChunk && pm.splits.size() >= options.max_splits) {
      stage = kDone;
      stopped = true;
    }
    if (stage == kDone) {
      raw = std::string();
      fans = SplitFans();
    }
  }
}

Status PmStreamReader::State::decode(uint32_t tag, ByteReader& in) {
  detach_carried();
  bool ok = true;
  if (tag == kTagBase) ok = decode_base(in);
  if (tag == kTagWelds) ok = decode_welds(in);
  if (tag == kTagCarried) ok = decode_carried(in);
  if (tag == kTagTables) ok = decode_tables(in);
  if (tag == kTagIndex) ok = decode_index(in);
  if (tag == kTagChunk) ok = decode_chunk(in);
  if (tag == kTagLoose) ok = decode_loose(in);
  if (tag == kTagOrder) ok = decode_order(in);
  return ok ? Status::ok() : in.status();
}

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

// One corner's id of `kind` (0 texture coordinates, 1 normals), from its code (§5.7).
bool PmStreamReader::State::read_corner(ByteReader& in, int kind, uint32_t vertex, uint32_t& id) {
  CornerPredictor& codes = kind == 0 ? *uv_codes : *normal_codes;
  uint32_t code;
  std::string problem;
  if (!in.read_varint(code)) return false;
  if (!codes.decode(code, vertex, kind == 0 ? h.uv_count : h.normal_count, id, problem)) {
    return in.fail(ErrorCode::kCorruptStream,
                   in.where() + ": a corner of vertex " + std::to_string(vertex) + " " + problem);
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
  if (!read_corners(in, pm.base_faces, &pm.face_uvs, &pm.face_normals)) return false;
  decoded_faces = h.base_face_count + uint64_t{h.carried_face_count};
  return true;
}


// The corner codes of faces whose vertices are `vertices` (3 per face): all texture
// coordinates' ids, then all normals' (§5.7), appended to the arrays the stream has.
bool PmStreamReader::State::read_corners(ByteReader& in, const std::vector<uint32_t>& vertices,
                                         std::vector<uint32_t>* uvs,
                                         std::vector<uint32_t>* normals) {
  for (int kind = 0; kind < 2; ++kind) {
    if ((kind == 0 ? uv_codes : normal_codes) == nullptr) continue;
    std::vector<uint32_t>& ids = *(kind == 0 ? uvs : normals);
    for (uint32_t vertex : vertices) {
      uint32_t id;
      if (!read_corner(in, kind, vertex, id)) return false;
      ids.push_back(id);
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
  return read_corners(in, pm.carried_faces, &carried_uvs, &carried_normals);
}

// 2.2 (§5.11): the wedge coders of the kinds the corners have.
void PmStreamReader::State::reset_wedges() {
  const uint64_t level_faces = uint64_t{h.base_face_count} + h.split_face_count;
  for (int kind = 0; kind < 2; ++kind) {
    if (!(kind == 0 ? h.uv_ids() : h.normal_ids())) continue;
    const int bits = kind == 0 ? h.uv_bits : h.normal_bits;
    wedges[kind].reset(kind == 0 ? 2 : 3, kind == 0 ? h.uv_count : h.normal_count,
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
    if (!(kind == 0 ? h.uv_ids() : h.normal_ids())) continue;
    const std::vector<uint32_t>& base = kind == 0 ? pm.face_uvs : pm.face_normals;
    const std::vector<uint32_t>& carried = kind == 0 ? carried_uvs : carried_normals;
    for (int part = 0; part < 2; ++part) {
      const std::vector<uint32_t>& vertices = part == 0 ? pm.base_faces : pm.carried_faces;
      const std::vector<uint32_t>& ids = part == 0 ? base : carried;
      for (std::size_t k = 0; k < vertices.size(); ++k) {
        if (ids[k] != kNoAttribute && !wedges[kind].known(ids[k])) {
          return in.fail(ErrorCode::kCorruptStream,
                         in.where() + ": a " + (part == 0 ? "base" : "carried") + " face's corner has " +
                             (kind == 0 ? "texture coordinate " : "normal ") + std::to_string(ids[k]) +
                             ", which the table does not list");
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
  return (h.uv_ids() && wedges[0].unknown() > 0) || (h.normal_ids() && wedges[1].unknown() > 0);
}

void PmStreamReader::State::drop_unknown_entries(ProgressiveMesh& target) const {
  for (int kind = 0; kind < 2; ++kind) {
    if (!wedges_ready || !(kind == 0 ? h.uv_ids() : h.normal_ids())) continue;
    const uint32_t count = kind == 0 ? h.uv_count : h.normal_count;
    const std::size_t components = kind == 0 ? 2 : 3;
    std::vector<uint32_t> new_id(count, kNoAttribute);
    uint32_t next = 0;
    for (uint32_t id = 0; id < count; ++id) {
      if (wedges[kind].known(id)) new_id[id] = next++;
    }
    if (next == count) continue;
    // Every id a corner has is known.
    if (kind == 0) {
      renumber_entries(target.uvs, components, new_id, next, {&target.face_uvs, &target.moved_uvs});
    } else {
      renumber_entries(target.normals, components, new_id, next,
                       {&target.face_normals, &target.moved_normals});
    }
  }
}

// 2.2 (§5.4): the entries listed with their ids' gaps; the others are 0 until a split
// introduces them (§5.11).
bool PmStreamReader::State::read_listed(ByteReader& in, int kind) {
  const uint32_t count = kind == 0 ? h.uv_count : h.normal_count;
  const int bits = kind == 0 ? h.uv_bits : h.normal_bits;
  const std::size_t components = kind == 0 ? 2 : 3;
  std::vector<float>& values = kind == 0 ? pm.uvs : pm.normals;
  values.assign(components * std::size_t{count}, 0.0f);
  if (count == 0) return true;
  Grid& grid = kind == 0 ? uv_grid : normal_grid;
  if (bits != 0 && !read_grid(in, bits, components, grid)) return false;
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
  const bool ids = kind == 0 ? h.uv_ids() : h.normal_ids();
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
      if (!read_table_value(in, bits != 0 ? &grid : nullptr, in_use(significant), c,
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

bool PmStreamReader::State::decode_chunk(ByteReader& in) {
  const ChunkEntry& entry = index[chunks_decoded];
  const std::string where = in.where();
  // The streams' sizes, then the streams (§5.5).
  uint64_t sizes[kChunkStreams];
  for (uint64_t& size : sizes) {
    if (!read_varint64(in, size)) return false;
  }
  std::vector<ByteReader> streams;
  streams.reserve(kChunkStreams);
  std::string_view stream_bytes[kChunkStreams];
  for (int k = 0; k < kChunkStreams; ++k) {
    std::string_view& bytes = stream_bytes[k];
    if (!in.read_bytes(sizes[k], bytes)) return false;
    streams.emplace_back(bytes, where + " (" + kStreamNames[k] + ")", ErrorCode::kCorruptStream);
  }
  const auto failed = [&](ByteReader& stream) { return in.fail(stream.status().code(), stream.status().message()); };
  const auto bad = [&](uint32_t v, const std::string& what) {
    return in.fail(ErrorCode::kCorruptStream,
                   where + ": split " + std::to_string(v - h.base_vertex_count) + " " + what);
  };
  ByteReader &u_in = streams[kStreamU], &vl_in = streams[kStreamVl], &vr_in = streams[kStreamVr],
             &explicit_in = streams[kStreamExplicit], &error_in = streams[kStreamErrors],
             &position_in = streams[kStreamPositions], &color_in = streams[kStreamColors],
             &material_in = streams[kStreamMaterials], &uv_in = streams[kStreamUvCodes],
             &normal_in = streams[kStreamNormalCodes];
  float previous_error = chunks_decoded == 0 ? h.max_error : index[chunks_decoded - 1].error_after;
  SplitFans::Fan fan;
  std::vector<uint32_t> arc, neighbours;
  std::vector<WedgeCoder::ArcFace> arc_sides;
  std::vector<int64_t> offsets;  // with_fan_offsets' scratch
  uint32_t predicted[3];
  std::vector<uint32_t> color_predicted(h.color_components);
  uint32_t new_faces = 0, moved_total = 0;
  std::vector<uint64_t> position_codes, color_codes;
  // 2.1 (§5.10): u, vl, vr and the positions are range codes, with fresh models per chunk.
  const bool ranged = h.minor >= 1;
  std::optional<RangeDecoder> u_rc, vl_rc, vr_rc, position_rc;
  // 2.2 (§5.11): the corners' ids and new values, a range code per kind.
  const bool wedged = h.minor >= 2;
  std::optional<RangeDecoder> wedge_rc[2];
  if (wedged) {
    if (!wedges_ready) {  // no TABL: no table entries
      reset_wedges();
      if (!start_wedges(in)) return false;
    }
    if (h.uv_ids()) wedge_rc[0].emplace(stream_bytes[kStreamUvCodes]);
    if (h.normal_ids()) wedge_rc[1].emplace(stream_bytes[kStreamNormalCodes]);
  }
  std::string wedge_problem;
  const auto wedge_corner = [&](int kind, const WedgeCoder::Corner& at, uint32_t& id) {
    if (!wedges[kind].decode(*wedge_rc[kind], positions.units, at, id, wedge_problem) ||
        !wedge_rc[kind]->ok()) {
      return in.fail(ErrorCode::kCorruptStream,
                     where + " (" + kStreamNames[kind == 0 ? kStreamUvCodes : kStreamNormalCodes] +
                         "): a corner of vertex " + std::to_string(at.vertex) + " " +
                         (wedge_problem.empty() ? "is cut short" : wedge_problem));
    }
    if (id != kNoAttribute) {
      std::vector<float>& values = kind == 0 ? pm.uvs : pm.normals;
      const Grid& grid = kind == 0 ? uv_grid : normal_grid;
      const std::size_t components = kind == 0 ? 2 : 3;
      const uint32_t* units = wedges[kind].units(id);
      const bool on_grid = (kind == 0 ? h.uv_bits : h.normal_bits) != 0;
      for (std::size_t c = 0; c < components; ++c) {  // 2.3's numbers too (§5.4)
        if (!float_of_unit(on_grid ? &grid : nullptr, in_use(table_significant[kind]), units[c], c,
                           values[components * std::size_t{id} + c])) {
          return in.fail(ErrorCode::kCorruptStream, where + ": a corner of vertex " +
                                                        std::to_string(at.vertex) +
                                                        " has a table value that is no decimal's");
        }
      }
    }
    return true;
  };
  if (ranged) {
    if (!models) models = std::make_unique<ChunkModels>();  // kept from chunk to chunk
    u_rc.emplace(stream_bytes[kStreamU]);
    vl_rc.emplace(stream_bytes[kStreamVl]);
    vr_rc.emplace(stream_bytes[kStreamVr]);
    position_rc.emplace(stream_bytes[kStreamPositions]);
  } else if (!read_planes(position_in, 3 * std::size_t{entry.splits}, position_codes)) {
    return failed(position_in);
  }
  int64_t previous_u = -1;
  const auto range_failed = [&](const char* stream) {
    return in.fail(ErrorCode::kCorruptStream,
                   where + " (" + stream + "): the range code is corrupt or ends early");
  };
  if (!read_planes(color_in, std::size_t{h.color_components} * entry.splits, color_codes)) {
    return failed(color_in);
  }
  std::size_t next_position = 0, next_color = 0;
  // 2.1: u has a range code of its own, so the chunk's u are decoded first, and their fans
  // fetched a few splits ahead of their turn (SplitFans::Prefetch).
  if (ranged) {
    chunk_u.resize(entry.splits);
    for (uint32_t j = 0; j < entry.splits; ++j) {
      const auto v = static_cast<uint32_t>(h.base_vertex_count + pm.splits.size() + j);
      if (j > 0 && u_rc->bit(models->restart) != 0) previous_u = -1;
      if (j == 0) previous_u = -1;
      uint64_t gap = 0;
      if (!get_eg(*u_rc, models->u_gap[previous_u < 0 ? 0 : 1], gap) || !u_rc->ok())
        return range_failed("u");
      if (gap >= uint64_t{v} || previous_u + 1 + static_cast<int64_t>(gap) >= int64_t{v}) {
        return bad(v, "names u beyond the vertices before it");
      }
      chunk_u[j] = static_cast<uint32_t>(previous_u + 1 + static_cast<int64_t>(gap));
      previous_u = chunk_u[j];
    }
  }
  // The moved corners' ids, when the stream has any (2.2: their faces, for the wedges).
  const bool moved_ids = wedged ? wedge_rc[0] || wedge_rc[1] : uv_codes || normal_codes;
  SplitFans::Prefetch prefetch(fans, &positions.units);
  constexpr std::size_t kAhead = SplitFans::Prefetch::kAhead;
  for (std::size_t k = 0; ranged && k < kAhead; ++k)
    prefetch.step(k < entry.splits ? chunk_u[k] : SplitFans::kNone);
  for (uint32_t j = 0; j < entry.splits; ++j) {
    const auto v = static_cast<uint32_t>(h.base_vertex_count + pm.splits.size());
    VertexSplit split;
    uint32_t u_offset, vl_code = 0, vr_code = 0;
    if (ranged) {
      split.u = chunk_u[j];
      prefetch.step(j + kAhead < entry.splits ? chunk_u[j + kAhead] : SplitFans::kNone);
    } else {
      if (!u_in.read_varint(u_offset)) return failed(u_in);
      if (u_offset >= v)
        return bad(
            v, "names u " + std::to_string(u_offset) + " before itself, of " + std::to_string(v));
      split.u = v - 1 - u_offset;
    }
    uint64_t error_code;
    if (!read_varint64(error_in, error_code)) return failed(error_in);
    int64_t error_step = 0;
    if (!residual_of(error_code, error_step)) return bad(v, "has an impossible error");
    const int64_t error_bits = int64_t{ordered_from_float(previous_error)} - error_step;
    if (error_bits < 0 || error_bits > 0xFFFFFFFFll) return bad(v, "has an impossible error");
    split.error = float_from_ordered(static_cast<uint32_t>(error_bits));
    if (!std::isfinite(split.error) || split.error < 0 || split.error > previous_error ||
        (j == 0 && ordered_from_float(split.error) != ordered_from_float(previous_error))) {
      return bad(v, "has an error that is negative, not finite, larger than the one before, or "
                    "not the index's");
    }
    previous_error = split.error;
    bool has_fan = false;
    if (ranged) {
      // The ring codes exist only when u has a fan (§5.10); without one the split is explicit.
      has_fan = fans.fan(split.u, fan);
      if (has_fan) {
        if (!get_ring_code(*vl_rc, models->vl, models->vl_large, fan.faces.size(), vl_code) ||
            !vl_rc->ok()) {
          return range_failed("vl");
        }
        if (!get_ring_code(*vr_rc, models->vr, models->vr_large, fan.faces.size(), vr_code) ||
            !vr_rc->ok()) {
          return range_failed("vr");
        }
      }
    } else {
      if (!vl_in.read_varint(vl_code)) return failed(vl_in);
      if (!vr_in.read_varint(vr_code)) return failed(vr_in);
    }
    neighbours.assign(1, split.u);
    // Both codes 0: an explicit split; otherwise the moved faces are the arc of `fan` from
    // place arc_first.
    const bool explicit_split = vl_code == 0 && vr_code == 0;
    std::size_t arc_first = 0;
    if (explicit_split) {
      // An explicit split: vl, vr and the moved faces as ids (§5.5).
      uint32_t codes[3];
      for (uint32_t& code : codes) {
        if (!explicit_in.read_varint(code)) return failed(explicit_in);
      }
      split.vl = codes[0] == 0 ? kNoVertex : codes[0] - 1;
      split.vr = codes[1] == 0 ? kNoVertex : codes[1] - 1;
      if ((split.vl != kNoVertex && split.vl >= v) || (split.vr != kNoVertex && split.vr >= v) ||
          (split.vl == kNoVertex && split.vr == kNoVertex) || split.vl == split.u ||
          split.vr == split.u || (split.vl == split.vr)) {
        return bad(v, "has impossible vl and vr");
      }
      if (codes[2] > fans.face_count() || codes[2] > h.moved_face_count) return bad(v, "moves too many faces");
      arc.clear();
      for (uint32_t k = 0; k < codes[2]; ++k) {
        uint32_t f;
        if (!explicit_in.read_varint(f)) return failed(explicit_in);
        if (!fans.holds_once(f, split.u) || std::find(arc.begin(), arc.end(), f) != arc.end()) {
          return bad(v, "moves face " + std::to_string(f) + ", which does not hold u once or is moved twice");
        }
        arc.push_back(f);
      }
    } else {
      if (!has_fan && !fans.fan(split.u, fan))
        return bad(v, "names places around u, whose faces are not a fan");
      const std::size_t n = fan.faces.size();
      std::size_t i = 0, end = n;
      if (vl_code != 0) {
        i = vl_code - 1;
        if (i >= (fan.closed ? n : n + 1)) return bad(v, "names place " + std::to_string(i) + " of u's ring for vl");
        if (ranged && fan.closed) i = (i + lopsided_place(positions, split.u, fan, offsets)) % n;  // §5.10
      } else if (fan.closed) {
        return bad(v, "has no vl on a closed fan");
      }
      if (vr_code != 0) {
        const uint64_t length = vr_code - 1;
        if (length > n) return bad(v, "moves more faces than u has");
        end = fan.closed ? (i + length) % n : i + length;
        if (!fan.closed && end > n) return bad(v, "moves faces beyond the end of u's fan");
      } else if (fan.closed) {
        return bad(v, "has no vr on a closed fan");
      }
      if (!SplitFans::arc(fan, i, end, arc)) return bad(v, "names an impossible arc of u's fan");
      arc_first = i;
      split.vl = vl_code == 0 ? kNoVertex : fan.ring[i];
      split.vr = vr_code == 0 ? kNoVertex : fan.ring[end];
      for (std::size_t k = 0; k <= arc.size(); ++k) neighbours.push_back(fan.ring[fan.closed ? (i + k) % n : i + k]);
    }
    if (moved_total + arc.size() > entry.moved_faces) return bad(v, "moves more faces than the index says");
    split.moved_begin = static_cast<uint32_t>(pm.moved_faces.size());
    split.moved_count = static_cast<uint32_t>(arc.size());
    moved_total += split.moved_count;
    pm.moved_faces.insert(pm.moved_faces.end(), arc.begin(), arc.end());
    // The position and colour: the neighbours' mean plus the residual.
    positions.predict(neighbours.data(), neighbours.size(), predicted);
    NormalFrame frame;
    const bool framed =
        ranged && positions.has_frames() && has_fan && normal_frame(positions, split.u, fan, offsets, frame);
    int64_t r[3] = {0, 0, 0}, d[3];
    uint32_t units[3] = {0, 0, 0};  // v's, as decoded so far
    for (int c = 0; c < 3; ++c)
      d[c] = int64_t{predicted[c]} - positions.units[3 * std::size_t{split.u} + c];
    for (int k = 0; k < 3; ++k) {
      const int c = frame.order[k];
      const bool along_normal = framed && k == 2;
      int64_t residual = 0;
      if (ranged) {
        const uint32_t context =
            positions.spread_context(neighbours.data(), neighbours.size(), predicted[c], c);
        uint64_t magnitude = 0;
        if (!get_eg(*position_rc, models->position[along_normal][context], magnitude))
          return range_failed("positions");
        if (magnitude > 0xFFFFFFFFu) return bad(v, "has a position beyond the grid");
        residual = static_cast<int64_t>(magnitude);
        const int side = d[c] < 0 ? 0 : d[c] == 0 ? 1 : 2;
        if (magnitude != 0 && position_rc->bit(models->sign[along_normal][context][side]) != 0)
          residual = -residual;
        if (!position_rc->ok()) return range_failed("positions");
      } else if (!residual_of(position_codes[next_position++], residual)) {
        return bad(v, "has a position beyond the grid");
      }
      int64_t unit = int64_t{predicted[c]} + residual;
      if (along_normal && positions.grid == nullptr) {  // 2.4: significant decimals
        unit = int64_t{normal_prediction_of_values(*positions.significant, frame,
                                                   &positions.units[3 * std::size_t{split.u}],
                                                   predicted, units)} + residual;
      } else if (along_normal) {
        unit += normal_offset(frame, d, r, position_grid.bits);  // r of the other two: checked
      }
      const int64_t top = h.position_bits != 0 ? (int64_t{1} << h.position_bits) - 1 : 0xFFFFFFFFll;
      if (unit < 0 || unit > top) return bad(v, "has a position beyond the grid");
      r[c] = residual;
      units[c] = static_cast<uint32_t>(unit);
    }
    for (int c = 0; c < 3; ++c) {
      positions.units.push_back(units[c]);
      float x = 0;
      if (!positions.to_float(units[c], c, x)) {
        return bad(v, "has a position that is no decimal's (§5.3)");
      }
      pm.positions.push_back(x);
    }
    if (h.color_components != 0) {
      colors.predict(neighbours.data(), neighbours.size(), color_predicted.data());
      for (std::size_t c = 0; c < h.color_components; ++c) {
        int64_t residual = 0;
        if (!residual_of(color_codes[next_color++], residual)) return bad(v, "has an impossible colour");
        const int64_t unit = int64_t{color_predicted[c]} + residual;
        if (unit < 0 || unit > 0xFFFFFFFFll) return bad(v, "has an impossible colour");
        colors.units.push_back(static_cast<uint32_t>(unit));
        pm.colors.push_back(float_from_ordered(static_cast<uint32_t>(unit)));
      }
    }
    // Attributes: the moved corners, then the new faces' corners and materials.
    if (wedged && moved_ids) arc_faces(fans, split.u, arc, arc_sides);
    for (std::size_t k = 0; moved_ids && k < arc.size(); ++k) {
      uint32_t id;
      if (wedged) {  // 2.2 (§5.11)
        const uint32_t f = arc[k];
        const int slot = arc_sides[k].slot;
        const WedgeCoder::Corner at{kRoleMoved, v, v, arc_sides.data(), arc_sides.size(), k};
        for (int kind = 0; kind < 2; ++kind) {
          if (!wedge_rc[kind]) continue;
          if (!wedge_corner(kind, at, id)) return false;
          wedges[kind].move(f, slot, id);
          (kind == 0 ? pm.moved_uvs : pm.moved_normals).push_back(id);
        }
        continue;
      }
      if (uv_codes) {
        if (!read_corner(uv_in, 0, v, id)) return failed(uv_in);
        pm.moved_uvs.push_back(id);
      }
      if (normal_codes) {
        if (!read_corner(normal_in, 1, v, id)) return failed(normal_in);
        pm.moved_normals.push_back(id);
      }
    }
    for (int side = 0; side < 2; ++side) {
      const uint32_t other = side == 0 ? split.vl : split.vr;
      if (other == kNoVertex) continue;
      const uint32_t corners[3] = {side == 0 ? v : split.u, side == 0 ? split.u : v, other};
      for (int c = 0; c < 3 && wedged; ++c) {  // 2.2 (§5.11)
        const WedgeCoder::Corner at{new_face_role(c, corners[c], v), corners[c]};
        for (int kind = 0; kind < 2; ++kind) {
          if (!wedge_rc[kind]) continue;
          uint32_t id;
          if (!wedge_corner(kind, at, id)) return false;
          (kind == 0 ? pm.face_uvs : pm.face_normals).push_back(id);
        }
      }
      for (uint32_t corner : corners) {
        if (wedged) break;
        uint32_t id;
        if (uv_codes) {
          if (!read_corner(uv_in, 0, corner, id)) return failed(uv_in);
          pm.face_uvs.push_back(id);
        }
        if (normal_codes) {
          if (!read_corner(normal_in, 1, corner, id)) return failed(normal_in);
          pm.face_normals.push_back(id);
        }
      }
      if (h.material_ids()) {
        uint32_t id;
        if (!read_optional_id(material_in, h.material_count, "material", id)) return failed(material_in);
        pm.face_materials.push_back(id);
      }
      ++new_faces;
    }
    if (new_faces > entry.new_faces) return bad(v, "adds more faces than the index says");
    fans.split(split.u, v, split.vl, split.vr, arc.data(), arc.size(),
               explicit_split ? nullptr : &fan, arc_first);
    pm.splits.push_back(split);
  }
  if (new_faces != entry.new_faces || moved_total != entry.moved_faces) {
    return in.fail(ErrorCode::kCorruptStream, where + ": its splits add " + std::to_string(new_faces) +
                                                  " faces and move " + std::to_string(moved_total) +
                                                  ", the index says " + std::to_string(entry.new_faces) +
                                                  " and " + std::to_string(entry.moved_faces));
  }
  if (ordered_from_float(previous_error) < ordered_from_float(entry.error_after)) {
    return in.fail(ErrorCode::kCorruptStream, where + ": the index's error after it is larger than its last");
  }
  if (ranged) {
    for (auto* rc : {&u_rc, &vl_rc, &vr_rc, &position_rc}) {
      if (!(*rc)->ok() || !(*rc)->at_end()) {
        return in.fail(
            ErrorCode::kCorruptStream,
            where + ": a range-coded stream is corrupt, ends early or has bytes left over");
      }
    }
    for (int k : {kStreamU, kStreamVl, kStreamVr, kStreamPositions})
      streams[k].skip(streams[k].remaining());
  }
  for (int kind = 0; kind < 2; ++kind) {
    if (!wedge_rc[kind]) continue;
    if (!wedge_rc[kind]->ok() || !wedge_rc[kind]->at_end()) {
      return in.fail(ErrorCode::kCorruptStream,
                     where + ": a corner attribute code is corrupt, ends early or has bytes left over");
    }
    ByteReader& stream = streams[kind == 0 ? kStreamUvCodes : kStreamNormalCodes];
    stream.skip(stream.remaining());
  }
  for (ByteReader& stream : streams) {
    if (!stream.at_end()) {
      return in.fail(ErrorCode::kCorruptStream, stream.where() + ": " +
                                                    std::to_string(stream.remaining()) + " bytes left over");
    }
  }
  decoded_faces += new_faces;
  ++chunks_decoded;
  return true;
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

PmStreamReader::PmStreamReader(const ReadOptions& options) : state_(new State) {
  state_->options = options;
}
PmStreamReader::~PmStreamReader() { delete state_; }

Status PmStreamReader::append(std::string_view bytes) {
  State& s = *state_;
  if (!s.status) return s.status;
  try {
    std::size_t used = 0;
    Status status;
    if (s.buffer.empty()) {
      status = s.process(bytes, used);
      if (status && used < bytes.size() && !(s.stage == State::kDone && s.stopped)) {
        s.buffer.assign(bytes.substr(used));
      }
      s.consumed += used;
    } else {
      s.buffer.append(bytes);
      status = s.process(s.buffer, used);
      s.buffer.erase(0, used);
      s.consumed += used;
      if (s.stage == State::kDone && s.stopped) s.buffer = std::string();
    }
    if (!status) return s.fail(status);
  } catch (const std::bad_alloc&) {
    return s.fail(Status(ErrorCode::kResourceLimit, "out of memory"));
  }
  return Status::ok();
}

Status PmStreamReader::finish(ReadResult* result) {
  State& s = *state_;
  if (!s.status) return s.status;
  ReadResult r;
  const bool version1 = s.stage == State::kVersion1;
  if (version1) {
    // A 1.x stream is decoded whole: its sections are not chunks.
    ProgressiveMesh pm;
    if (Status status = read_pm_v1(s.buffer, pm, s.options); !status) return s.fail(status);
    s.pm = std::move(pm);
    s.stage = State::kDone;
    s.base_done = true;
    s.buffer = std::string();
  } else if (s.stage == State::kDone && !s.stopped && !s.buffer.empty()) {
    return s.fail(corrupt(std::to_string(s.buffer.size()) + " bytes follow the last section"));
  } else if (s.stage != State::kDone) {
    const std::string where = s.stage == State::kHeader
                                  ? "the header"
                                  : section_name(s.expected[s.next], s.chunks_decoded);
    const std::string message = "truncated in " + where + " (the stream ends at byte " +
                                std::to_string(s.consumed + s.buffer.size()) + ")";
    if (!s.options.allow_truncated || !s.base_done) {
      return s.fail(Status(ErrorCode::kTruncatedStream, message));
    }
    r.truncated = true;
    r.warning = message + ": decoded " + std::to_string(s.pm.splits.size()) + " of " +
                std::to_string(s.h.split_count) + " splits";
    s.stage = State::kDone;
    s.buffer = std::string();
    s.fans = SplitFans();
  }
  s.attach_carried();
  if (!version1) {
    r.partial = s.pm.splits.size() < s.h.split_count;
    if (r.partial && s.has_unknown_entries()) {
      s.drop_unknown_entries(s.pm);
      s.wedges_ready = false;  // the coders' ids are the stream's: no more of this
    }
    r.chunks_decoded = static_cast<uint32_t>(s.chunks_decoded);
    r.chunk_count = s.h.chunk_count;
  }
  std::string message;
  // A 2.x stream's splits were replayed as they were decoded: validate() less its own replay.
  if (!(version1 ? validate(s.pm, &message) : detail::validate_decoded(s.pm, &message)))
    return s.fail(corrupt(message));
  if (result != nullptr) *result = r;
  return Status::ok();
}

bool PmStreamReader::has_base() const { return state_->base_done; }
bool PmStreamReader::complete() const {
  return state_->stage == State::kDone && !state_->stopped;
}
const ProgressiveMesh& PmStreamReader::mesh() const {
  State& s = *state_;
  s.attach_carried();
  // 2.2 (§7): in the middle of a stream, entries that later splits introduce have no value
  // yet (0 in s.pm, which decoding goes on filling): the caller gets a copy without them,
  // as finish() leaves a prefix.
  // Once per decoded chunk: mesh() is asked for several times for one level.
  if (s.has_unknown_entries()) {
    if (s.trimmed_chunks != s.chunks_decoded) {
      s.trimmed = s.pm;
      s.drop_unknown_entries(s.trimmed);
      s.trimmed_chunks = s.chunks_decoded;
    }
    return s.trimmed;
  }
  return s.pm;
}
uint64_t PmStreamReader::decoded_face_count() const {
  return state_->stage == State::kVersion1 ? 0 : state_->decoded_faces;
}
uint64_t PmStreamReader::stream_face_count() const {
  return state_->stage == State::kHeader ? 0 : state_->h.faces();
}

// ---------------------------------------------------------------------------------------
// The entry points: 2.0 is written; both majors are read.

Status check_material_strings(const std::vector<std::string>& names,
                              const std::vector<std::string>& libraries) {
  return check_material_strings_impl(names, libraries);
}

Status write_pm(const ProgressiveMesh& pm, const WriteOptions& options, std::string& bytes) {
  return write_pm_v2(pm, options, bytes);
}

Status read_pm(std::string_view bytes, ProgressiveMesh& pm, const ReadOptions& options,
               ReadResult* result) {
  PmStreamReader reader(options);
  if (Status status = reader.append(bytes); !status) return status;
  if (Status status = reader.finish(result); !status) return status;
  pm = std::move(reader.state_->pm);
  return Status::ok();
}
Status read_pm(std::string_view bytes, ProgressiveMesh& pm, const ReadOptions& options) {
  return read_pm(bytes, pm, options, nullptr);
}
Status read_pm(std::string_view bytes, ProgressiveMesh& pm) {
  return read_pm(bytes, pm, ReadOptions{}, nullptr);
}

Status measure_pm_sizes(std::string_view bytes, PmSizes& sizes, const ReadOptions& options) {
  ProgressiveMesh pm;
  if (Status status = read_pm(bytes, pm, options, nullptr); !status) return status;
  if ((static_cast<uint8_t>(bytes[8]) | static_cast<uint8_t>(bytes[9]) << 8) != kMajor2) {
    return Status(ErrorCode::kUnsupportedVersion, "sizes are measured in 2.x streams (this is 1.x)");
  }
  PmSizes r;
  r.header = kHeaderSize;
  for (int k = 0; k < kChunkStreams; ++k) r.chunk_streams.emplace_back(kStreamNames[k], 0);
  r.chunk_streams_compressed.assign(kChunkStreams, 0);
  std::unique_ptr<ZSTD_DCtx, size_t (*)(ZSTD_DCtx*)> dctx(ZSTD_createDCtx(), ZSTD_freeDCtx);
  if (!dctx) return Status(ErrorCode::kInternal, "zstd: cannot create a decompression context");
  std::string raw;
  // read_pm accepted the stream: every section header and frame is whole and valid.
  for (std::size_t offset = kHeaderSize; offset < bytes.size();) {
    SectionHeader section;
    if (!read_section_header(bytes.substr(offset), section)) break;
    const uint64_t size = kSectionHeaderSize + section.stored_size;
    const std::string tag = tag_name(section.tag);
    if (!r.sections.empty() && r.sections.back().first == tag) {
      r.sections.back().second += size;
    } else {
      r.sections.emplace_back(tag, size);
    }
    if (section.tag == kTagChunk) {
      ++r.chunks;
      const std::string where = section_name(section.tag, r.chunks - 1);
      if (Status s = decompress_frame(where, bytes.substr(offset + kSectionHeaderSize, section.stored_size),
                                      section.raw_size, dctx.get(), raw);
          !s) {
        return s;
      }
      ByteReader in(raw, where, ErrorCode::kCorruptStream);
      uint64_t lengths[kChunkStreams];
      for (int k = 0; k < kChunkStreams; ++k) {
        if (!read_varint64(in, lengths[k])) return in.status();
        r.chunk_streams[k].second += lengths[k];
      }
      for (int k = 0; k < kChunkStreams; ++k) {
        std::string_view stream;
        if (!in.read_bytes(lengths[k], stream)) return in.status();
        if (stream.empty()) continue;
        std::string packed(ZSTD_compressBound(stream.size()), '\0');
        const std::size_t n = ZSTD_compress(packed.data(), packed.size(), stream.data(), stream.size(), 19);
        if (ZSTD_isError(n)) return Status(ErrorCode::kInternal, std::string("zstd: ") + ZSTD_getErrorName(n));
        r.chunk_streams_compressed[k] += n;
      }
    }
    offset += size;
  }
  sizes = std::move(r);
  return Status::ok();
}

Status read_pm_info(std::string_view bytes, PmInfo& info) {
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
}

}  // namespace pm
