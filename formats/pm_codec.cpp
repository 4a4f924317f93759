// The .pm stream: a fixed header with a CRC-32, then zstd-compressed sections
// (BASE, SPLT, WELD, CARY, LOOS). formats/pm-format.md is normative; section numbers in
// comments (§) refer to it.
//
// The reader trusts nothing: every count is checked against a hard cap and against the
// bytes actually present before anything is allocated, every zstd frame must declare the
// size its section header declares, and the decoded record goes through validate().
#include "pm/pm_codec.h"

#include <zstd.h>
#include <zstd_errors.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "byte_io.h"
#include "pm_layout.h"

namespace pm {
namespace detail {

std::string tag_name(uint32_t tag) {
  static const char kHex[] = "0123456789abcdef";
  std::string name;
  for (int i = 0; i < 4; ++i) {
    const auto c = static_cast<unsigned char>(tag >> (8 * i));
    if (std::isalnum(c)) {
      name.push_back(static_cast<char>(c));
    } else {
      name += "\\x";
      name.push_back(kHex[c >> 4]);
      name.push_back(kHex[c & 15]);
    }
  }
  return name;
}

void append_header(const Header& header, std::string& out) {
  const std::size_t start = out.size();
  ByteWriter writer(out);
  writer.put_bytes(std::string_view(kMagic, sizeof kMagic));
  writer.put_u16(header.major);
  writer.put_u16(header.minor);
  writer.put_u32(header.flags);
  writer.put_u32(header.base_vertex_count);
  writer.put_u32(header.base_face_count);
  writer.put_u32(header.split_count);
  writer.put_u32(header.loose_vertex_count);
  writer.put_u32(header.weld_count);
  writer.put_u32(header.carried_face_count);
  writer.put_u32(header.moved_face_count);
  writer.put_u32(header.split_face_count);
  writer.put_u32(header.section_count);
  writer.put_f32(header.max_error);
  writer.put_zeros(kHeaderCrcOffset - kHeaderReservedOffset);
  writer.put_u32(crc32(std::string_view(out).substr(start, kHeaderCrcOffset)));
}

namespace {

// The sections this reader knows, in the order a stream must hold them (§4.3).
enum KnownSection { kBase, kSplits, kWelds, kCarried, kLoose, kKnownSectionCount };
constexpr std::array<uint32_t, kKnownSectionCount> kKnownTags = {kTagBase, kTagSplits, kTagWelds,
                                                                 kTagCarried, kTagLoose};

int known_section(uint32_t tag) {
  const auto it = std::find(kKnownTags.begin(), kKnownTags.end(), tag);
  return it == kKnownTags.end() ? -1 : static_cast<int>(it - kKnownTags.begin());
}

// A section is present exactly when it has entries (§4.3: empty sections are omitted).
bool section_expected(const Header& h, int section) {
  switch (section) {
    case kBase:
      return h.base_vertex_count > 0 || h.base_face_count > 0;
    case kSplits:
      return h.split_count > 0;
    case kWelds:
      return h.weld_count > 0;
    case kCarried:
      return h.carried_face_count > 0;
    case kLoose:
      return h.loose_vertex_count > 0;
  }
  return false;
}

// Smallest and largest raw (decompressed) size the header counts allow: f32 fields are 4
// bytes, varints 1 to 5 (§4.4).
struct RawBounds {
  uint64_t min = 0, max = 0;
};
RawBounds raw_bounds(const Header& h, int section) {
  const uint64_t base_vertices = h.base_vertex_count, base_faces = h.base_face_count;
  const uint64_t splits = h.split_count, moved = h.moved_face_count;
  switch (section) {
    case kBase:
      return {12 * base_vertices + 3 * base_faces, 12 * base_vertices + 15 * base_faces};
    // Per split: 4 varints (u, vl, vr, moved count), 3 f32 position, 1 f32 error.
    case kSplits:
      return {20 * splits + moved, 36 * splits + 5 * moved};
    case kWelds:
      return {2 * uint64_t{h.weld_count}, 10 * uint64_t{h.weld_count}};
    case kCarried:
      return {3 * uint64_t{h.carried_face_count}, 15 * uint64_t{h.carried_face_count}};
    case kLoose:
      return {12 * uint64_t{h.loose_vertex_count}, 12 * uint64_t{h.loose_vertex_count}};
  }
  return {};
}

std::string hex32(uint32_t value) {
  static const char kHex[] = "0123456789abcdef";
  std::string text = "0x";
  for (int shift = 28; shift >= 0; shift -= 4) text.push_back(kHex[(value >> shift) & 15]);
  return text;
}

std::string version_text(const Header& h) {
  return std::to_string(h.major) + "." + std::to_string(h.minor);
}

// A stream of a later minor version may use flag bits this reader does not know: that
// is a feature it lacks, not damage. In a version it knows, the same bits are corruption.
ErrorCode unknown_feature_code(const Header& h) {
  return h.minor > kFormatMinor ? ErrorCode::kUnsupportedVersion : ErrorCode::kCorruptStream;
}

Status check_count(uint32_t count, const char* what) {
  if (count <= kMaxCount) return Status::ok();
  return Status(ErrorCode::kResourceLimit, "header: " + std::to_string(count) + " " + what +
                                               " exceed the limit of " + std::to_string(kMaxCount));
}

// Counts against the bytes that follow the header: every present section needs its
// 24-byte header and a zstd frame that can expand to at least its minimum raw size.
Status check_plausible_size(const Header& h, std::size_t stream_size) {
  const uint64_t available = stream_size - kHeaderSize;
  uint64_t needed = 0;
  uint32_t expected_sections = 0;
  for (int section = 0; section < kKnownSectionCount; ++section) {
    if (!section_expected(h, section)) continue;
    ++expected_sections;
    const uint64_t min_raw = raw_bounds(h, section).min;
    const uint64_t min_frame = (min_raw + kMaxZstdRatio - 1) / kMaxZstdRatio;
    needed += kSectionHeaderSize + std::max(kMinZstdFrameSize, min_frame);
  }
  if (h.section_count < expected_sections) {
    return Status(ErrorCode::kCorruptStream, "header: " + std::to_string(h.section_count) +
                                                 " sections declared, the counts need " +
                                                 std::to_string(expected_sections));
  }
  needed = std::max(needed, uint64_t{h.section_count} * kSectionHeaderSize);
  if (needed > available) {
    return Status(ErrorCode::kTruncatedStream, "truncated after header (the counts need at least " +
                                                   std::to_string(needed) + " bytes of sections, " +
                                                   std::to_string(available) + " left)");
  }
  return Status::ok();
}

}  // namespace

Status parse_header(std::string_view bytes, Header& header) {
  // Magic first: a short stream that is a prefix of the magic is truncated, anything
  // else is not a .pm stream at all.
  const std::size_t magic_bytes = std::min(bytes.size(), sizeof kMagic);
  if (bytes.substr(0, magic_bytes) != std::string_view(kMagic, magic_bytes)) {
    return Status(ErrorCode::kCorruptStream, "not a .pm stream (bad magic)");
  }
  ByteReader in(bytes, "header", ErrorCode::kTruncatedStream);
  std::string_view header_bytes;
  if (!in.read_bytes(kHeaderSize, header_bytes)) return in.status();

  // The reads cannot fail: header_bytes holds all 96 bytes.
  ByteReader fields(header_bytes, "header", ErrorCode::kTruncatedStream);
  Header h;
  uint32_t stored_crc = 0;
  fields.skip(sizeof kMagic);
  fields.read_u16(h.major);
  fields.read_u16(h.minor);
  fields.read_u32(h.flags);
  fields.read_u32(h.base_vertex_count);
  fields.read_u32(h.base_face_count);
  fields.read_u32(h.split_count);
  fields.read_u32(h.loose_vertex_count);
  fields.read_u32(h.weld_count);
  fields.read_u32(h.carried_face_count);
  fields.read_u32(h.moved_face_count);
  fields.read_u32(h.split_face_count);
  fields.read_u32(h.section_count);
  fields.read_f32(h.max_error);
  fields.skip(kHeaderCrcOffset - kHeaderReservedOffset);
  fields.read_u32(stored_crc);

  // Then the CRC, before any field is believed, so that a damaged version field is
  // reported as damage rather than as a version this reader lacks.
  const uint32_t computed_crc = crc32(header_bytes.substr(0, kHeaderCrcOffset));
  if (stored_crc != computed_crc) {
    return Status(ErrorCode::kChecksumMismatch, "header: checksum mismatch (stored " +
                                                    hex32(stored_crc) + ", computed " +
                                                    hex32(computed_crc) + ")");
  }

  if (h.major != kFormatMajor) {
    return Status(ErrorCode::kUnsupportedVersion, "header: format version " + version_text(h) +
                                                      " is not supported (this reader reads " +
                                                      std::to_string(kFormatMajor) + ".x)");
  }
  if (h.flags != 0) {
    return Status(unknown_feature_code(h),
                  h.minor > kFormatMinor
                      ? "header: format " + version_text(h) +
                            " uses features this reader lacks (flags " + hex32(h.flags) + ")"
                      : "header: reserved flag bits " + hex32(h.flags) + " set");
  }
  // A later minor may put fields that older readers can ignore in the reserved bytes
  // (§3.2); in a version this reader knows they must be zero.
  if (h.minor <= kFormatMinor) {
    for (std::size_t i = kHeaderReservedOffset; i < kHeaderCrcOffset; ++i) {
      if (header_bytes[i] != 0) {
        return Status(ErrorCode::kCorruptStream,
                      "header: reserved byte " + std::to_string(i) + " is " +
                          std::to_string(static_cast<uint8_t>(header_bytes[i])) + ", must be 0");
      }
    }
  }

  const std::pair<uint32_t, const char*> counts[] = {{h.base_vertex_count, "base vertices"},
                                                     {h.base_face_count, "base faces"},
                                                     {h.split_count, "splits"},
                                                     {h.loose_vertex_count, "loose vertices"},
                                                     {h.weld_count, "welds"},
                                                     {h.carried_face_count, "carried faces"},
                                                     {h.moved_face_count, "moved faces"},
                                                     {h.split_face_count, "split faces"}};
  for (const auto& [count, what] : counts) {
    if (Status status = check_count(count, what); !status) return status;
  }
  // Each split adds one face or two.
  if (h.split_face_count < h.split_count || h.split_face_count > 2 * uint64_t{h.split_count}) {
    return Status(ErrorCode::kCorruptStream,
                  "header: " + std::to_string(h.split_face_count) + " split faces for " +
                      std::to_string(h.split_count) + " splits (each adds 1 or 2)");
  }
  // Copies are distinct base vertices.
  if (h.weld_count > h.base_vertex_count) {
    return Status(ErrorCode::kCorruptStream,
                  "header: " + std::to_string(h.weld_count) + " welds for " +
                      std::to_string(h.base_vertex_count) + " base vertices");
  }
  if (h.split_count == 0 && h.moved_face_count != 0) {
    return Status(ErrorCode::kCorruptStream,
                  "header: " + std::to_string(h.moved_face_count) + " moved faces but no splits");
  }
  if (!(h.max_error >= 0.0f && h.max_error <= std::numeric_limits<float>::max())) {
    return Status(ErrorCode::kCorruptStream,
                  "header: max error " + std::to_string(h.max_error) + " is not finite and >= 0");
  }
  if (Status status = check_plausible_size(h, bytes.size()); !status) return status;
  header = h;
  return Status::ok();
}

namespace {

struct FreeCompressContext {
  void operator()(ZSTD_CCtx* context) const { ZSTD_freeCCtx(context); }
};
struct FreeDecompressContext {
  void operator()(ZSTD_DCtx* context) const { ZSTD_freeDCtx(context); }
};
using CompressContext = std::unique_ptr<ZSTD_CCtx, FreeCompressContext>;
using DecompressContext = std::unique_ptr<ZSTD_DCtx, FreeDecompressContext>;

}  // namespace

Status append_section(uint32_t tag, uint32_t flags, std::string_view raw,
                      uint64_t declared_raw_size, int zstd_level, std::string& out) {
  CompressContext context(ZSTD_createCCtx());
  if (!context) return Status(ErrorCode::kInternal, "zstd: cannot create a compression context");
  ZSTD_CCtx* cctx = context.get();
  for (const auto& [parameter, value] :
       {std::pair{ZSTD_c_compressionLevel, zstd_level}, std::pair{ZSTD_c_checksumFlag, 1},
        std::pair{ZSTD_c_contentSizeFlag, 1}}) {
    const size_t result = ZSTD_CCtx_setParameter(cctx, parameter, value);
    if (ZSTD_isError(result)) {
      return Status(ErrorCode::kInvalidArgument, std::string("zstd: ") + ZSTD_getErrorName(result));
    }
  }
  std::string frame(ZSTD_compressBound(raw.size()), '\0');
  const size_t frame_size =
      ZSTD_compress2(cctx, frame.data(), frame.size(), raw.data(), raw.size());
  if (ZSTD_isError(frame_size)) {
    return Status(ErrorCode::kInternal,
                  "section " + tag_name(tag) + ": zstd: " + ZSTD_getErrorName(frame_size));
  }
  frame.resize(frame_size);
  ByteWriter writer(out);
  writer.put_u32(tag);
  writer.put_u32(flags);
  writer.put_u64(frame.size());
  writer.put_u64(declared_raw_size);
  writer.put_bytes(frame);
  return Status::ok();
}

namespace {

// ---------------------------------------------------------------------------------------
// Section payloads (§5). Encoders and decoders in matching pairs.

void put_positions(ByteWriter& out, const std::vector<float>& positions, std::size_t first_vertex,
                   std::size_t vertex_count) {
  for (std::size_t i = 3 * first_vertex; i < 3 * (first_vertex + vertex_count); ++i) {
    out.put_f32(positions[i]);
  }
}

bool read_positions(ByteReader& in, std::size_t vertex_count, std::vector<float>& positions) {
  for (std::size_t i = 0; i < 3 * vertex_count; ++i) {
    float value;
    if (!in.read_f32(value)) return false;
    positions.push_back(value);
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

std::string encode_base(const ProgressiveMesh& pm) {
  std::string raw;
  ByteWriter out(raw);
  put_positions(out, pm.positions, 0, pm.base_vertex_count);
  for (uint32_t index : pm.base_faces) out.put_varint(index);
  return raw;
}

bool decode_base(ByteReader& in, const Header& h, ProgressiveMesh& pm) {
  return read_positions(in, h.base_vertex_count, pm.positions) &&
         read_varints(in, 3 * std::size_t{h.base_face_count}, pm.base_faces);
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
  put_positions(out, pm.positions, base, pm.splits.size());
  for (const VertexSplit& split : pm.splits) out.put_f32(split.error);
  return raw;
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
  for (VertexSplit& split : pm.splits) {
    uint32_t code;
    if (!in.read_varint(code)) return false;
    split.vl = decode_optional_vertex(code);
    split_faces += split.vl != kNoVertex;
  }
  for (VertexSplit& split : pm.splits) {
    uint32_t code;
    if (!in.read_varint(code)) return false;
    split.vr = decode_optional_vertex(code);
    split_faces += split.vr != kNoVertex;
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
  if (!read_positions(in, h.split_count, pm.positions)) return false;
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
  return read_varints(in, 3 * std::size_t{h.carried_face_count}, pm.carried_faces);
}

std::string encode_loose(const ProgressiveMesh& pm) {
  std::string raw;
  ByteWriter out(raw);
  put_positions(out, pm.positions, pm.base_vertex_count + pm.splits.size(), pm.loose_vertex_count);
  return raw;
}

bool decode_loose(ByteReader& in, const Header& h, ProgressiveMesh& pm) {
  return read_positions(in, h.loose_vertex_count, pm.positions);
}

using SectionEncoder = std::string (*)(const ProgressiveMesh&);
using SectionDecoder = bool (*)(ByteReader&, const Header&, ProgressiveMesh&);
constexpr std::array<SectionEncoder, kKnownSectionCount> kEncoders = {
    encode_base, encode_splits, encode_welds, encode_carried, encode_loose};
constexpr std::array<SectionDecoder, kKnownSectionCount> kDecoders = {
    decode_base, decode_splits, decode_welds, decode_carried, decode_loose};

// ---------------------------------------------------------------------------------------

Header header_for(const ProgressiveMesh& pm) {
  Header h;
  h.major = kFormatMajor;
  h.minor = kFormatMinor;
  h.base_vertex_count = pm.base_vertex_count;
  h.base_face_count = static_cast<uint32_t>(pm.base_face_count());
  h.split_count = static_cast<uint32_t>(pm.split_count());
  h.loose_vertex_count = pm.loose_vertex_count;
  h.weld_count = static_cast<uint32_t>(pm.welds.size());
  h.carried_face_count = static_cast<uint32_t>(pm.carried_faces.size() / 3);
  h.moved_face_count = static_cast<uint32_t>(pm.moved_faces.size());
  for (const VertexSplit& split : pm.splits) h.split_face_count += split.new_face_count();
  h.max_error = pm.splits.empty() ? 0.0f : pm.splits[0].error;
  for (int section = 0; section < kKnownSectionCount; ++section) {
    h.section_count += section_expected(h, section);
  }
  return h;
}

// One zstd frame, exactly `frame.size()` bytes, with a content checksum and a content
// size equal to the section's raw size (§4.2), decompressed into `raw`.
Status decompress_frame(const std::string& where, std::string_view frame, uint64_t raw_size,
                        ZSTD_DCtx* dctx, std::string& raw) {
  uint32_t magic = 0;
  if (frame.size() >= 4) ByteReader(frame, where, ErrorCode::kCorruptStream).read_u32(magic);
  if (frame.size() < 5 || magic != ZSTD_MAGICNUMBER) {
    return Status(ErrorCode::kCorruptStream, where + ": payload is not a zstd frame");
  }
  // Frame_Header_Descriptor (RFC 8878 §3.1.1.1.1): bits 0-1 dictionary id size,
  // bit 2 content checksum.
  const auto descriptor = static_cast<uint8_t>(frame[4]);
  if ((descriptor & 0x04) == 0) {
    return Status(ErrorCode::kCorruptStream, where + ": zstd frame has no content checksum");
  }
  if ((descriptor & 0x03) != 0) {
    return Status(ErrorCode::kCorruptStream, where + ": zstd frame needs a dictionary");
  }
  const size_t frame_size = ZSTD_findFrameCompressedSize(frame.data(), frame.size());
  if (ZSTD_isError(frame_size)) {
    return Status(ErrorCode::kCorruptStream,
                  where + ": malformed zstd frame (" + ZSTD_getErrorName(frame_size) + ")");
  }
  if (frame_size != frame.size()) {
    return Status(
        ErrorCode::kCorruptStream,
        where + ": " + std::to_string(frame.size() - frame_size) + " bytes follow the zstd frame");
  }
  const unsigned long long content_size = ZSTD_getFrameContentSize(frame.data(), frame.size());
  if (content_size == ZSTD_CONTENTSIZE_UNKNOWN || content_size == ZSTD_CONTENTSIZE_ERROR) {
    return Status(ErrorCode::kCorruptStream, where + ": zstd frame does not state its size");
  }
  if (content_size != raw_size) {
    return Status(ErrorCode::kCorruptStream,
                  where + ": zstd frame holds " + std::to_string(content_size) +
                      " bytes, the section declares " + std::to_string(raw_size));
  }
  raw.resize(static_cast<std::size_t>(raw_size));
  const size_t result =
      ZSTD_decompressDCtx(dctx, raw.data(), raw.size(), frame.data(), frame.size());
  if (ZSTD_isError(result)) {
    if (ZSTD_getErrorCode(result) == ZSTD_error_checksum_wrong) {
      return Status(ErrorCode::kChecksumMismatch, where + ": content checksum mismatch");
    }
    return Status(ErrorCode::kCorruptStream, where + ": zstd: " + ZSTD_getErrorName(result));
  }
  if (result != raw_size) {
    return Status(ErrorCode::kCorruptStream, where + ": zstd frame decoded to " +
                                                 std::to_string(result) + " bytes, expected " +
                                                 std::to_string(raw_size));
  }
  return Status::ok();
}

bool is_tag_character(uint8_t c) {
  return (c >= '0' && c <= '9') || (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z');
}

}  // namespace
}  // namespace detail

using namespace detail;  // NOLINT: the layout helpers are this file's vocabulary

Status write_pm(const ProgressiveMesh& pm, const WriteOptions& options, std::string& bytes) {
  std::string message;
  if (!validate(pm, &message)) {
    return Status(ErrorCode::kInvalidArgument,
                  "cannot write an invalid progressive mesh: " + message);
  }
  // The reader's limits (§7), checked before the counts are narrowed to u32.
  std::size_t split_face_count = 0;
  for (const VertexSplit& split : pm.splits) split_face_count += split.new_face_count();
  const std::size_t counts[] = {pm.base_vertex_count,  pm.base_face_count(),
                                pm.split_count(),      pm.loose_vertex_count,
                                pm.welds.size(),       pm.carried_faces.size() / 3,
                                pm.moved_faces.size(), split_face_count};
  for (std::size_t count : counts) {
    if (count > kMaxCount) {
      return Status(ErrorCode::kResourceLimit, "a count of " + std::to_string(count) +
                                                   " exceeds the .pm limit of " +
                                                   std::to_string(kMaxCount));
    }
  }
  if (options.zstd_level < 1 || options.zstd_level > ZSTD_maxCLevel()) {
    return Status(ErrorCode::kInvalidArgument, "zstd level " + std::to_string(options.zstd_level) +
                                                   " is outside 1.." +
                                                   std::to_string(ZSTD_maxCLevel()));
  }
  const Header header = header_for(pm);
  std::string out;
  append_header(header, out);
  for (int section = 0; section < kKnownSectionCount; ++section) {
    if (!section_expected(header, section)) continue;
    const std::string raw = kEncoders[section](pm);
    if (Status status = append_section(kKnownTags[section], kSectionRequired, raw, raw.size(),
                                       options.zstd_level, out);
        !status) {
      return status;
    }
  }
  bytes = std::move(out);
  return Status::ok();
}

Status read_pm(std::string_view bytes, ProgressiveMesh& pm) {
  return read_pm(bytes, pm, ReadOptions{});
}

Status read_pm(std::string_view bytes, ProgressiveMesh& pm, const ReadOptions& options) {
  (void)options;  // TODO(issue 9): bound the allocation by options.max_memory
  Header h;
  if (Status status = parse_header(bytes, h); !status) return status;

  DecompressContext dctx(ZSTD_createDCtx());
  if (!dctx) return Status(ErrorCode::kInternal, "zstd: cannot create a decompression context");

  ProgressiveMesh out;
  out.base_vertex_count = h.base_vertex_count;
  out.loose_vertex_count = h.loose_vertex_count;
  ByteReader file(bytes, "header", ErrorCode::kTruncatedStream);
  file.skip(kHeaderSize);
  int next_known = 0;  // known sections must come in order, each at most once
  std::string raw;
  for (uint32_t s = 0; s < h.section_count; ++s) {
    // The 24 bytes as one unit, so a cut reports the section header it falls in.
    file.set_where("section " + std::to_string(s) + " header");
    std::string_view section_header;
    if (!file.read_bytes(kSectionHeaderSize, section_header)) return file.status();
    ByteReader fields(section_header, file.where(), ErrorCode::kTruncatedStream);
    uint32_t tag = 0, flags = 0;
    uint64_t stored_size = 0, raw_size = 0;
    fields.read_u32(tag);  // cannot fail: all 24 bytes are there
    fields.read_u32(flags);
    fields.read_u64(stored_size);
    fields.read_u64(raw_size);
    for (int i = 0; i < 4; ++i) {
      if (!is_tag_character(static_cast<uint8_t>(tag >> (8 * i)))) {
        return Status(ErrorCode::kCorruptStream, "section " + std::to_string(s) + ": tag " +
                                                     tag_name(tag) +
                                                     " is not four ascii letters or digits");
      }
    }
    const std::string where = "section " + tag_name(tag);
    file.set_where(where);
    std::string_view frame;
    const int section = known_section(tag);
    if (section < 0) {
      // §4.1: an unknown section may be skipped only when it is not required.
      if (flags & kSectionRequired) {
        return Status(ErrorCode::kUnsupportedVersion, where + ": unknown section marked required");
      }
      if (!file.read_bytes(stored_size, frame)) return file.status();
      continue;
    }
    if (section < next_known) {
      return Status(ErrorCode::kCorruptStream, where + ": repeated or out of order");
    }
    for (int skipped = next_known; skipped < section; ++skipped) {
      if (section_expected(h, skipped)) {
        return Status(ErrorCode::kCorruptStream, "section " + tag_name(kKnownTags[skipped]) +
                                                     " missing (before " + where + ")");
      }
    }
    next_known = section + 1;
    if ((flags & kSectionRequired) == 0) {
      return Status(ErrorCode::kCorruptStream, where + ": required flag is clear");
    }
    if ((flags & ~kSectionRequired) != 0) {
      return Status(unknown_feature_code(h),
                    where + ": reserved flag bits " + hex32(flags & ~kSectionRequired) + " set");
    }
    if (!section_expected(h, section)) {
      return Status(ErrorCode::kCorruptStream,
                    where + ": present, but the header counts no entries");
    }
    if (!file.read_bytes(stored_size, frame)) return file.status();
    // Sizes are checked before the raw buffer is allocated: the counts bound it, and so
    // does zstd's largest possible expansion of the bytes actually present.
    const RawBounds bounds = raw_bounds(h, section);
    if (raw_size < bounds.min || raw_size > bounds.max) {
      return Status(ErrorCode::kCorruptStream,
                    where + ": raw size " + std::to_string(raw_size) + ", the counts allow " +
                        (bounds.min == bounds.max
                             ? std::to_string(bounds.min)
                             : std::to_string(bounds.min) + " to " + std::to_string(bounds.max)));
    }
    if (raw_size > stored_size * kMaxZstdRatio) {
      return Status(ErrorCode::kCorruptStream, where + ": raw size " + std::to_string(raw_size) +
                                                   " is impossible for " +
                                                   std::to_string(stored_size) + " stored bytes");
    }
    if (Status status = decompress_frame(where, frame, raw_size, dctx.get(), raw); !status) {
      return status;
    }
    ByteReader payload(raw, where, ErrorCode::kCorruptStream);
    if (!kDecoders[section](payload, h, out)) return payload.status();
    if (!payload.at_end()) {
      return Status(ErrorCode::kCorruptStream, where + ": " + std::to_string(payload.remaining()) +
                                                   " bytes left after the last entry");
    }
  }
  for (int skipped = next_known; skipped < kKnownSectionCount; ++skipped) {
    if (section_expected(h, skipped)) {
      return Status(ErrorCode::kCorruptStream,
                    "section " + tag_name(kKnownTags[skipped]) + " missing");
    }
  }
  if (!file.at_end()) {
    return Status(ErrorCode::kCorruptStream,
                  std::to_string(file.remaining()) + " trailing bytes after the last section");
  }
  // The header repeats the first split's error so that --info needs no decompression.
  const float expected_max_error = out.splits.empty() ? 0.0f : out.splits[0].error;
  if (std::memcmp(&expected_max_error, &h.max_error, sizeof(float)) != 0) {
    return Status(ErrorCode::kCorruptStream, "header: max error " + std::to_string(h.max_error) +
                                                 " differs from split 0's " +
                                                 std::to_string(expected_max_error));
  }
  std::string message;
  if (!validate(out, &message)) return Status(ErrorCode::kCorruptStream, message);
  pm = std::move(out);
  return Status::ok();
}

Status read_pm_info(std::string_view bytes, PmInfo& info) {
  Header h;
  if (Status status = parse_header(bytes, h); !status) return status;
  PmInfo result;
  result.major = h.major;
  result.minor = h.minor;
  result.flags = h.flags;
  result.base_vertex_count = h.base_vertex_count;
  result.base_face_count = h.base_face_count;
  result.split_count = h.split_count;
  result.loose_vertex_count = h.loose_vertex_count;
  result.weld_count = h.weld_count;
  result.carried_face_count = h.carried_face_count;
  result.moved_face_count = h.moved_face_count;
  result.split_face_count = h.split_face_count;
  result.section_count = h.section_count;
  // Welded copies are output as their canonical vertex, so they are not counted.
  result.full_vertex_count =
      uint64_t{h.base_vertex_count} + h.split_count + h.loose_vertex_count - h.weld_count;
  result.full_face_count = uint64_t{h.base_face_count} + h.split_face_count + h.carried_face_count;
  result.max_error = h.max_error;
  info = result;
  return Status::ok();
}

}  // namespace pm
