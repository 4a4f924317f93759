// The .pm byte layout in one place: magic, header offsets, section tags, limits, and the
// header and section encoders the writer uses (tests use them too, to build hostile
// streams); pm_layout.cpp implements what both majors share. formats/pm-format-1.md and
// pm-format.md (2.0) are normative; these constants follow it. Internal.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <zstd.h>

#include "pm/pm_codec.h"
#include "pm/status.h"

namespace pm::detail {
class ByteReader;
class ByteWriter;
}  // namespace pm::detail

namespace pm::detail {

// PNG-style: a non-ASCII first byte (caught by 7-bit channels), "PMESH", then CR LF
// (caught by text-mode newline conversion either way).
inline constexpr char kMagic[8] = {'\x89', 'P', 'M', 'E', 'S', 'H', '\r', '\n'};

inline constexpr std::size_t kHeaderSize = 96;
// Bytes 56..91 were reserved in 1.0; 1.1 defines the attribute fields at 56..83 (§3.1).
inline constexpr std::size_t kHeaderAttributesOffset = 56;
inline constexpr std::size_t kHeaderReservedOffset = 84;  // bytes 84..91 are reserved in 1.1
inline constexpr std::size_t kHeaderCrcOffset = 92;       // CRC-32 of bytes 0..91
inline constexpr std::size_t kSectionHeaderSize = 24;     // tag, flags, stored, raw

// The 1.x versions pm_codec_v1.cpp reads (and writes, for tests): 1.0 and 1.1.
inline constexpr uint16_t kMajor1 = 1;
inline constexpr uint16_t kMinor1 = 1;

// The first minor version with the attribute fields and sections (COLR, UVS0, NRML, MATL).
inline constexpr uint16_t kMinorWithAttributes = 1;

// No count in a header may exceed this (vertex ids, face ids and their sums stay well
// inside uint32, and a reader's worst-case allocation stays bounded).
inline constexpr uint32_t kMaxCount = uint32_t{1} << 30;
// Material names and material libraries: at most this many of each, each string at most
// kMaxStringBytes bytes of UTF-8 (a path fits: PATH_MAX is 4096 on Linux).
inline constexpr uint32_t kMaxMaterials = uint32_t{1} << 20;
inline constexpr uint32_t kMaxStringBytes = 4096;
// zstd cannot expand input by more than this: its densest block is an RLE block, 4 bytes
// (3 of header, 1 of content) for at most 128 KiB of output.
inline constexpr uint64_t kMaxZstdRatio = 32768;
// Smallest zstd frame with a content size, a content checksum and at least one block:
// magic 4 + descriptor 1 + content size >= 1 + block header 3 + checksum 4.
inline constexpr uint64_t kMinZstdFrameSize = 13;

inline constexpr uint32_t kSectionRequired = 1u;  // section flags bit 0

// Header field `attributes` (offset 56): which per-corner and per-face id arrays the stream
// holds. The value tables, colours and strings are announced by their counts instead.
inline constexpr uint32_t kAttributeUvIds = 1u;        // face_uvs and moved_uvs
inline constexpr uint32_t kAttributeNormalIds = 2u;    // face_normals and moved_normals
inline constexpr uint32_t kAttributeMaterialIds = 4u;  // face_materials
inline constexpr uint32_t kKnownAttributeBits = 7u;

constexpr uint32_t make_tag(const char (&name)[5]) {
  return uint32_t{static_cast<uint8_t>(name[0])} | uint32_t{static_cast<uint8_t>(name[1])} << 8 |
         uint32_t{static_cast<uint8_t>(name[2])} << 16 |
         uint32_t{static_cast<uint8_t>(name[3])} << 24;
}
inline constexpr uint32_t kTagBase = make_tag("BASE");
inline constexpr uint32_t kTagSplits = make_tag("SPLT");
inline constexpr uint32_t kTagWelds = make_tag("WELD");
inline constexpr uint32_t kTagCarried = make_tag("CARY");
inline constexpr uint32_t kTagLoose = make_tag("LOOS");
inline constexpr uint32_t kTagColors = make_tag("COLR");     // 1.1
inline constexpr uint32_t kTagUvs = make_tag("UVS0");        // 1.1
inline constexpr uint32_t kTagNormals = make_tag("NRML");    // 1.1
inline constexpr uint32_t kTagMaterials = make_tag("MATL");  // 1.1

// "BASE"; bytes outside [0-9A-Za-z] are shown as \xNN.
std::string tag_name(uint32_t tag);

// The fixed 1.x header, field by field (pm-format-1.md, "Header").
struct Header {
  uint16_t major = 0, minor = 0;
  uint32_t flags = 0;
  uint32_t base_vertex_count = 0, base_face_count = 0, split_count = 0;
  uint32_t loose_vertex_count = 0, weld_count = 0, carried_face_count = 0;
  uint32_t moved_face_count = 0;  // total of the splits' moved faces
  uint32_t split_face_count = 0;  // faces the splits add (1 or 2 each)
  uint32_t section_count = 0;
  float max_error = 0.0f;
  // 1.1 (zero in a 1.0 stream, where these bytes are reserved).
  uint32_t attributes = 0;        // kAttribute* bits
  uint32_t color_components = 0;  // 0, 3 or 4
  uint32_t uv_count = 0, normal_count = 0;
  uint32_t material_count = 0, material_library_count = 0;
  uint32_t material_string_bytes = 0;  // UTF-8 bytes of all names and libraries together
};

// Writes the 96 header bytes, reserved bytes zero, CRC filled in. The 1.1 fields are
// written whatever header.minor says (tests write 1.0 headers with them zero).
void append_header(const Header& header, std::string& out);

// Checks magic, CRC, version, flags, reserved bytes, count limits, consistency and the
// counts against the stream's length, in that order (§3.3). `bytes` is the whole stream
// (at least the header is needed). Does not look at sections.
Status parse_header(std::string_view bytes, Header& header);

// An upper bound on the bytes read_pm allocates for a stream with this (checked) header
// whose largest section has `largest_raw_size` raw bytes: the decoded ProgressiveMesh plus
// the larger of the decoding and validating transients, plus kDecodeMemorySlack (§7.1).
inline constexpr uint64_t kDecodeMemorySlack = 4096;  // messages and small state
// A bound on zstd's decompression context (ZSTD_sizeof_DCtx: 95 992 bytes with zstd 1.5.4;
// a single-pass decode into a flat buffer allocates no window). ZSTD_estimateDCtxSize()
// would say it exactly but is not in zstd's stable API; tests check the bound.
inline constexpr uint64_t kZstdContextBytes = 256 * 1024;
uint64_t decode_memory(const Header& header, uint64_t largest_raw_size);

// Appends one section: its 24-byte header, then `raw` as one zstd frame (content size
// and content checksum on). `declared_raw_size` is what goes in the raw-size field; the
// writer passes raw.size(), tests may lie.
Status append_section(uint32_t tag, uint32_t flags, std::string_view raw,
                      uint64_t declared_raw_size, int zstd_level, std::string& out);

// append_section() with one zstd context kept from section to section, for a writer that
// writes many (2.x: a section per chunk), as zstd's manual advises for many compressions.
// A context at level 18 holds megabytes of tables, which a context per section allocated
// and gave back each time; where large blocks are mapped on their own (pmenc sets glibc so,
// cli_common.h) every section's tables were new pages to fault in: reading the 950K-face
// textured mesh's .pm and writing it 5 times with that setting, 586,000 -> 263,000 page
// faults. The same bytes: a frame depends on its parameters and its input, not on what the
// context compressed before.
class SectionWriter {
 public:
  SectionWriter();
  SectionWriter(const SectionWriter&) = delete;
  SectionWriter& operator=(const SectionWriter&) = delete;
  Status append(uint32_t tag, uint32_t flags, std::string_view raw, uint64_t declared_raw_size,
                int zstd_level, std::string& out);

