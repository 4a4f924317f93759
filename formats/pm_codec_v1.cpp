// The .pm stream of format 1.x (1.0 and 1.1): a fixed header with a CRC-32, then
// zstd-compressed sections (BASE, SPLT, WELD, CARY, LOOS; since 1.1 the attribute sections
// COLR, UVS0, NRML, MATL). Since format 2.0 (pm_codec_v2.cpp) this is the reader of older
// files, and a writer kept for tests and golden files. formats/pm-format-1.md is normative
// for it; section numbers in comments (§) refer to it.
//
// The reader trusts nothing and validates before it allocates: every count is checked
// against a hard cap and against the bytes actually present, every section header is
// checked (tag, order, flags, sizes) before any section is decompressed, the memory the
// decode will take is computed from those checked numbers and compared with
// ReadOptions::max_memory, every zstd frame must declare the size its section header
// declares (RFC 8878 §3.1.1.1.4, Frame_Content_Size) and cannot decode past it, and the
// decoded record goes through validate().
//
// This file holds the header, the checks of the section headers and the entry points;
// the section payloads are in v1/sections.cpp, what both majors share in pm_layout.cpp.
#include "pm/pm_codec.h"

#include <zstd.h>
#include <zstd_errors.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstring>
#include <limits>
#include <memory>
#include <new>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "byte_io.h"
#include "corner_codes.h"
#include "pm_layout.h"
#include "v1/sections.h"