 private:
  struct FreeContext {
    void operator()(ZSTD_CCtx* context) const { ZSTD_freeCCtx(context); }
  };
  std::unique_ptr<ZSTD_CCtx, FreeContext> context_;
};

// One zstd frame, exactly `frame.size()` bytes, with a content checksum and a content
// size equal to `raw_size` (§4.2 of both format documents), decompressed into `raw`.
Status decompress_frame(const std::string& where, std::string_view frame, uint64_t raw_size,
                        ZSTD_DCtx* dctx, std::string& raw);

// Material strings (pm-format.md §5.9 in 1.1, the TABL section in 2.0): a varint length
// then the bytes. string_problem says why a string cannot be stored, or is empty.
void put_string(ByteWriter& out, const std::string& text);
std::string string_problem(std::string_view text);
// `count` strings; `budget` is what is left of the header's string bytes.
bool read_strings(ByteReader& in, uint32_t count, const char* what, uint64_t& budget,
                  std::vector<std::string>& out);

// The PmInfo fields 1.x and 2.0 headers share (their structs name them alike).
template <typename AnyHeader>
PmInfo info_from_header(const AnyHeader& h) {
  PmInfo r;
  r.major = h.major;
  r.minor = h.minor;
  r.flags = h.flags;
  r.base_vertex_count = h.base_vertex_count;
  r.base_face_count = h.base_face_count;
  r.split_count = h.split_count;
  r.loose_vertex_count = h.loose_vertex_count;
  r.weld_count = h.weld_count;
  r.carried_face_count = h.carried_face_count;
  r.moved_face_count = h.moved_face_count;
  r.split_face_count = h.split_face_count;
  // Welded copies are output as their canonical vertex, so they are not counted.
  r.full_vertex_count =
      uint64_t{h.base_vertex_count} + h.split_count + h.loose_vertex_count - h.weld_count;
  r.full_face_count = uint64_t{h.base_face_count} + h.split_face_count + h.carried_face_count;
  r.max_error = h.max_error;
  r.color_components = h.color_components;
  r.uv_count = h.uv_count;
  r.normal_count = h.normal_count;
  r.material_count = h.material_count;
  r.material_library_count = h.material_library_count;
  r.has_uvs = (h.attributes & kAttributeUvIds) != 0;
  r.has_normals = (h.attributes & kAttributeNormalIds) != 0;
  r.has_materials = (h.attributes & kAttributeMaterialIds) != 0;
  return r;
}

// A section's 24-byte header (§4.1 of both format documents).
struct SectionHeader {
  uint32_t tag = 0, flags = 0;
  uint64_t stored_size = 0, raw_size = 0;
};
// The section header at the start of `bytes`; false when fewer than 24 bytes are there.
bool read_section_header(std::string_view bytes, SectionHeader& out);
// Its writer: the 24 bytes appended to `out`.
void write_section_header(const SectionHeader& header, ByteWriter& out);
// Whether the tag's four bytes are all ASCII letters or digits.
bool is_valid_tag(uint32_t tag);

// "3190448 bytes (3 MiB)".
std::string byte_count_text(uint64_t bytes);

// Format 1.x (pm_codec_v1.cpp, pm-format-1.md): the reader of older streams, and the
// writer, kept for tests and golden files.
Status write_pm_v1(const ProgressiveMesh& pm, int zstd_level, std::string& bytes);
Status read_pm_v1(std::string_view bytes, ProgressiveMesh& pm, const ReadOptions& options);
Status read_pm_info_v1(std::string_view bytes, PmInfo& info);
Status check_material_strings_impl(const std::vector<std::string>& names,
                                   const std::vector<std::string>& libraries);

}  // namespace pm::detail