namespace pm {
namespace detail {

using namespace v1;  // NOLINT: the sections are this file's vocabulary

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
  writer.put_u32(header.attributes);  // offset 56: the 1.1 fields
  writer.put_u32(header.color_components);
  writer.put_u32(header.uv_count);
  writer.put_u32(header.normal_count);
  writer.put_u32(header.material_count);
  writer.put_u32(header.material_library_count);
  writer.put_u32(header.material_string_bytes);
  writer.put_zeros(kHeaderCrcOffset - kHeaderReservedOffset);
  writer.put_u32(crc32(std::string_view(out).substr(start, kHeaderCrcOffset)));
}

namespace {

// The known section with this tag in a stream of this version, or -1. In a 1.0 stream the
// 1.1 tags are not known: there they can only be private sections (§4.1).
int known_section(const Header& h, uint32_t tag) {
  const auto it = std::find(kKnownTags.begin(), kKnownTags.end(), tag);
  if (it == kKnownTags.end()) return -1;
  const int section = static_cast<int>(it - kKnownTags.begin());
  return is_attribute_section(section) && h.minor < kMinorWithAttributes ? -1 : section;
}

int known_section_count(const Header& h) {
  return h.minor < kMinorWithAttributes ? kFirstAttributeSection : kKnownSectionCount;
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
    case kColors:
      return h.color_components > 0 && all_vertices(h) > 0;
    case kUvs:
      return h.uv_count > 0 || (h.attributes & kAttributeUvIds) != 0;
    case kNormals:
      return h.normal_count > 0 || (h.attributes & kAttributeNormalIds) != 0;
    case kMaterials:
      return h.material_count > 0 || h.material_library_count > 0 ||
             (h.attributes & kAttributeMaterialIds) != 0;
  }
  return false;
}

// Smallest and largest raw (decompressed) size the header counts allow: f32 fields are 4
// bytes, varints 1 to 5, or fewer where the value is bounded (§4.4).
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
    case kColors: {
      const uint64_t size = 4 * uint64_t{h.color_components} * all_vertices(h);
      return {size, size};
    }
    case kUvs:
    case kNormals: {
      const bool uvs = section == kUvs;
      const uint64_t table = uvs ? 8 * uint64_t{h.uv_count} : 12 * uint64_t{h.normal_count};
      const bool ids = (h.attributes & (uvs ? kAttributeUvIds : kAttributeNormalIds)) != 0;
      const uint64_t codes = ids ? corner_codes(h) : 0;
      return {table + codes, table + 5 * codes};
    }
    case kMaterials: {
      // A length varint of 1 or 2 bytes per string (lengths <= 4096 < 2^14), the strings'
      // bytes, and one id varint of 1 to 3 bytes per face (ids + 1 <= 2^20 < 2^21).
      const uint64_t strings = uint64_t{h.material_count} + h.material_library_count;
      const uint64_t ids = (h.attributes & kAttributeMaterialIds) != 0 ? all_faces(h) : 0;
      return {strings + h.material_string_bytes + ids,
              2 * strings + h.material_string_bytes + 3 * ids};
    }
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

// A stream of a later minor version may use flag bits or sections this reader does not
// know: that is a feature it lacks, not damage. In a version it knows, they are corruption.
ErrorCode unknown_feature_code(const Header& h) {
  return h.minor > kMinor1 ? ErrorCode::kUnsupportedVersion : ErrorCode::kCorruptStream;
}

Status check_count(uint32_t count, uint32_t limit, const char* what) {
  if (count <= limit) return Status::ok();
  return Status(ErrorCode::kResourceLimit, "header: " + std::to_string(count) + " " + what +
                                               " exceed the limit of " + std::to_string(limit));
}

// Counts against the bytes that follow the header: every present section needs its
// 24-byte header and a zstd frame that can expand to at least its minimum raw size.
Status check_plausible_size(const Header& h, std::size_t stream_size) {
  const uint64_t available = stream_size - kHeaderSize;
  uint64_t needed = 0;
  uint32_t expected_sections = 0;
  for (int section = 0; section < known_section_count(h); ++section) {
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

// §3.3 step 5: flags, the 1.1 attribute bits and reserved bytes.
Status check_reserved(const Header& h, std::string_view header_bytes) {
  if (h.flags != 0) {
    return Status(unknown_feature_code(h),
                  h.minor > kMinor1
                      ? "header: format " + version_text(h) +
                            " uses features this reader lacks (flags " + hex32(h.flags) + ")"
                      : "header: reserved flag bits " + hex32(h.flags) + " set");
  }
  // A later minor may put fields that older readers can ignore in the reserved bytes and
  // the attribute bits (§3.2); in a version this reader knows they must be zero. In 1.0
  // the attribute fields themselves are reserved bytes.
  if (h.minor > kMinor1) return Status::ok();
  const std::size_t first_reserved =
      h.minor < kMinorWithAttributes ? kHeaderAttributesOffset : kHeaderReservedOffset;
  for (std::size_t i = first_reserved; i < kHeaderCrcOffset; ++i) {
    if (header_bytes[i] != 0) {
      return Status(ErrorCode::kCorruptStream,
                    "header: reserved byte " + std::to_string(i) + " is " +
                        std::to_string(static_cast<uint8_t>(header_bytes[i])) + ", must be 0");
    }
  }
  if ((h.attributes & ~kKnownAttributeBits) != 0) {
    return Status(
        ErrorCode::kCorruptStream,
        "header: reserved attribute bits " + hex32(h.attributes & ~kKnownAttributeBits) + " set");
  }
  return Status::ok();
}

// §3.3 steps 6 and 7.
Status check_counts(const Header& h) {
  const std::pair<uint32_t, const char*> counts[] = {
      {h.base_vertex_count, "base vertices"},
      {h.base_face_count, "base faces"},
      {h.split_count, "splits"},
      {h.loose_vertex_count, "loose vertices"},
      {h.weld_count, "welds"},
      {h.carried_face_count, "carried faces"},
      {h.moved_face_count, "moved faces"},
      {h.split_face_count, "split faces"},
      {h.uv_count, "texture coordinates"},
      {h.normal_count, "normals"},
      {h.material_string_bytes, "bytes of material strings"}};
  for (const auto& [count, what] : counts) {
    if (Status status = check_count(count, kMaxCount, what); !status) return status;
  }
  if (Status status = check_count(h.material_count, kMaxMaterials, "materials"); !status) {
    return status;
  }
  if (Status status = check_count(h.material_library_count, kMaxMaterials, "material libraries");
      !status) {
    return status;
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
  if (h.color_components != 0 && h.color_components != 3 && h.color_components != 4) {
    return Status(ErrorCode::kCorruptStream, "header: " + std::to_string(h.color_components) +
                                                 " colour components (0, 3 or 4)");
  }
  // An id array of a mesh without faces is empty, which is "absent" in memory.
  if ((h.attributes & kKnownAttributeBits) != 0 && all_faces(h) == 0) {
    return Status(ErrorCode::kCorruptStream, "header: attribute ids " +
                                                 hex32(h.attributes & kKnownAttributeBits) +
                                                 " declared for a mesh without faces");
  }
  const uint64_t strings = uint64_t{h.material_count} + h.material_library_count;
  if (h.material_string_bytes > strings * kMaxStringBytes) {
    return Status(ErrorCode::kCorruptStream, "header: " + std::to_string(h.material_string_bytes) +
                                                 " bytes of " + std::to_string(strings) +
                                                 " material strings (at most " +
                                                 std::to_string(kMaxStringBytes) + " each)");
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
  fields.read_u32(h.attributes);
  fields.read_u32(h.color_components);
  fields.read_u32(h.uv_count);
  fields.read_u32(h.normal_count);
  fields.read_u32(h.material_count);
  fields.read_u32(h.material_library_count);
  fields.read_u32(h.material_string_bytes);
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
  if (h.major != kMajor1) {
    return Status(ErrorCode::kUnsupportedVersion, "header: format version " + version_text(h) +
                                                      " is not supported (this reader reads " +
                                                      std::to_string(kMajor1) + ".x)");
  }
  if (Status status = check_reserved(h, header_bytes); !status) return status;
  // Attribute bits of a later minor are may-ignore (§3.2): this reader sees its own only.
  h.attributes &= kKnownAttributeBits;
  if (Status status = check_counts(h); !status) return status;
  if (Status status = check_plausible_size(h, bytes.size()); !status) return status;
  header = h;
  return Status::ok();
}

namespace {

struct FreeDecompressContext {
  void operator()(ZSTD_DCtx* context) const { ZSTD_freeDCtx(context); }
};
using DecompressContext = std::unique_ptr<ZSTD_DCtx, FreeDecompressContext>;

}  // namespace

uint64_t decode_memory(const Header& h, uint64_t largest_raw_size) {
  const uint64_t vertices = all_vertices(h), faces = all_faces(h);
  const uint64_t split_faces = uint64_t{h.base_face_count} + h.split_face_count;
  const uint64_t strings = uint64_t{h.material_count} + h.material_library_count;
  const bool uv_ids = (h.attributes & kAttributeUvIds) != 0;
  const bool normal_ids = (h.attributes & kAttributeNormalIds) != 0;
  const bool material_ids = (h.attributes & kAttributeMaterialIds) != 0;
  // The decoded ProgressiveMesh (§7.1, "mesh").
  uint64_t mesh = 4 * 3 * vertices                                   // positions
                  + 4 * 3 * uint64_t{h.base_face_count}              // base_faces
                  + sizeof(VertexSplit) * uint64_t{h.split_count}    // splits
                  + 4 * uint64_t{h.moved_face_count}                 // moved_faces
                  + sizeof(Weld) * uint64_t{h.weld_count}            // welds
                  + 4 * 3 * uint64_t{h.carried_face_count}           // carried_faces
                  + 4 * uint64_t{h.color_components} * vertices      // colors
                  + 4 * 2 * uint64_t{h.uv_count}                     // uvs
                  + 4 * 3 * uint64_t{h.normal_count}                 // normals
                  + sizeof(std::string) * strings                    // material names, libraries
                  + uint64_t{h.material_string_bytes} + strings;     // their heap, with a NUL each
  const uint64_t corner_ids = 4 * (3 * faces + h.moved_face_count);  // face_* and moved_*
  mesh +=
      (uv_ids ? corner_ids : 0) + (normal_ids ? corner_ids : 0) + (material_ids ? 4 * faces : 0);
  // While sections are decoded: one raw buffer (the largest section's), the corner-id
  // predictor's last id per vertex (UVS0, NRML), the zstd context.
  const uint64_t predictor =
      uv_ids || normal_ids ? 4 * (uint64_t{h.base_vertex_count} + h.split_count) : 0;
  const uint64_t decoding = largest_raw_size + predictor + kZstdContextBytes;
  // While validate() runs, after those are freed: the faces replayed with one marker each
  // (16 bytes per base or split face) and a bit per base vertex for the welds.
  const uint64_t validating = 16 * split_faces + 8 * ((uint64_t{h.base_vertex_count} + 63) / 64);
  return mesh + std::max(decoding, validating) + kDecodeMemorySlack;
}

namespace {

Header header_for(const ProgressiveMesh& pm) {
  Header h;
  h.major = kMajor1;
  h.minor = kMinor1;
  h.base_vertex_count = pm.base_vertex_count;
  h.base_face_count = static_cast<uint32_t>(pm.base_face_count());
  h.split_count = static_cast<uint32_t>(pm.split_count());
  h.loose_vertex_count = pm.loose_vertex_count;
  h.weld_count = static_cast<uint32_t>(pm.welds.size());
  h.carried_face_count = static_cast<uint32_t>(pm.carried_faces.size() / 3);
  h.moved_face_count = static_cast<uint32_t>(pm.moved_faces.size());
  for (const VertexSplit& split : pm.splits) h.split_face_count += split.new_face_count();
  h.max_error = pm.splits.empty() ? 0.0f : pm.splits[0].error;
  h.attributes = (pm.has_uvs() ? kAttributeUvIds : 0) |
                 (pm.has_normals() ? kAttributeNormalIds : 0) |
                 (pm.has_materials() ? kAttributeMaterialIds : 0);
  h.color_components = pm.color_components;
  h.uv_count = static_cast<uint32_t>(pm.uv_count());
  h.normal_count = static_cast<uint32_t>(pm.normal_count());
  h.material_count = static_cast<uint32_t>(pm.material_names.size());
  h.material_library_count = static_cast<uint32_t>(pm.material_libraries.size());
  for (const auto* strings : {&pm.material_names, &pm.material_libraries}) {
    for (const std::string& text : *strings) {
      h.material_string_bytes += static_cast<uint32_t>(text.size());
    }
  }
  for (int section = 0; section < kKnownSectionCount; ++section) {
    h.section_count += section_expected(h, section);
  }
  return h;
}

// What write_pm refuses beyond validate(): the reader's limits (§7), checked before the
// counts are narrowed to u32, and strings the format cannot hold.
Status check_writable(const ProgressiveMesh& pm) {
  std::size_t split_face_count = 0;
  for (const VertexSplit& split : pm.splits) split_face_count += split.new_face_count();
  if (Status s = check_material_strings(pm.material_names, pm.material_libraries); !s) return s;
  std::size_t string_bytes = 0;
  for (const auto* strings : {&pm.material_names, &pm.material_libraries})
    for (const std::string& text : *strings) string_bytes += text.size();
  const std::pair<std::size_t, std::size_t> counts[] = {
      {pm.base_vertex_count, kMaxCount},
      {pm.base_face_count(), kMaxCount},
      {pm.split_count(), kMaxCount},
      {pm.loose_vertex_count, kMaxCount},
      {pm.welds.size(), kMaxCount},
      {pm.carried_faces.size() / 3, kMaxCount},
      {pm.moved_faces.size(), kMaxCount},
      {split_face_count, kMaxCount},
      {pm.uv_count(), kMaxCount},
      {pm.normal_count(), kMaxCount},
      {string_bytes, kMaxCount},
      {pm.material_names.size(), kMaxMaterials},
      {pm.material_libraries.size(), kMaxMaterials}};
  for (const auto& [count, limit] : counts) {
    if (count > limit) {
      return Status(ErrorCode::kResourceLimit, "a count of " + std::to_string(count) +
                                                   " exceeds the .pm limit of " +
                                                   std::to_string(limit));
    }
  }
  return Status::ok();
}

}  // namespace

namespace {

// A known section found by scan_sections(): where its frame is and what it declares.
struct SectionRef {
  int section = -1;
  uint64_t raw_size = 0;
  std::string_view frame;
};
using SectionList = std::array<SectionRef, kKnownSectionCount>;

// §4: every section header, checked before any payload is decompressed or any buffer is
// allocated: tags, order, presence, flags, stored sizes against the stream, raw sizes
// against the counts (§4.4) and against zstd's largest expansion (§4.2). Fills `list`
// with the known sections in order (`found` of them) and `largest_raw` with the largest
// raw size among them.
Status scan_sections(std::string_view bytes, const Header& h, SectionList& list, int& found,
                     uint64_t& largest_raw) {
  ByteReader file(bytes, "header", ErrorCode::kTruncatedStream);
  file.skip(kHeaderSize);
  found = 0;
  largest_raw = 0;
  int next_known = 0;  // known sections must come in order, each at most once
  for (uint32_t s = 0; s < h.section_count; ++s) {
    // The 24 bytes as one unit, so a cut reports the section header it falls in.
    file.set_where("section " + std::to_string(s) + " header");
    std::string_view section_header;
    if (!file.read_bytes(kSectionHeaderSize, section_header)) return file.status();
    SectionHeader fields;
    read_section_header(section_header, fields);
    const uint32_t tag = fields.tag, flags = fields.flags;
    const uint64_t stored_size = fields.stored_size, raw_size = fields.raw_size;
    if (!is_valid_tag(tag)) {
      return Status(ErrorCode::kCorruptStream, "section " + std::to_string(s) + ": tag " +
                                                   tag_name(tag) +
                                                   " is not four ascii letters or digits");
    }
    const std::string where = "section " + tag_name(tag);
    file.set_where(where);
    std::string_view frame;
    const int section = known_section(h, tag);
    if (section < 0) {
      // §4.1: an unknown section may be skipped only when it is not required; a required
      // one is a feature of a later version, or damage in a version this reader knows.
      if (flags & kSectionRequired) {
        return Status(unknown_feature_code(h), where + ": unknown section marked required");
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
    // Geometry is essential (required); attributes are optional, so that a 1.0 reader
    // skips them and still decodes the mesh (§4.1).
    const uint32_t expected_required = is_attribute_section(section) ? 0 : kSectionRequired;
    if ((flags & kSectionRequired) != expected_required) {
      return Status(ErrorCode::kCorruptStream,
                    where + (expected_required ? ": required flag is clear"
                                               : ": required flag is set (attributes are "
                                                 "optional sections)"));
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
    // The counts bound the raw size, and so does zstd's largest possible expansion of the
    // bytes actually present.
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
    list[found++] = SectionRef{section, raw_size, frame};
    largest_raw = std::max(largest_raw, raw_size);
  }
  for (int skipped = next_known; skipped < known_section_count(h); ++skipped) {
    if (section_expected(h, skipped)) {
      return Status(ErrorCode::kCorruptStream,
                    "section " + tag_name(kKnownTags[skipped]) + " missing");
    }
  }
  if (!file.at_end()) {
    return Status(ErrorCode::kCorruptStream,
                  std::to_string(file.remaining()) + " trailing bytes after the last section");
  }
  return Status::ok();
}

}  // namespace

namespace {

// read_pm's steps 3 and 4, once the header and section headers are checked.
Status decode_sections(const Header& h, const SectionList& sections, int section_count,
                       uint64_t largest_raw, ProgressiveMesh& pm) {
  // 3. The arrays that are filled piecewise, at their final sizes (the others are sized
  // once by their decoder); then each section.
  ProgressiveMesh out;
  out.base_vertex_count = h.base_vertex_count;
  out.loose_vertex_count = h.loose_vertex_count;
  out.color_components = h.color_components;
  out.positions.reserve(3 * static_cast<std::size_t>(all_vertices(h)));
  std::string raw;
  raw.reserve(static_cast<std::size_t>(largest_raw));
  {
    DecompressContext dctx(ZSTD_createDCtx());
    if (!dctx) return Status(ErrorCode::kInternal, "zstd: cannot create a decompression context");
    for (int i = 0; i < section_count; ++i) {
      const SectionRef& ref = sections[i];
      const std::string where = "section " + tag_name(kKnownTags[ref.section]);
      if (Status status = decompress_frame(where, ref.frame, ref.raw_size, dctx.get(), raw);
          !status) {
        return status;
      }
      ByteReader payload(raw, where, ErrorCode::kCorruptStream);
      if (!kDecoders[ref.section](payload, h, out)) return payload.status();
      if (!payload.at_end()) {
        return Status(ErrorCode::kCorruptStream, where + ": " +
                                                     std::to_string(payload.remaining()) +
                                                     " bytes left after the last entry");
      }
    }
  }
  std::string().swap(raw);  // freed before validate() allocates (§7.1)

  // 4. The header repeats the first split's error so that --info needs no decompression.
  const float expected_max_error = out.splits.empty() ? 0.0f : out.splits[0].error;
  if (std::memcmp(&expected_max_error, &h.max_error, sizeof(float)) != 0) {
    return Status(ErrorCode::kCorruptStream, "header: max error " + std::to_string(h.max_error) +
                                                 " differs from split 0's " +
                                                 std::to_string(expected_max_error));
  }
  if (Status valid = validate(out); !valid)
    return Status(ErrorCode::kCorruptStream, valid.message());
  pm = std::move(out);
  return Status::ok();
}

}  // namespace

Status write_pm_v1(const ProgressiveMesh& pm, int zstd_level, std::string& bytes) {
  if (Status valid = validate(pm); !valid) {
    return Status(ErrorCode::kInvalidArgument,
                  "cannot write an invalid progressive mesh: " + valid.message());
  }
  if (Status status = check_writable(pm); !status) return status;
  if (zstd_level < 1 || zstd_level > ZSTD_maxCLevel()) {
    return Status(ErrorCode::kInvalidArgument, "zstd level " + std::to_string(zstd_level) +
                                                   " is outside 1.." +
                                                   std::to_string(ZSTD_maxCLevel()));
  }
  const Header header = header_for(pm);
  std::string out;
  append_header(header, out);
  SectionWriter writer;
  for (int section = 0; section < kKnownSectionCount; ++section) {
    if (!section_expected(header, section)) continue;
    const std::string raw = kEncoders[section](pm);
    const uint32_t flags = is_attribute_section(section) ? 0 : kSectionRequired;
    if (Status status =
            writer.append(kKnownTags[section], flags, raw, raw.size(), zstd_level, out);
        !status) {
      return status;
    }
  }
  bytes = std::move(out);
  return Status::ok();
}

Status read_pm_v1(std::string_view bytes, ProgressiveMesh& pm, const ReadOptions& options) {
  // 1. The header (§3.3) and every section header (§4), before anything is allocated.
  Header h;
  if (Status status = parse_header(bytes, h); !status) return status;
  SectionList sections;
  int section_count = 0;
  uint64_t largest_raw = 0;
  if (Status status = scan_sections(bytes, h, sections, section_count, largest_raw); !status) {
    return status;
  }

  // 2. What the decode will take (§7.1), against the caller's bound.
  const uint64_t needed = decode_memory(h, largest_raw);
  if (options.max_memory != 0 && needed > options.max_memory) {
    return Status(ErrorCode::kResourceLimit, "decoding needs " + byte_count_text(needed) +
                                                 " of memory, the limit is " +
                                                 byte_count_text(options.max_memory));
  }

  // Without a bound, a valid stream may still need more than the machine has (zstd
  // expands up to 32768 times): that is a resource limit too, not a crash.
  try {
    return decode_sections(h, sections, section_count, largest_raw, pm);
  } catch (const std::bad_alloc&) {
    return Status(ErrorCode::kResourceLimit,
                  "out of memory (decoding needs " + byte_count_text(needed) + ")");
  }
}

Status read_pm_info_v1(std::string_view bytes, PmInfo& info) {
  Header h;
  if (Status status = parse_header(bytes, h); !status) return status;
  PmInfo result = info_from_header(h);
  result.section_count = h.section_count;
  info = result;
  return Status::ok();
}

}  // namespace detail
}  // namespace pm
