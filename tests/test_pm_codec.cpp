// The 1.x .pm codec (formats/pm-format-1.md), read through read_pm, and validate().
//
// Round trips of small literal progressive meshes, field by field, with and without
// attributes; a 1.0 stream written by the 1.0 writer, which must still decode; a reference
// encoder written from the spec (not from pm_codec.cpp) whose streams the reader must
// accept; adversarial streams: every truncation, every single-byte flip, trailing bytes,
// bad magic, versions, reserved bits, hostile counts and sizes, ids out of range; the
// memory bound (ReadOptions::max_memory); one validate() test per rule.
#include <gtest/gtest.h>
#include <zstd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "../formats/byte_io.h"
#include "../formats/pm_layout.h"
#include "../formats/split_fans.h"
#include "pm/encoder.h"
#include "pm/mesh_io.h"
#include "pm/pm_codec.h"
#include "pm/progressive_mesh.h"
#include "pm_literals.h"
#include "test_util.h"

namespace pm {
namespace {

using detail::ByteWriter;
using namespace literals;  // NOLINT

std::string encode(const ProgressiveMesh& pm, int level = 3) {
  std::string bytes;
  WriteOptions options;
  options.zstd_level = level;
  const Status status = detail::write_pm_v1(pm, options.zstd_level, bytes);
  EXPECT_TRUE(status.is_ok()) << status.message();
  return bytes;
}

// ---------------------------------------------------------------------------------------
// Byte surgery
// ---------------------------------------------------------------------------------------

// Header offsets (pm-format-1.md §3.1).
constexpr std::size_t kMajorOffset = 8, kMinorOffset = 10, kFlagsOffset = 12;
constexpr std::size_t kSplitCountOffset = 24, kSectionCountOffset = 48, kMaxErrorOffset = 52;
// The 1.1 fields.
constexpr std::size_t kAttributesOffset = 56, kColorComponentsOffset = 60, kUvCountOffset = 64,
                      kNormalCountOffset = 68, kMaterialCountOffset = 72, kLibraryCountOffset = 76,
                      kStringBytesOffset = 80;

void put_u32_at(std::string& bytes, std::size_t offset, uint32_t value) {
  for (int i = 0; i < 4; ++i) bytes[offset + i] = static_cast<char>(value >> (8 * i));
}
void put_u16_at(std::string& bytes, std::size_t offset, uint16_t value) {
  for (int i = 0; i < 2; ++i) bytes[offset + i] = static_cast<char>(value >> (8 * i));
}
void put_u64_at(std::string& bytes, std::size_t offset, uint64_t value) {
  for (int i = 0; i < 8; ++i) bytes[offset + i] = static_cast<char>(value >> (8 * i));
}
uint64_t get_u64_at(const std::string& bytes, std::size_t offset) {
  uint64_t value = 0;
  for (int i = 0; i < 8; ++i) value |= uint64_t{static_cast<uint8_t>(bytes[offset + i])} << (8 * i);
  return value;
}
uint32_t get_u32_at(const std::string& bytes, std::size_t offset) {
  return static_cast<uint32_t>(get_u64_at(bytes + std::string(4, '\0'), offset));
}

// Recomputes the header CRC after an edit, so the edit itself is what the reader sees.
void reseal_header(std::string& bytes) {
  put_u32_at(bytes, detail::kHeaderCrcOffset,
             detail::crc32(std::string_view(bytes).substr(0, detail::kHeaderCrcOffset)));
}

struct SectionSpan {
  uint32_t tag = 0;
  std::size_t offset = 0;  // of the section header
  std::size_t size = 0;    // header + payload
};

std::vector<SectionSpan> sections_of(const std::string& bytes) {
  std::vector<SectionSpan> sections;
  std::size_t offset = detail::kHeaderSize;
  while (offset + detail::kSectionHeaderSize <= bytes.size()) {
    SectionSpan span;
    span.tag = get_u32_at(bytes, offset);
    span.offset = offset;
    span.size = detail::kSectionHeaderSize + get_u64_at(bytes, offset + 8);
    sections.push_back(span);
    offset += span.size;
  }
  return sections;
}

SectionSpan section_with_tag(const std::string& bytes, uint32_t tag) {
  for (const SectionSpan& span : sections_of(bytes)) {
    if (span.tag == tag) return span;
  }
  ADD_FAILURE() << "no section " << detail::tag_name(tag);
  return {};
}

Status decode(const std::string& bytes, ProgressiveMesh* out = nullptr) {
  ProgressiveMesh pm;
  Status status = read_pm(bytes, pm);
  if (out) *out = std::move(pm);
  return status;
}

#define EXPECT_ERROR(status_expr, code_value)                   \
  do {                                                          \
    const Status status_ = (status_expr);                       \
    EXPECT_EQ(status_.code(), code_value) << status_.message(); \
    EXPECT_FALSE(status_.message().empty());                    \
  } while (0)

// ---------------------------------------------------------------------------------------
// A reference encoder written from pm-format-1.md §5 (independent of pm_codec.cpp).
// ---------------------------------------------------------------------------------------

struct RawSection {
  uint32_t tag;
  std::string raw;
  uint32_t flags = detail::kSectionRequired;  // attribute sections: 0 (optional)
};

// §5.10, spelled out: the (vertex, id) of every attribute corner, in corner order.
std::vector<std::pair<uint32_t, uint32_t>> spec_corners(const ProgressiveMesh& pm,
                                                        const std::vector<uint32_t>& face_ids,
                                                        const std::vector<uint32_t>& moved_ids) {
  std::vector<std::pair<uint32_t, uint32_t>> corners;
  std::size_t f = 0;  // faces in creation order
  for (; f < pm.base_faces.size() / 3; ++f)
    for (int c = 0; c < 3; ++c) corners.push_back({pm.base_faces[3 * f + c], face_ids[3 * f + c]});
  for (std::size_t i = 0; i < pm.splits.size(); ++i) {
    const VertexSplit& s = pm.splits[i];
    const uint32_t v = pm.base_vertex_count + uint32_t(i);
    for (uint32_t k = 0; k < s.moved_count; ++k)
      corners.push_back({v, moved_ids[s.moved_begin + k]});
    for (const auto& face :
         {std::vector<uint32_t>{v, s.u, s.vl}, std::vector<uint32_t>{s.u, v, s.vr}}) {
      if (face[2] == kNoVertex) continue;
      for (int c = 0; c < 3; ++c) corners.push_back({face[c], face_ids[3 * f + c]});
      ++f;
    }
  }
  for (std::size_t j = 0; j < pm.carried_faces.size(); ++j)
    corners.push_back({pm.carried_faces[j], face_ids[3 * f + j]});
  return corners;
}

// §5.10's codes: 0 none, 1 the vertex's previous id, else zigzag(id - previous id) + 2.
std::string spec_corner_codes(const ProgressiveMesh& pm, const std::vector<uint32_t>& face_ids,
                              const std::vector<uint32_t>& moved_ids) {
  std::string raw;
  ByteWriter out(raw);
  std::map<uint32_t, uint32_t> last;
  int64_t previous = 0;
  for (const auto& [vertex, id] : spec_corners(pm, face_ids, moved_ids)) {
    if (id == kNoAttribute) {
      out.put_varint(0);
      continue;
    }
    const auto it = last.find(vertex);
    const int64_t delta = int64_t{id} - previous;
    out.put_varint(it != last.end() && it->second == id
                       ? 1
                       : uint32_t(delta >= 0 ? 2 * delta + 2 : -2 * delta - 1 + 2));
    last[vertex] = id;
    previous = id;
  }
  return raw;
}

std::vector<RawSection> spec_sections(const ProgressiveMesh& pm) {
  std::vector<RawSection> sections;
  const std::size_t base = pm.base_vertex_count, splits = pm.splits.size();
  {
    std::string raw;
    ByteWriter out(raw);
    for (std::size_t i = 0; i < 3 * base; ++i) out.put_f32(pm.positions[i]);
    for (uint32_t index : pm.base_faces) out.put_varint(index);
    if (base > 0) sections.push_back({detail::kTagBase, raw});
  }
  if (splits > 0) {
    std::string raw;
    ByteWriter out(raw);
    for (std::size_t i = 0; i < splits; ++i)
      out.put_varint(uint32_t(base + i - 1 - pm.splits[i].u));
    for (const auto& s : pm.splits) out.put_varint(s.vl == kNoVertex ? 0 : s.vl + 1);
    for (const auto& s : pm.splits) out.put_varint(s.vr == kNoVertex ? 0 : s.vr + 1);
    for (const auto& s : pm.splits) out.put_varint(s.moved_count);
    for (uint32_t face : pm.moved_faces) out.put_varint(face);
    for (std::size_t i = 3 * base; i < 3 * (base + splits); ++i) out.put_f32(pm.positions[i]);
    for (const auto& s : pm.splits) out.put_f32(s.error);
    sections.push_back({detail::kTagSplits, raw});
  }
  if (!pm.welds.empty()) {
    std::string raw;
    ByteWriter out(raw);
    for (const Weld& weld : pm.welds) {
      out.put_varint(weld.copy);
      out.put_varint(weld.canonical);
    }
    sections.push_back({detail::kTagWelds, raw});
  }
  if (!pm.carried_faces.empty()) {
    std::string raw;
    ByteWriter out(raw);
    for (uint32_t index : pm.carried_faces) out.put_varint(index);
    sections.push_back({detail::kTagCarried, raw});
  }
  if (pm.loose_vertex_count > 0) {
    std::string raw;
    ByteWriter out(raw);
    for (std::size_t i = 3 * (base + splits); i < pm.positions.size(); ++i)
      out.put_f32(pm.positions[i]);
    sections.push_back({detail::kTagLoose, raw});
  }
  // 1.1: the attribute sections, optional (flags 0), present when they have entries.
  if (!pm.colors.empty()) {
    std::string raw;
    ByteWriter out(raw);
    for (float c : pm.colors) out.put_f32(c);
    sections.push_back({detail::kTagColors, raw, 0});
  }
  for (const bool uvs : {true, false}) {
    const std::vector<float>& table = uvs ? pm.uvs : pm.normals;
    const std::vector<uint32_t>& face_ids = uvs ? pm.face_uvs : pm.face_normals;
    if (table.empty() && face_ids.empty()) continue;
    std::string raw;
    ByteWriter out(raw);
    for (float x : table) out.put_f32(x);
    if (!face_ids.empty())
      raw += spec_corner_codes(pm, face_ids, uvs ? pm.moved_uvs : pm.moved_normals);
    sections.push_back({uvs ? detail::kTagUvs : detail::kTagNormals, raw, 0});
  }
  if (!pm.material_names.empty() || !pm.material_libraries.empty() || !pm.face_materials.empty()) {
    std::string raw;
    ByteWriter out(raw);
    for (const auto* strings : {&pm.material_libraries, &pm.material_names}) {
      for (const std::string& text : *strings) {
        out.put_varint(uint32_t(text.size()));
        raw += text;
      }
    }
    for (uint32_t id : pm.face_materials) out.put_varint(id == kNoAttribute ? 0 : id + 1);
    sections.push_back({detail::kTagMaterials, raw, 0});
  }
  return sections;
}

// A 1.1 header by default; minor 0 writes a 1.0 header (the attribute fields stay zero).
detail::Header spec_header(const ProgressiveMesh& pm, uint32_t section_count, uint16_t minor = 1) {
  detail::Header h;
  h.major = 1;
  h.minor = minor;
  h.base_vertex_count = pm.base_vertex_count;
  h.base_face_count = uint32_t(pm.base_faces.size() / 3);
  h.split_count = uint32_t(pm.splits.size());
  h.loose_vertex_count = pm.loose_vertex_count;
  h.weld_count = uint32_t(pm.welds.size());
  h.carried_face_count = uint32_t(pm.carried_faces.size() / 3);
  h.moved_face_count = uint32_t(pm.moved_faces.size());
  for (const auto& s : pm.splits) h.split_face_count += s.new_face_count();
  h.section_count = section_count;
  h.max_error = pm.splits.empty() ? 0.0f : pm.splits[0].error;
  if (minor >= 1) {
    h.attributes = (pm.face_uvs.empty() ? 0 : 1) | (pm.face_normals.empty() ? 0 : 2) |
                   (pm.face_materials.empty() ? 0 : 4);
    h.color_components = pm.color_components;
    h.uv_count = uint32_t(pm.uvs.size() / 2);
    h.normal_count = uint32_t(pm.normals.size() / 3);
    h.material_count = uint32_t(pm.material_names.size());
    h.material_library_count = uint32_t(pm.material_libraries.size());
    for (const auto* strings : {&pm.material_names, &pm.material_libraries})
      for (const std::string& text : *strings) h.material_string_bytes += uint32_t(text.size());
  }
  return h;
}

std::string assemble(const detail::Header& header, const std::vector<RawSection>& sections) {
  std::string bytes;
  detail::append_header(header, bytes);
  for (const RawSection& section : sections) {
    const Status status = detail::append_section(section.tag, section.flags, section.raw,
                                                 section.raw.size(), 3, bytes);
    EXPECT_TRUE(status.is_ok()) << status.message();
  }
  return bytes;
}

std::string spec_stream(const ProgressiveMesh& pm, uint16_t minor = 1) {
  const auto sections = spec_sections(pm);
  return assemble(spec_header(pm, uint32_t(sections.size()), minor), sections);
}

uint64_t raw_size_of(const std::string& bytes, const SectionSpan& span) {
  return get_u64_at(bytes, span.offset + 16);
}

// ---------------------------------------------------------------------------------------
// Round trips
// ---------------------------------------------------------------------------------------

// One zstd context for many sections writes each as a context of its own would: the same
// bytes, whatever the context compressed before and at whatever level.
TEST(SectionWriter, ReusedContextWritesWhatFreshContextsWrite) {
  std::string repetitive, noisy(3000, '\0'), empty;
  for (int i = 0; i < 4000; ++i) repetitive += "v 0.5 1.25 " + std::to_string(i % 37) + "\n";
  std::mt19937 random(7);
  for (char& c : noisy) c = static_cast<char>(random());
  const struct {
    uint32_t tag;
    const std::string* raw;
    int level;
  } sections[] = {{detail::kTagBase, &repetitive, 18},
                  {detail::make_tag("CHNK"), &noisy, 3},
                  {detail::make_tag("CHNK"), &empty, 18},
                  {detail::make_tag("CHNK"), &repetitive, 1},
                  {detail::make_tag("INDX"), &noisy, 18}};
  detail::SectionWriter writer;
  std::string reused = "prefix", fresh = "prefix";
  for (const auto& section : sections) {
    ASSERT_TRUE(writer.append(section.tag, detail::kSectionRequired, *section.raw,
                              section.raw->size(), section.level, reused));
    ASSERT_TRUE(detail::append_section(section.tag, detail::kSectionRequired, *section.raw,
                                       section.raw->size(), section.level, fresh));
  }
  EXPECT_EQ(reused, fresh);
  // Each section: its header, then a frame of the size the header says, holding the raw bytes.
  std::size_t at = 6;
  ZSTD_DCtx* dctx = ZSTD_createDCtx();
  for (const auto& section : sections) {
    ASSERT_LE(at + detail::kSectionHeaderSize, reused.size());
    EXPECT_EQ(get_u32_at(reused, at), section.tag);
    const uint64_t stored = get_u64_at(reused, at + 8);
    EXPECT_EQ(get_u64_at(reused, at + 16), section.raw->size());
    std::string raw;
    const std::string_view frame(reused.data() + at + detail::kSectionHeaderSize, stored);
    EXPECT_TRUE(detail::decompress_frame("test", frame, section.raw->size(), dctx, raw));
    EXPECT_EQ(raw, *section.raw);
    at += detail::kSectionHeaderSize + stored;
  }
  ZSTD_freeDCtx(dctx);
  EXPECT_EQ(at, reused.size());
}

TEST(PmCodecRoundTrip, SmallMeshIsExact) {
  const ProgressiveMesh original = small_mesh();
  std::string message;
  ASSERT_TRUE(test::ok(validate(original)));
  const std::string bytes = encode(original);
  ProgressiveMesh decoded;
  const Status status = read_pm(bytes, decoded);
  ASSERT_TRUE(status.is_ok()) << status.message();
  expect_identical(original, decoded);
}

TEST(PmCodecRoundTrip, AllSectionsInOrder) {
  const std::string bytes = encode(small_mesh());
  std::vector<uint32_t> tags;
  for (const SectionSpan& span : sections_of(bytes)) tags.push_back(span.tag);
  EXPECT_EQ(tags, (std::vector<uint32_t>{detail::kTagBase, detail::kTagSplits, detail::kTagWelds,
                                         detail::kTagCarried, detail::kTagLoose}));
  EXPECT_EQ(get_u32_at(bytes, kSectionCountOffset), 5u);
}

TEST(PmCodecRoundTrip, EmptySectionsAreOmitted) {
  const ProgressiveMesh original = triangle_mesh();
  const std::string bytes = encode(original);
  const auto sections = sections_of(bytes);
  ASSERT_EQ(sections.size(), 1u);
  EXPECT_EQ(sections[0].tag, detail::kTagBase);
  ProgressiveMesh decoded;
  ASSERT_TRUE(read_pm(bytes, decoded).is_ok());
  expect_identical(original, decoded);
}

TEST(PmCodecRoundTrip, LooseVerticesOnly) {
  ProgressiveMesh original;
  original.loose_vertex_count = 2;
  original.positions = {1, 2, 3, 4, 5, 6};
  const std::string bytes = encode(original);
  ASSERT_EQ(sections_of(bytes).size(), 1u);
  ProgressiveMesh decoded;
  const Status status = read_pm(bytes, decoded);
  ASSERT_TRUE(status.is_ok()) << status.message();
  expect_identical(original, decoded);
}

TEST(PmCodecRoundTrip, GeneratedMeshWithMultiByteVarints) {
  const ProgressiveMesh original = generated_mesh(20000);
  std::string message;
  ASSERT_TRUE(test::ok(validate(original)));
  for (int level : {1, 19}) {
    SCOPED_TRACE("level " + std::to_string(level));
    ProgressiveMesh decoded;
    const Status status = read_pm(encode(original, level), decoded);
    ASSERT_TRUE(status.is_ok()) << status.message();
    expect_identical(original, decoded);
  }
}

TEST(PmCodecRoundTrip, SpecialFloatBitPatternsSurvive) {
  ProgressiveMesh original = small_mesh();
  original.positions[0] = -0.0f;
  original.positions[1] = std::numeric_limits<float>::denorm_min();
  original.positions[2] = std::numeric_limits<float>::infinity();  // positions are not checked
  ProgressiveMesh decoded;
  ASSERT_TRUE(read_pm(encode(original), decoded).is_ok());
  expect_identical(original, decoded);
}

TEST(PmCodecRoundTrip, HeaderBytesAreExactlyAsSpecified) {
  // pm-format-1.md §3.1 for small_mesh(): counts 5, 4, 2, 2, 1, 1, moved 2, split faces 3,
  // 5 sections, max error 0.5, 28 bytes of attribute fields (all zero: no attributes), 8
  // reserved zero bytes, then the CRC.
  const std::string bytes = encode(small_mesh());
  const std::string expected_fields =
      std::string("\x89PMESH\r\n", 8) + std::string("\x01\x00\x01\x00", 4) +  // 1.1
      std::string(4, '\0') +                                                  // flags
      std::string("\x05\0\0\0\x04\0\0\0\x02\0\0\0", 12) +
      std::string("\x02\0\0\0\x01\0\0\0\x01\0\0\0", 12) +
      std::string("\x02\0\0\0\x03\0\0\0\x05\0\0\0", 12) + std::string("\0\0\0\x3f", 4) +  // 0.5f
      std::string(36, '\0');
  ASSERT_EQ(expected_fields.size(), detail::kHeaderCrcOffset);
  EXPECT_EQ(bytes.substr(0, detail::kHeaderCrcOffset), expected_fields);
  EXPECT_EQ(detail::crc32("123456789"), 0xCBF43926u);  // the CRC-32 check value
}

TEST(PmCodecRoundTrip, SpecReferenceStreamIsAccepted) {
  for (const ProgressiveMesh& original : {small_mesh(), triangle_mesh(), generated_mesh(300)}) {
    ProgressiveMesh decoded;
    const Status status = decode(spec_stream(original), &decoded);
    ASSERT_TRUE(status.is_ok()) << status.message();
    expect_identical(original, decoded);
  }
}

TEST(PmCodecRoundTrip, InfoReadsTheHeader) {
  const std::string bytes = encode(small_mesh());
  PmInfo info;
  const Status status = read_pm_info(bytes, info);
  ASSERT_TRUE(status.is_ok()) << status.message();
  EXPECT_EQ(info.major, 1);
  EXPECT_EQ(info.minor, 1);
  EXPECT_EQ(info.flags, 0u);
  EXPECT_EQ(info.base_vertex_count, 5u);
  EXPECT_EQ(info.base_face_count, 4u);
  EXPECT_EQ(info.split_count, 2u);
  EXPECT_EQ(info.loose_vertex_count, 2u);
  EXPECT_EQ(info.weld_count, 1u);
  EXPECT_EQ(info.carried_face_count, 1u);
  EXPECT_EQ(info.moved_face_count, 2u);
  EXPECT_EQ(info.split_face_count, 3u);
  EXPECT_EQ(info.section_count, 5u);
  EXPECT_EQ(info.full_vertex_count, 5u + 2u + 2u - 1u);  // the welded copy is not output
  EXPECT_EQ(info.full_face_count, 4u + 3u + 1u);
  EXPECT_EQ(info.max_error, 0.5f);
  EXPECT_EQ(info.color_components, 0u);
  EXPECT_EQ(info.uv_count, 0u);
  EXPECT_EQ(info.normal_count, 0u);
  EXPECT_EQ(info.material_count, 0u);
  EXPECT_EQ(info.material_library_count, 0u);
  EXPECT_FALSE(info.has_uvs || info.has_normals || info.has_materials);
  EXPECT_ERROR(read_pm_info(bytes.substr(0, 50), info), ErrorCode::kTruncatedStream);
}

TEST(PmCodecWrite, RejectsInvalidMeshAndBadLevel) {
  ProgressiveMesh invalid = small_mesh();
  invalid.moved_faces[0] = 99;
  std::string bytes = "untouched";
  EXPECT_ERROR(write_pm(invalid, WriteOptions{}, bytes), ErrorCode::kInvalidArgument);
  EXPECT_EQ(bytes, "untouched");
  for (int level : {0, 23}) {
    WriteOptions options;
    options.zstd_level = level;
    EXPECT_ERROR(write_pm(small_mesh(), options, bytes), ErrorCode::kInvalidArgument);
  }
}

// ---------------------------------------------------------------------------------------
// Adversarial streams
// ---------------------------------------------------------------------------------------

TEST(PmCodecAdversarial, EveryTruncationIsReported) {
  for (const ProgressiveMesh& original : {small_mesh(), triangle_mesh(), attributed_mesh()}) {
    const std::string bytes = encode(original);
    for (std::size_t length = 0; length < bytes.size(); ++length) {
      SCOPED_TRACE("length " + std::to_string(length) + " of " + std::to_string(bytes.size()));
      ProgressiveMesh decoded;
      const Status status = read_pm(std::string_view(bytes).substr(0, length), decoded);
      EXPECT_EQ(status.code(), ErrorCode::kTruncatedStream) << status.message();
    }
  }
}

TEST(PmCodecAdversarial, TruncationMessageNamesTheSection) {
  const std::string bytes = encode(small_mesh());
  // The last byte: the header's counts are plausible, LOOS's payload is one byte short.
  const Status status = decode(bytes.substr(0, bytes.size() - 1));
  EXPECT_EQ(status.code(), ErrorCode::kTruncatedStream);
  EXPECT_NE(status.message().find("truncated in section LOOS (need "), std::string::npos)
      << status.message();
  EXPECT_EQ(decode(bytes.substr(0, 40)).message(), "truncated in header (need 96 bytes, 40 left)");
}

TEST(PmCodecAdversarial, TrailingBytesAreRejected) {
  for (const std::string& tail :
       {std::string(1, '\0'), std::string("junk"), std::string(24, '\0')}) {
    EXPECT_ERROR(decode(encode(small_mesh()) + tail), ErrorCode::kCorruptStream);
  }
}

TEST(PmCodecAdversarial, BadMagicIsRejected) {
  std::string bytes = encode(small_mesh());
  bytes[1] = 'X';
  EXPECT_ERROR(decode(bytes), ErrorCode::kCorruptStream);
  EXPECT_ERROR(decode("PLY\nformat"), ErrorCode::kCorruptStream);
  // A text-mode transfer that turned CR LF into LF.
  std::string mangled = encode(small_mesh());
  mangled.erase(6, 1);
  EXPECT_ERROR(decode(mangled), ErrorCode::kCorruptStream);
}

TEST(PmCodecAdversarial, HeaderChecksumMismatch) {
  std::string bytes = encode(small_mesh());
  bytes[kSplitCountOffset] ^= 1;
  const Status status = decode(bytes);
  EXPECT_EQ(status.code(), ErrorCode::kChecksumMismatch);
  EXPECT_EQ(status.message().rfind("header: checksum mismatch", 0), 0u) << status.message();
}

TEST(PmCodecAdversarial, UnknownMajorVersion) {
  for (uint16_t major : {0, 3, 0xFFFF}) {
    std::string bytes = encode(small_mesh());
    put_u16_at(bytes, kMajorOffset, major);
    reseal_header(bytes);
    EXPECT_ERROR(decode(bytes), ErrorCode::kUnsupportedVersion);
    PmInfo info;
    EXPECT_ERROR(read_pm_info(bytes, info), ErrorCode::kUnsupportedVersion);
  }
}

TEST(PmCodecAdversarial, ReservedHeaderFlagsAndBytes) {
  for (uint32_t flag = 1; flag != 0; flag <<= 1) {
    std::string bytes = encode(small_mesh());
    put_u32_at(bytes, kFlagsOffset, flag);
    reseal_header(bytes);
    EXPECT_ERROR(decode(bytes), ErrorCode::kCorruptStream);
  }
  // 1.1: bytes 84-91.
  for (std::size_t offset = detail::kHeaderReservedOffset; offset < detail::kHeaderCrcOffset;
       ++offset) {
    std::string bytes = encode(attributed_mesh());
    bytes[offset] = 1;
    reseal_header(bytes);
    const Status status = decode(bytes);
    EXPECT_EQ(status.code(), ErrorCode::kCorruptStream);
    EXPECT_EQ(status.message(),
              "header: reserved byte " + std::to_string(offset) + " is 1, must be 0");
  }
  // 1.0: bytes 56-91, where 1.1 has its attribute fields: a 1.0 stream cannot have attributes.
  for (std::size_t offset = kAttributesOffset; offset < detail::kHeaderCrcOffset; ++offset) {
    std::string bytes = small_mesh_v1_0();
    bytes[offset] = 1;
    reseal_header(bytes);
    const Status status = decode(bytes);
    EXPECT_EQ(status.code(), ErrorCode::kCorruptStream);
    EXPECT_EQ(status.message(),
              "header: reserved byte " + std::to_string(offset) + " is 1, must be 0");
  }
  // The attribute bits above the three of 1.1.
  for (uint32_t bit = 8; bit != 0; bit <<= 1) {
    std::string bytes = encode(attributed_mesh());
    put_u32_at(bytes, kAttributesOffset, 7 | bit);
    reseal_header(bytes);
    EXPECT_ERROR(decode(bytes), ErrorCode::kCorruptStream);
  }
}

TEST(PmCodecAdversarial, ReservedSectionFlags) {
  for (uint32_t flag = 2; flag != 0; flag <<= 1) {
    std::string bytes = encode(small_mesh());
    const SectionSpan splits = section_with_tag(bytes, detail::kTagSplits);
    put_u32_at(bytes, splits.offset + 4, detail::kSectionRequired | flag);
    EXPECT_ERROR(decode(bytes), ErrorCode::kCorruptStream);
  }
  // A 1.0 section must be marked required.
  std::string bytes = encode(small_mesh());
  put_u32_at(bytes, section_with_tag(bytes, detail::kTagWelds).offset + 4, 0);
  EXPECT_ERROR(decode(bytes), ErrorCode::kCorruptStream);
}

// A later minor version: unknown optional sections are skipped, reserved header bytes are
// ignored; flag bits and unknown required sections are features this reader lacks.
TEST(PmCodecAdversarial, NewerMinorVersion) {
  const ProgressiveMesh original = small_mesh();
  auto newer = [&](bool required_extra, uint32_t header_flags) {
    auto sections = spec_sections(original);
    sections.insert(sections.begin() + 2, RawSection{detail::make_tag("NORM"), "later data"});
    detail::Header header = spec_header(original, uint32_t(sections.size()));
    header.minor = 7;
    header.flags = header_flags;
    header.attributes = 0x100;  // an attribute bit of minor 7
    std::string bytes = assemble(header, sections);
    bytes[84] = 42;  // a field of minor 7
    reseal_header(bytes);
    if (!required_extra)
      put_u32_at(bytes, section_with_tag(bytes, detail::make_tag("NORM")).offset + 4, 0);
    return bytes;
  };
  ProgressiveMesh decoded;
  const Status status = decode(newer(false, 0), &decoded);
  ASSERT_TRUE(status.is_ok()) << status.message();
  expect_identical(original, decoded);
  EXPECT_ERROR(decode(newer(true, 0)), ErrorCode::kUnsupportedVersion);
  EXPECT_ERROR(decode(newer(false, 1)), ErrorCode::kUnsupportedVersion);
}

// In a version this reader knows, a private section must be optional: a required section
// with a tag no known version defines is damage (a flipped tag), not a missing feature.
TEST(PmCodecAdversarial, UnknownSectionsInKnownVersions) {
  for (const uint16_t minor : {0, 1}) {
    SCOPED_TRACE("minor " + std::to_string(minor));
    const ProgressiveMesh original = small_mesh();
    auto sections = spec_sections(original);
    sections.push_back(RawSection{detail::make_tag("XTRA"), "vendor data"});
    std::string bytes = assemble(spec_header(original, uint32_t(sections.size()), minor), sections);
    const SectionSpan extra = section_with_tag(bytes, detail::make_tag("XTRA"));
    const Status status = decode(bytes);  // written as required
    EXPECT_EQ(status.code(), ErrorCode::kCorruptStream);
    EXPECT_EQ(status.message(), "section XTRA: unknown section marked required");
    put_u32_at(bytes, extra.offset + 4, 0);
    ProgressiveMesh decoded;
    ASSERT_TRUE(decode(bytes, &decoded).is_ok());
    expect_identical(original, decoded);
    bytes[extra.offset] = '\x01';  // tags are letters and digits
    EXPECT_ERROR(decode(bytes), ErrorCode::kCorruptStream);
  }
}

// 1.1's tags in a 1.0 stream are private sections of some tool: skipped when optional, as
// a 1.0 reader did; the attributes they would hold in 1.1 are not read.
TEST(PmCodecAdversarial, AttributeTagsInA1_0StreamAreUnknownSections) {
  const ProgressiveMesh attributed = attributed_mesh();
  auto sections = spec_sections(attributed);
  ASSERT_EQ(sections.size(), 9u);
  std::string bytes = assemble(spec_header(attributed, 9, 0), sections);
  ProgressiveMesh decoded;
  const Status status = decode(bytes, &decoded);
  ASSERT_TRUE(status.is_ok()) << status.message();
  expect_identical(small_mesh(), decoded);  // geometry only
  // Marked required, they are damage in 1.0 as any unknown required tag.
  sections[5].flags = detail::kSectionRequired;
  EXPECT_ERROR(decode(assemble(spec_header(attributed, 9, 0), sections)),
               ErrorCode::kCorruptStream);
}

// Any single damaged byte is either detected or (were that possible) harmless: never a
// different mesh.
TEST(PmCodecAdversarial, EverySingleByteFlipIsDetected) {
  for (const ProgressiveMesh& original : {small_mesh(), attributed_mesh()}) {
    const std::string bytes = encode(original);
    int accepted = 0;
    for (std::size_t i = 0; i < bytes.size(); ++i) {
      std::string damaged = bytes;
      damaged[i] = static_cast<char>(damaged[i] ^ 0xFF);
      ProgressiveMesh decoded;
      const Status status = read_pm(damaged, decoded);
      if (status.is_ok()) {
        ++accepted;
        EXPECT_TRUE(identical(original, decoded)) << "byte " << i << " decoded to a different mesh";
      } else {
        EXPECT_FALSE(status.message().empty());
        // A checksum or format error: never "unsupported" (the version is this reader's) or
        // a resource limit (the counts are the header's, which its CRC guards).
        EXPECT_TRUE(status.code() == ErrorCode::kChecksumMismatch ||
                    status.code() == ErrorCode::kCorruptStream ||
                    status.code() == ErrorCode::kTruncatedStream)
            << "byte " << i << ": " << status.message();
      }
    }
    EXPECT_EQ(accepted, 0);
  }
}

// The same on what the encoder writes for a real mesh: samples/nonmanifold.obj, which has all
// five sections (welds, carried faces, loose vertices), each byte XORed with 0x01, 0x80 and
// 0xFF in turn. Where the flip lands decides the error: in the magic the bytes are not a .pm;
// elsewhere in the header its CRC fails; in a section header the framing breaks (tag, flags,
// sizes: a format error); in a zstd frame its content checksum fails, or zstd's own structure
// breaks first (a corrupt stream).
//
// A few flips in a frame are accepted: zstd still decodes the frame to the same bytes (not
// every bit of its entropy tables changes the output), so the mesh is the original, as
// checked. That is the only way to be accepted: every frame carries the XXH64 of its decoded
// bytes, checked on every read, so a flip that changed them fails (up to a 2^-32 collision).
//
// Run twice: on the encoder's output, and on it with synthetic attributes (all nine sections).
class PmCodecFlips : public ::testing::TestWithParam<bool> {};

TEST_P(PmCodecFlips, EveryByteFlipOfAnEncodedSampleIsAnErrorOrHarmless) {
  Mesh mesh;
  ASSERT_TRUE(read_mesh(test::sample_mesh_path("nonmanifold.obj"), mesh).is_ok());
  ProgressiveMesh original;
  EncodeOptions options;
  options.drop_attributes = true;  // this test adds its own (or none)
  ASSERT_TRUE(pm::encode(mesh, options, original).is_ok());
  if (GetParam()) original = with_attributes(std::move(original));
  const std::string bytes = encode(original, 19);
  const std::vector<SectionSpan> sections = sections_of(bytes);
  ASSERT_EQ(sections.size(), GetParam() ? 9u : 5u);
  std::size_t frame_flips = 0, frame_checksum_errors = 0, accepted = 0;
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    bool in_section_header = false;
    for (const SectionSpan& span : sections) {
      in_section_header |= i >= span.offset && i < span.offset + detail::kSectionHeaderSize;
    }
    for (const uint8_t mask : {0x01, 0x80, 0xFF}) {
      std::string damaged = bytes;
      damaged[i] = static_cast<char>(damaged[i] ^ mask);
      ProgressiveMesh decoded;
      const Status status = decode(damaged, &decoded);
      SCOPED_TRACE("byte " + std::to_string(i) + " ^ " + std::to_string(mask) + ": " +
                   status.message());
      const ErrorCode code = status.code();
      if (i < sizeof detail::kMagic) {
        EXPECT_EQ(code, ErrorCode::kCorruptStream);
      } else if (i < detail::kHeaderSize) {
        EXPECT_EQ(code, ErrorCode::kChecksumMismatch);
      } else if (in_section_header) {
        // A damaged tag is unknown: required, it is damage in this version; optional (an
        // attribute section), it is skipped and the section it was is missing. A stored
        // size past the end reads as truncation.
        EXPECT_TRUE(code == ErrorCode::kCorruptStream || code == ErrorCode::kTruncatedStream);
      } else {
        ++frame_flips;
        frame_checksum_errors += code == ErrorCode::kChecksumMismatch;
        if (status.is_ok()) {
          ++accepted;
          EXPECT_TRUE(identical(original, decoded));
        } else {
          EXPECT_TRUE(code == ErrorCode::kChecksumMismatch || code == ErrorCode::kCorruptStream);
        }
      }
    }
  }
  // Bounds, not exact counts, which depend on the encoder's and zstd's output (when written,
  // 59% of the frame flips were checksum errors and 0.4% harmless): the checksum catches a
  // good share of the flips in a frame, and harmless ones are rare.
  EXPECT_GT(frame_checksum_errors, frame_flips / 4);
  EXPECT_LT(accepted, frame_flips / 50);
}

INSTANTIATE_TEST_SUITE_P(WithAndWithoutAttributes, PmCodecFlips, ::testing::Bool(),
                         [](const ::testing::TestParamInfo<bool>& info) {
                           return info.param ? "Attributes" : "GeometryOnly";
                         });

TEST(PmCodecAdversarial, HugeCountsAreRejectedBeforeAllocating) {
  const std::string bytes = encode(small_mesh());
  struct Case {
    std::size_t offset;
    uint32_t value;
    ErrorCode code;
  };
  const Case cases[] = {
      {kSplitCountOffset, 0x80000000u, ErrorCode::kResourceLimit},  // 2^31 splits
      {16, 0xFFFFFFFFu, ErrorCode::kResourceLimit},                 // base vertices
      {40, detail::kMaxCount + 1, ErrorCode::kResourceLimit},       // moved faces
      // At the cap, but far more than ~1 KB of zstd frames can hold.
      {16, detail::kMaxCount, ErrorCode::kTruncatedStream},
      {28, detail::kMaxCount, ErrorCode::kTruncatedStream},
      {kSectionCountOffset, 0x10000000u, ErrorCode::kTruncatedStream},
  };
  for (const Case& c : cases) {
    std::string damaged = bytes;
    put_u32_at(damaged, c.offset, c.value);
    reseal_header(damaged);
    EXPECT_ERROR(decode(damaged), c.code);
  }
}

TEST(PmCodecAdversarial, InconsistentHeaderCounts) {
  const std::string bytes = encode(small_mesh());
  for (auto [offset, value] : std::vector<std::pair<std::size_t, uint32_t>>{
           {kSectionCountOffset, 4},  // fewer sections than the counts need
           {kSectionCountOffset, 6},  // one more than present
           {44, 5},                   // 5 split faces for 2 splits
           {44, 1},                   // 1 split face for 2 splits
           {32, 6},                   // 6 welds for 5 base vertices
           {36, 2},                   // 2 carried faces, CARY holds 1
           {40, 3},                   // moved faces
       }) {
    SCOPED_TRACE("offset " + std::to_string(offset));
    std::string damaged = bytes;
    put_u32_at(damaged, offset, value);
    reseal_header(damaged);
    const Status status = decode(damaged);
    EXPECT_TRUE(status.code() == ErrorCode::kCorruptStream ||
                status.code() == ErrorCode::kTruncatedStream)
        << status.message();
  }
}

TEST(PmCodecAdversarial, MaxErrorMustMatchFirstSplit) {
  std::string bytes = encode(small_mesh());
  put_u32_at(bytes, kMaxErrorOffset, 0x3f400000u);  // 0.75f
  reseal_header(bytes);
  EXPECT_ERROR(decode(bytes), ErrorCode::kCorruptStream);
  put_u32_at(bytes, kMaxErrorOffset, 0x7fc00000u);  // NaN
  reseal_header(bytes);
  EXPECT_ERROR(decode(bytes), ErrorCode::kCorruptStream);
}

TEST(PmCodecAdversarial, DecompressedSizeBeyondDeclaredIsRejected) {
  const ProgressiveMesh original = small_mesh();
  auto sections = spec_sections(original);
  ASSERT_EQ(sections[1].tag, detail::kTagSplits);
  const std::size_t honest_size = sections[1].raw.size();
  std::string bytes;
  detail::append_header(spec_header(original, uint32_t(sections.size())), bytes);
  for (const RawSection& section : sections) {
    // SPLT's frame holds one byte more than its section header declares.
    const bool lie = section.tag == detail::kTagSplits;
    ASSERT_TRUE(detail::append_section(section.tag, detail::kSectionRequired,
                                       lie ? section.raw + '\x01' : section.raw,
                                       lie ? honest_size : section.raw.size(), 3, bytes)
                    .is_ok());
  }
  const Status status = decode(bytes);
  EXPECT_EQ(status.code(), ErrorCode::kCorruptStream);
  EXPECT_NE(status.message().find("section SPLT"), std::string::npos) << status.message();
}

TEST(PmCodecAdversarial, DeclaredRawSizeOutsideCountsIsRejected) {
  std::string bytes = encode(small_mesh());
  const SectionSpan base = section_with_tag(bytes, detail::kTagBase);
  for (uint64_t raw_size : {uint64_t{0}, uint64_t{1} << 40, ~uint64_t{0}}) {
    std::string damaged = bytes;
    put_u64_at(damaged, base.offset + 16, raw_size);
    EXPECT_ERROR(decode(damaged), ErrorCode::kCorruptStream);
  }
  // A stored size past the end of the stream is truncation, whatever the value.
  for (uint64_t stored_size : {uint64_t{1} << 40, ~uint64_t{0}}) {
    std::string damaged = bytes;
    put_u64_at(damaged, base.offset + 8, stored_size);
    EXPECT_ERROR(decode(damaged), ErrorCode::kTruncatedStream);
  }
}

TEST(PmCodecAdversarial, PayloadLeftOverOrShortIsRejected) {
  const ProgressiveMesh original = small_mesh();
  for (int extra : {+1, -1}) {
    auto sections = spec_sections(original);
    std::string& carried = sections[3].raw;
    ASSERT_EQ(sections[3].tag, detail::kTagCarried);
    if (extra > 0) carried += '\x00';
    if (extra < 0) carried.pop_back();
    // 4 bytes for 1 face: inside the counts' 3..15, but a varint is left over; 2 bytes: short.
    EXPECT_ERROR(decode(assemble(spec_header(original, 5), sections)), ErrorCode::kCorruptStream);
  }
}

TEST(PmCodecAdversarial, ContentChecksumMismatch) {
  std::string bytes = encode(small_mesh());
  const SectionSpan loose = section_with_tag(bytes, detail::kTagLoose);
  // The last 4 bytes of a frame are its content checksum.
  bytes[loose.offset + loose.size - 1] ^= 0x55;
  EXPECT_ERROR(decode(bytes), ErrorCode::kChecksumMismatch);
}

TEST(PmCodecAdversarial, SectionsMissingRepeatedOrOutOfOrder) {
  const ProgressiveMesh original = small_mesh();
  const auto sections = spec_sections(original);
  auto with = [&](std::vector<RawSection> list) {
    return assemble(spec_header(original, uint32_t(list.size())), list);
  };
  auto without = [&](std::size_t index) {
    auto list = sections;
    list.erase(list.begin() + index);
    return list;
  };
  // Missing: the header still counts welds.
  std::string missing = with(without(2));
  put_u32_at(missing, kSectionCountOffset, 4);
  reseal_header(missing);
  EXPECT_ERROR(decode(missing), ErrorCode::kCorruptStream);
  EXPECT_ERROR(decode(with(without(4))), ErrorCode::kCorruptStream);  // no LOOS
  auto swapped = sections;
  std::swap(swapped[2], swapped[3]);
  EXPECT_ERROR(decode(with(swapped)), ErrorCode::kCorruptStream);
  auto repeated = sections;
  repeated.push_back(sections[4]);
  EXPECT_ERROR(decode(with(repeated)), ErrorCode::kCorruptStream);
  // A section with no entries must be omitted.
  ProgressiveMesh no_welds = original;
  no_welds.welds.clear();
  auto list = spec_sections(no_welds);
  list.insert(list.begin() + 2, RawSection{detail::kTagWelds, ""});
  EXPECT_ERROR(decode(assemble(spec_header(no_welds, uint32_t(list.size())), list)),
               ErrorCode::kCorruptStream);
}

TEST(PmCodecAdversarial, TwoFramesInOneSection) {
  std::string bytes = encode(triangle_mesh());
  const SectionSpan base = section_with_tag(bytes, detail::kTagBase);
  const std::string frame = bytes.substr(base.offset + detail::kSectionHeaderSize);
  bytes += frame;
  put_u64_at(bytes, base.offset + 8, 2 * frame.size());
  EXPECT_ERROR(decode(bytes), ErrorCode::kCorruptStream);
}

TEST(PmCodecAdversarial, OverlongAndOversizedVarints) {
  const ProgressiveMesh original = small_mesh();
  for (const std::string& carried : {std::string("\x82\x00\x02\x03", 4),  // overlong 2
                                     std::string("\xff\xff\xff\xff\x1f\x02\x03", 7)}) {  // > 2^32
    auto sections = spec_sections(original);
    sections[3].raw = carried;
    EXPECT_ERROR(decode(assemble(spec_header(original, 5), sections)), ErrorCode::kCorruptStream);
  }
}

TEST(PmCodecAdversarial, DecodedMeshIsValidated) {
  ProgressiveMesh invalid = small_mesh();
  invalid.moved_faces[1] = 99;  // split 1 moves a face that does not exist
  const Status status = decode(spec_stream(invalid));
  EXPECT_EQ(status.code(), ErrorCode::kCorruptStream);
  EXPECT_EQ(status.message(), "split 1 moves face 99 of 6");
  // u encoded as an offset larger than the vertices before the split.
  auto sections = spec_sections(small_mesh());
  sections[1].raw[0] = 5;  // split 0 creates vertex 5: offsets 0..4 are possible
  EXPECT_ERROR(decode(assemble(spec_header(small_mesh(), 5), sections)), ErrorCode::kCorruptStream);
}

TEST(PmCodecAdversarial, EmptyAndTinyInputs) {
  EXPECT_ERROR(decode(""), ErrorCode::kTruncatedStream);
  EXPECT_ERROR(decode(std::string("\x89", 1)), ErrorCode::kTruncatedStream);
  EXPECT_ERROR(decode(std::string("\x89PMESH\r\n", 8)), ErrorCode::kTruncatedStream);
  EXPECT_ERROR(decode(std::string(200, '\0')), ErrorCode::kCorruptStream);
}

// ---------------------------------------------------------------------------------------
// Format 1.1: attributes
// ---------------------------------------------------------------------------------------

TEST(PmCodecAttributes, LiteralMeshesAreValid) {
  EXPECT_TRUE(test::ok(validate(attributed_mesh())));
  EXPECT_TRUE(test::ok(validate(with_attributes(small_mesh()))));
  EXPECT_TRUE(test::ok(validate(with_attributes(generated_mesh(3000)))));
}

TEST(PmCodecAttributes, RoundTripIsExact) {
  for (const ProgressiveMesh& original :
       {attributed_mesh(), with_attributes(small_mesh()), with_attributes(generated_mesh(20000))}) {
    ProgressiveMesh decoded;
    const Status status = read_pm(encode(original), decoded);
    ASSERT_TRUE(status.is_ok()) << status.message();
    expect_identical(original, decoded);
    EXPECT_TRUE(identical(original, decoded));
  }
}

TEST(PmCodecAttributes, SectionsOrderFlagsAndHeaderFields) {
  const std::string bytes = encode(attributed_mesh());
  std::vector<uint32_t> tags, flags;
  for (const SectionSpan& span : sections_of(bytes)) {
    tags.push_back(span.tag);
    flags.push_back(get_u32_at(bytes, span.offset + 4));
  }
  EXPECT_EQ(tags,
            (std::vector<uint32_t>{detail::kTagBase, detail::kTagSplits, detail::kTagWelds,
                                   detail::kTagCarried, detail::kTagLoose, detail::kTagColors,
                                   detail::kTagUvs, detail::kTagNormals, detail::kTagMaterials}));
  EXPECT_EQ(flags, (std::vector<uint32_t>{1, 1, 1, 1, 1, 0, 0, 0, 0}));  // attributes optional
  EXPECT_EQ(get_u32_at(bytes, kSectionCountOffset), 9u);
  // §3.1, offsets 56-91: ids of all three kinds, 4 colour components, 6 UVs, 3 normals,
  // 3 materials, 2 libraries, 5 + 10 + 0 + 9 + 22 string bytes, 8 reserved zero bytes.
  const std::string expected = std::string("\x07\0\0\0\x04\0\0\0\x06\0\0\0\x03\0\0\0", 16) +
                               std::string("\x03\0\0\0\x02\0\0\0\x2e\0\0\0", 12) +
                               std::string(8, '\0');
  EXPECT_EQ(bytes.substr(kAttributesOffset, 36), expected);
  // The UVS0 payload, worked by hand from §5.10 (uv table first: 48 bytes):
  //   base faces  0 1 2 | 0 2 3 | 0 3 1 | 1 3 -  -> 2 4 4 | 1 1 4 | 1 1 1 | 1 1 0
  //     (the previous id starts at 0: zigzag(0) + 2 = 2, then zigzag(+1) + 2 = 4 twice)
  //   split 0: moved corner of 5 takes 4 (zigzag(4 - 3) + 2 = 4); faces (5 0 2) (0 5 3):
  //     4 0 2 -> 1 1 1, 0 4 3 -> 1 1 1
  //   split 1: moved corner of 6 takes 5 (zigzag(5 - 3) + 2 = 6); face (5 6 3): 4 5 3 -> 1 1 1
  //   carried (2 2 3): 2 5 3 -> 1 (vertex 2 had 2), 5 (zigzag(5 - 2) + 2 = 8), 1 (vertex 3's 3)
  std::string raw;
  const SectionSpan uvs = section_with_tag(bytes, detail::kTagUvs);
  raw.resize(raw_size_of(bytes, uvs));
  ASSERT_EQ(ZSTD_decompress(raw.data(), raw.size(), bytes.data() + uvs.offset + 24, uvs.size - 24),
            raw.size());
  EXPECT_EQ(raw.substr(48), std::string("\x02\x04\x04\x01\x01\x04\x01\x01\x01\x01\x01\x00"
                                        "\x04\x01\x01\x01\x01\x01\x01\x06\x01\x01\x01\x01\x08\x01",
                                        26));
}

TEST(PmCodecAttributes, SpecReferenceStreamIsAccepted) {
  for (const ProgressiveMesh& original :
       {attributed_mesh(), with_attributes(small_mesh()), with_attributes(generated_mesh(300))}) {
    ProgressiveMesh decoded;
    const Status status = decode(spec_stream(original), &decoded);
    ASSERT_TRUE(status.is_ok()) << status.message();
    expect_identical(original, decoded);
  }
}

// Each kind alone, and the value tables without ids: a section exists exactly when it
// has entries, and what is absent stays absent.
TEST(PmCodecAttributes, EachKindAloneRoundTrips) {
  const ProgressiveMesh full = attributed_mesh();
  std::vector<std::pair<ProgressiveMesh, std::vector<uint32_t>>> cases;
  auto geometry = [] { return small_mesh(); };
  ProgressiveMesh colors = geometry();
  colors.color_components = 4;
  colors.colors = full.colors;
  cases.push_back({colors, {detail::kTagColors}});
  ProgressiveMesh uv_table_only = geometry();
  uv_table_only.uvs = full.uvs;
  cases.push_back({uv_table_only, {detail::kTagUvs}});
  ProgressiveMesh uv_ids_without_values = geometry();  // every corner "none"
  uv_ids_without_values.face_uvs.assign(24, kNoAttribute);
  uv_ids_without_values.moved_uvs.assign(2, kNoAttribute);
  cases.push_back({uv_ids_without_values, {detail::kTagUvs}});
  ProgressiveMesh normals = geometry();
  normals.normals = full.normals;
  normals.face_normals = full.face_normals;
  normals.moved_normals = full.moved_normals;
  cases.push_back({normals, {detail::kTagNormals}});
  ProgressiveMesh libraries = geometry();
  libraries.material_libraries = {"only.mtl"};
  cases.push_back({libraries, {detail::kTagMaterials}});
  ProgressiveMesh materials = geometry();
  materials.material_names = full.material_names;
  materials.face_materials = full.face_materials;
  cases.push_back({materials, {detail::kTagMaterials}});
  ProgressiveMesh colours_without_vertices;  // 3 components of nothing: header only
  colours_without_vertices.color_components = 3;
  cases.push_back({colours_without_vertices, {}});
  for (const auto& [original, attribute_tags] : cases) {
    const std::string bytes = encode(original);
    std::vector<uint32_t> tags;
    for (const SectionSpan& span : sections_of(bytes))
      if (get_u32_at(bytes, span.offset + 4) == 0) tags.push_back(span.tag);
    EXPECT_EQ(tags, attribute_tags);
    ProgressiveMesh decoded;
    const Status status = read_pm(bytes, decoded);
    ASSERT_TRUE(status.is_ok()) << status.message();
    expect_identical(original, decoded);
    EXPECT_EQ(decoded.has_uvs(), original.has_uvs());
  }
}

// Without attributes, a 1.1 stream is the 1.0 stream but for the minor version (and so the
// header CRC): not one byte larger.
TEST(PmCodecAttributes, WithoutAttributesTheStreamIsAsSmallAs1_0) {
  const std::string bytes = encode(small_mesh(), 19);
  const std::string& old = small_mesh_v1_0();
  ASSERT_EQ(bytes.size(), old.size());
  EXPECT_EQ(bytes.substr(0, kMinorOffset), old.substr(0, kMinorOffset));
  EXPECT_EQ(bytes[kMinorOffset], '\x01');
  EXPECT_EQ(old[kMinorOffset], '\x00');
  EXPECT_EQ(bytes.substr(kMinorOffset + 1, detail::kHeaderCrcOffset - kMinorOffset - 1),
            old.substr(kMinorOffset + 1, detail::kHeaderCrcOffset - kMinorOffset - 1));
  EXPECT_EQ(bytes.substr(detail::kHeaderSize), old.substr(detail::kHeaderSize));
}

TEST(PmCodecAttributes, Version1_0StreamStillDecodes) {
  ProgressiveMesh decoded;
  const Status status = decode(small_mesh_v1_0(), &decoded);
  ASSERT_TRUE(status.is_ok()) << status.message();
  expect_identical(small_mesh(), decoded);
  PmInfo info;
  ASSERT_TRUE(read_pm_info(small_mesh_v1_0(), info).is_ok());
  EXPECT_EQ(info.minor, 0);
  EXPECT_EQ(info.section_count, 5u);
  // And the reference encoder's 1.0 streams.
  for (const ProgressiveMesh& original : {small_mesh(), generated_mesh(300)}) {
    ASSERT_TRUE(decode(spec_stream(original, 0), &decoded).is_ok());
    expect_identical(original, decoded);
  }
}

TEST(PmCodecAttributes, InfoReportsTheAttributes) {
  PmInfo info;
  ASSERT_TRUE(read_pm_info(encode(attributed_mesh()), info).is_ok());
  EXPECT_EQ(info.minor, 1);
  EXPECT_EQ(info.color_components, 4u);
  EXPECT_EQ(info.uv_count, 6u);
  EXPECT_EQ(info.normal_count, 3u);
  EXPECT_EQ(info.material_count, 3u);
  EXPECT_EQ(info.material_library_count, 2u);
  EXPECT_TRUE(info.has_uvs);
  EXPECT_TRUE(info.has_normals);
  EXPECT_TRUE(info.has_materials);
  EXPECT_EQ(info.section_count, 9u);
  ProgressiveMesh libraries_only = small_mesh();
  libraries_only.material_libraries = {"x.mtl"};
  ASSERT_TRUE(read_pm_info(encode(libraries_only), info).is_ok());
  EXPECT_EQ(info.material_library_count, 1u);
  EXPECT_FALSE(info.has_uvs || info.has_normals || info.has_materials);
}

// Corner codes of §5.10 compress: with one UV per vertex, each vertex costs one explicit
// code, and its other corners (about five) are "same as this vertex's", which zstd squeezes
// out. Compared with the plain coding (a varint of id + 1 per corner, compressed alike).
TEST(PmCodecAttributes, PerVertexIdsCostLittle) {
  ProgressiveMesh pm = generated_mesh(20000);
  const std::size_t geometry_bytes = encode(pm, 19).size();
  pm.uvs.assign(2 * pm.vertex_count(), 0.0f);  // the values do not matter here
  std::vector<uint32_t> corners(pm.base_faces);
  for (std::size_t i = 0; i < pm.splits.size(); ++i) {
    const VertexSplit& s = pm.splits[i];
    const uint32_t v = pm.base_vertex_count + uint32_t(i);
    if (s.vl != kNoVertex) corners.insert(corners.end(), {v, s.u, s.vl});
    if (s.vr != kNoVertex) corners.insert(corners.end(), {s.u, v, s.vr});
    for (uint32_t k = 0; k < s.moved_count; ++k) pm.moved_uvs.push_back(v);
  }
  // uv id = a pseudo-random permutation of the vertex id, as an input's own order would be.
  auto shuffled = [&pm](uint32_t vertex) {
    return uint32_t((uint64_t{vertex} * 7919) % pm.vertex_count());
  };
  for (uint32_t vertex : corners) pm.face_uvs.push_back(shuffled(vertex));
  for (uint32_t& id : pm.moved_uvs) id = shuffled(id);
  const std::string bytes = encode(pm, 19);
  const SectionSpan uvs = section_with_tag(bytes, detail::kTagUvs);
  EXPECT_EQ(bytes.size(), geometry_bytes + uvs.size);
  std::string plain;
  ByteWriter out(plain);
  for (float x : pm.uvs) out.put_f32(x);
  for (const auto& [vertex, id] : spec_corners(pm, pm.face_uvs, pm.moved_uvs))
    out.put_varint(id + 1);
  std::string compressed(ZSTD_compressBound(plain.size()), '\0');
  compressed.resize(
      ZSTD_compress(compressed.data(), compressed.size(), plain.data(), plain.size(), 19));
  // When written: 58963 bytes against 210255 (zstd 1.5.4), for 144329 corners.
  EXPECT_LT(uvs.size, compressed.size() / 2);
  ProgressiveMesh decoded;
  ASSERT_TRUE(read_pm(bytes, decoded).is_ok());
  EXPECT_EQ(decoded.face_uvs, pm.face_uvs);
  EXPECT_EQ(decoded.moved_uvs, pm.moved_uvs);
}

TEST(PmCodecAttributes, WriterRejectsStringsTheFormatCannotHold) {
  struct Case {
    std::string text;
    ErrorCode code;
    const char* message;
  };
  const Case cases[] = {
      {std::string("a\0b", 3), ErrorCode::kInvalidArgument, "material name 1: a NUL character"},
      {std::string(4097, 'x'), ErrorCode::kResourceLimit,
       "material name 1: 4097 bytes (at most 4096)"},
  };
  for (const Case& c : cases) {
    ProgressiveMesh pm = attributed_mesh();
    pm.material_names[1] = c.text;
    std::string bytes = "untouched";
    const Status status = write_pm(pm, WriteOptions{}, bytes);
    EXPECT_EQ(status.code(), c.code);
    EXPECT_EQ(status.message(), c.message);
    EXPECT_EQ(bytes, "untouched");
  }
  ProgressiveMesh longest = attributed_mesh();
  longest.material_libraries[0] = std::string(4096, 'y');
  ProgressiveMesh decoded;
  ASSERT_TRUE(read_pm(encode(longest), decoded).is_ok());
  EXPECT_EQ(decoded.material_libraries[0], longest.material_libraries[0]);
  ProgressiveMesh too_many = small_mesh();
  too_many.material_libraries.assign(detail::kMaxMaterials + 1, "");
  std::string bytes;
  EXPECT_ERROR(write_pm(too_many, WriteOptions{}, bytes), ErrorCode::kResourceLimit);
}

TEST(PmCodecAttributes, NamesAreBytesAsTheFileHadThem) {
  // Latin-1, a lone surrogate, bytes no encoding uses: all round-trip as they were.
  ProgressiveMesh pm = attributed_mesh();
  pm.material_names[1] = std::string("caf\xe9");
  pm.material_libraries[0] = std::string("\xff\xed\xa0\x80.mtl");
  ProgressiveMesh decoded;
  ASSERT_TRUE(read_pm(encode(pm), decoded).is_ok());
  EXPECT_EQ(decoded.material_names, pm.material_names);
  EXPECT_EQ(decoded.material_libraries, pm.material_libraries);
}

// Replaces section `tag`'s payload in the reference stream of `pm` (header as written).
std::string with_raw(const ProgressiveMesh& pm, uint32_t tag, const std::string& raw) {
  auto sections = spec_sections(pm);
  for (RawSection& section : sections)
    if (section.tag == tag) section.raw = raw;
  return assemble(spec_header(pm, uint32_t(sections.size())), sections);
}

std::string raw_of(const ProgressiveMesh& pm, uint32_t tag) {
  for (const RawSection& section : spec_sections(pm))
    if (section.tag == tag) return section.raw;
  ADD_FAILURE() << "no section " << detail::tag_name(tag);
  return "";
}

TEST(PmCodecAttributesAdversarial, CornerCodesOutOfRangeOrNotCanonical) {
  const ProgressiveMesh pm = attributed_mesh();
  const std::string uv_raw = raw_of(pm, detail::kTagUvs);
  const std::size_t codes = 48;  // where the codes start: after the 6 UVs
  struct Case {
    std::size_t corner;
    std::string code;
    const char* message;
  };
  const Case cases[] = {
      // Corner 0: previous is 0; zigzag(6) + 2 = 14 gives id 6 of 6.
      {0, "\x0e", "section UVS0: corner 0 has id 6 of 6"},
      // zigzag(-1) + 2 = 3 gives id -1.
      {0, "\x03", "section UVS0: corner 0 has id -1 of 6"},
      // Code 1 on vertex 0's first corner: nothing to repeat.
      {0, "\x01", "section UVS0: corner 0 repeats the id of vertex 0, which has none yet"},
      // Corner 3 is vertex 0 again with id 0: code 1 is the only spelling; 2 (delta 0
      // from corner 2's id 2... is id 2) is fine as a different id, but zigzag(-2) + 2 = 5
      // spells out 0, which vertex 0 repeats.
      {3, "\x05", "section UVS0: corner 3 spells out id 0, which its vertex repeats (code 1)"},
      // The largest code: 2^32 - 1, far out of range either way.
      // (Corner 4's id was 2: 2 + unzigzag(2^32 - 3) = 2 - 2147483647.)
      {5, "\xff\xff\xff\xff\x0f", "section UVS0: corner 5 has id -2147483645 of 6"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.message);
    std::string raw = uv_raw;
    raw.replace(codes + c.corner, 1, c.code);
    const Status status = decode(with_raw(pm, detail::kTagUvs, raw));
    EXPECT_EQ(status.code(), ErrorCode::kCorruptStream);
    EXPECT_EQ(status.message(), c.message);
  }
  // A moved corner is checked like the others: split 0's (corner 12) against 6 normals.
  std::string normal_raw = raw_of(pm, detail::kTagNormals);
  normal_raw[36 + 12] = '\x08';  // previous id 2 (corner 11 has none): zigzag(3) + 2 gives 5
  const Status status = decode(with_raw(pm, detail::kTagNormals, normal_raw));
  EXPECT_EQ(status.message(), "section NRML: corner 12 has id 5 of 3");
}

TEST(PmCodecAttributesAdversarial, MaterialIdsAndStrings) {
  const ProgressiveMesh pm = attributed_mesh();
  const std::string raw = raw_of(pm, detail::kTagMaterials);
  // Strings: 9 "scene.mtl", 22 "lib/more materials.mtl", 5 "stone", 10 "métal €", 0 "".
  const std::size_t ids = 1 + 9 + 1 + 22 + 1 + 5 + 1 + 10 + 1;
  ASSERT_EQ(raw.size(), ids + 8);
  struct Case {
    std::size_t offset;
    std::string bytes;
    const char* message;
  };
  const Case cases[] = {
      {ids + 3, "\x04", "section MATL: face 3 has material 3 of 3"},
      {ids + 7, "\x7f", "section MATL: face 7 has material 126 of 3"},
      {1, std::string(1, '\0'), "section MATL: material library 0: a NUL character"},
      // A length beyond what the header's string bytes (46) leave.
      {0, "\x2f",
       "section MATL: material library 0 has 47 bytes, more than the header's string bytes"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.message);
    std::string damaged = raw;
    damaged.replace(c.offset, c.bytes.size(), c.bytes);
    const Status status = decode(with_raw(pm, detail::kTagMaterials, damaged));
    EXPECT_EQ(status.code(), ErrorCode::kCorruptStream);
    EXPECT_EQ(status.message(), c.message);
  }
  // Shorter strings than the header's total: the bytes are then in the wrong place.
  std::string shorter = raw;
  shorter[0] = 8;  // "scene.mt", then "l" is read as a length
  EXPECT_ERROR(decode(with_raw(pm, detail::kTagMaterials, shorter)), ErrorCode::kCorruptStream);
}

TEST(PmCodecAttributesAdversarial, HeaderFieldsThatDisagree) {
  const std::string bytes = encode(attributed_mesh());
  struct Case {
    std::size_t offset;
    uint32_t value;
    ErrorCode code;
    const char* message;  // nullptr: any message
  };
  const Case cases[] = {
      {kColorComponentsOffset, 5, ErrorCode::kCorruptStream,
       "header: 5 colour components (0, 3 or 4)"},
      {kColorComponentsOffset, 3, ErrorCode::kCorruptStream,
       "section COLR: raw size 144, the counts allow 108"},
      {kColorComponentsOffset, 0, ErrorCode::kCorruptStream,
       "section COLR: present, but the header counts no entries"},
      {kUvCountOffset, 7, ErrorCode::kCorruptStream, nullptr},  // raw size outside the bounds
      {kUvCountOffset, 5, ErrorCode::kCorruptStream, nullptr},  // an id of 5 is out of range
      {kNormalCountOffset, 2, ErrorCode::kCorruptStream, nullptr},
      {kMaterialCountOffset, 2, ErrorCode::kCorruptStream, nullptr},  // fewer names: bytes left
      {kLibraryCountOffset, 3, ErrorCode::kCorruptStream, nullptr},
      {kStringBytesOffset, 43, ErrorCode::kCorruptStream, nullptr},
      {kStringBytesOffset, 5 * 4096 + 1, ErrorCode::kCorruptStream,
       "header: 20481 bytes of 5 material strings (at most 4096 each)"},
      {kAttributesOffset, 6, ErrorCode::kCorruptStream, nullptr},  // UV ids undeclared
      {kAttributesOffset, 3, ErrorCode::kCorruptStream, nullptr},  // material ids undeclared
      {kSectionCountOffset, 8, ErrorCode::kCorruptStream, nullptr},
      // Limits (§7): resource limits before anything else is believed.
      {kUvCountOffset, detail::kMaxCount + 1, ErrorCode::kResourceLimit,
       "header: 1073741825 texture coordinates exceed the limit of 1073741824"},
      {kMaterialCountOffset, detail::kMaxMaterials + 1, ErrorCode::kResourceLimit,
       "header: 1048577 materials exceed the limit of 1048576"},
      {kLibraryCountOffset, 0xFFFFFFFFu, ErrorCode::kResourceLimit, nullptr},
      {kStringBytesOffset, 0xFFFFFFFFu, ErrorCode::kResourceLimit, nullptr},
      // At the limits, but more than the stream can hold.
      {kUvCountOffset, detail::kMaxCount, ErrorCode::kTruncatedStream, nullptr},
      {kNormalCountOffset, detail::kMaxCount, ErrorCode::kTruncatedStream, nullptr},
      // 2^20 names need 2^20 bytes of MATL, which a 32-byte frame could hold: the raw size
      // the section header declares is what gives it away. Bounds: (2^20 + 2 strings) + 46
      // string bytes + 8 ids at 1 byte each, to 2 * (2^20 + 2) + 46 + 3 * 8.
      {kMaterialCountOffset, detail::kMaxMaterials, ErrorCode::kCorruptStream,
       "section MATL: raw size 59, the counts allow 1048632 to 2097226"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE("offset " + std::to_string(c.offset) + " = " + std::to_string(c.value));
    std::string damaged = bytes;
    put_u32_at(damaged, c.offset, c.value);
    reseal_header(damaged);
    const Status status = decode(damaged);
    EXPECT_EQ(status.code(), c.code) << status.message();
    if (c.message) {
      EXPECT_EQ(status.message(), c.message);
    }
    PmInfo info;  // the header checks are read_pm_info's too
    if (c.code != ErrorCode::kCorruptStream || (c.message && c.message[0] == 'h')) {
      EXPECT_EQ(read_pm_info(damaged, info).code(), c.code);
    }
  }
  // Ids declared for a mesh without faces.
  ProgressiveMesh no_faces;
  no_faces.loose_vertex_count = 1;
  no_faces.positions = {1, 2, 3};
  std::string empty = encode(no_faces);
  put_u32_at(empty, kAttributesOffset, 1);
  reseal_header(empty);
  EXPECT_EQ(decode(empty).message(),
            "header: attribute ids 0x00000001 declared for a mesh without faces");
}

TEST(PmCodecAttributesAdversarial, SectionFlagsAndPresence) {
  const ProgressiveMesh pm = attributed_mesh();
  const std::string bytes = encode(pm);
  for (uint32_t tag :
       {detail::kTagColors, detail::kTagUvs, detail::kTagNormals, detail::kTagMaterials}) {
    SCOPED_TRACE(detail::tag_name(tag));
    const SectionSpan span = section_with_tag(bytes, tag);
    std::string damaged = bytes;
    put_u32_at(damaged, span.offset + 4, detail::kSectionRequired);
    EXPECT_EQ(decode(damaged).message(),
              "section " + detail::tag_name(tag) +
                  ": required flag is set (attributes are optional sections)");
    for (uint32_t flag = 2; flag != 0; flag <<= 1) {
      put_u32_at(damaged, span.offset + 4, flag);
      EXPECT_ERROR(decode(damaged), ErrorCode::kCorruptStream);
    }
    // The section left out: the header still announces it.
    std::string missing = bytes.substr(0, span.offset) + bytes.substr(span.offset + span.size);
    put_u32_at(missing, kSectionCountOffset, 8);
    reseal_header(missing);
    EXPECT_ERROR(decode(missing), ErrorCode::kCorruptStream);
  }
  // Out of order: NRML before UVS0.
  auto sections = spec_sections(pm);
  std::swap(sections[6], sections[7]);
  EXPECT_ERROR(decode(assemble(spec_header(pm, 9), sections)), ErrorCode::kCorruptStream);
  // Repeated.
  sections = spec_sections(pm);
  sections.push_back(sections[8]);
  EXPECT_ERROR(decode(assemble(spec_header(pm, 10), sections)), ErrorCode::kCorruptStream);
}

// Every cut of every attribute payload, with a section header that tells the truth about the
// cut: the raw size leaves the counts' bounds, or the data ends before its last field.
TEST(PmCodecAttributesAdversarial, EveryShortPayloadIsRejected) {
  const ProgressiveMesh pm = attributed_mesh();
  for (uint32_t tag :
       {detail::kTagColors, detail::kTagUvs, detail::kTagNormals, detail::kTagMaterials}) {
    const std::string raw = raw_of(pm, tag);
    for (std::size_t length = 0; length < raw.size(); ++length) {
      SCOPED_TRACE(detail::tag_name(tag) + " cut to " + std::to_string(length));
      EXPECT_ERROR(decode(with_raw(pm, tag, raw.substr(0, length))), ErrorCode::kCorruptStream);
    }
    EXPECT_ERROR(decode(with_raw(pm, tag, raw + '\x01')), ErrorCode::kCorruptStream);
  }
}

// A later minor: its attribute bits and reserved bytes are ignored, its optional sections
// skipped; the 1.1 attributes are read as 1.1 defines them.
TEST(PmCodecAttributesAdversarial, LaterMinorKeepsThe1_1Attributes) {
  const ProgressiveMesh original = attributed_mesh();
  auto sections = spec_sections(original);
  sections.insert(sections.begin() + 7, RawSection{detail::make_tag("UVS1"), "a second set", 0});
  detail::Header header = spec_header(original, uint32_t(sections.size()));
  header.minor = 2;
  header.attributes |= 0x8;
  std::string bytes = assemble(header, sections);
  bytes[90] = 7;
  reseal_header(bytes);
  ProgressiveMesh decoded;
  const Status status = decode(bytes, &decoded);
  ASSERT_TRUE(status.is_ok()) << status.message();
  expect_identical(original, decoded);
  PmInfo info;
  ASSERT_TRUE(read_pm_info(bytes, info).is_ok());
  EXPECT_EQ(info.minor, 2);
  EXPECT_TRUE(info.has_uvs);
}

// ---------------------------------------------------------------------------------------
// Issue 9: validate before allocating; the memory bound
// ---------------------------------------------------------------------------------------

// pm-format-1.md §7.1, written out from the spec for a decoded mesh and the largest raw size
// its stream declares.
uint64_t spec_decode_memory(const ProgressiveMesh& pm, uint64_t largest_raw) {
  static_assert(sizeof(VertexSplit) == 24 && sizeof(Weld) == 8, "§7.1's sizes");
  const uint64_t vertices = pm.vertex_count(), faces = pm.total_face_count();
  const uint64_t split_faces = faces - pm.carried_faces.size() / 3;
  const uint64_t strings = pm.material_names.size() + pm.material_libraries.size();
  uint64_t string_bytes = 0;
  for (const auto* list : {&pm.material_names, &pm.material_libraries})
    for (const std::string& text : *list) string_bytes += text.size();
  const uint64_t mesh =
      12 * vertices + 4 * pm.base_faces.size() + 24 * pm.splits.size() + 4 * pm.moved_faces.size() +
      8 * pm.welds.size() + 4 * pm.carried_faces.size() + 4 * pm.color_components * vertices +
      4 * pm.uvs.size() + 4 * pm.normals.size() + sizeof(std::string) * strings + string_bytes +
      strings + (pm.has_uvs() ? 4 * (3 * faces + pm.moved_faces.size()) : 0) +
      (pm.has_normals() ? 4 * (3 * faces + pm.moved_faces.size()) : 0) +
      (pm.has_materials() ? 4 * faces : 0);
  const uint64_t predictor =
      pm.has_uvs() || pm.has_normals() ? 4 * (pm.base_vertex_count + pm.splits.size()) : 0;
  const uint64_t decoding = largest_raw + predictor + 256 * 1024;
  const uint64_t validating = 16 * split_faces + 8 * ((pm.base_vertex_count + 63) / 64);
  return mesh + std::max(decoding, validating) + 4096;
}

uint64_t largest_raw_size(const std::string& bytes) {
  uint64_t largest = 0;
  for (const SectionSpan& span : sections_of(bytes))
    largest = std::max(largest, raw_size_of(bytes, span));
  return largest;
}

std::string memory_text(uint64_t bytes) {
  std::string text = std::to_string(bytes) + " bytes";
  if (bytes >= (1u << 20)) text += " (" + std::to_string((bytes + (1u << 19)) >> 20) + " MiB)";
  return text;
}

TEST(PmCodecMemory, LimitJustBelowAndAtWhatTheStreamNeeds) {
  for (const ProgressiveMesh& original :
       {small_mesh(), attributed_mesh(), triangle_mesh(), with_attributes(generated_mesh(20000))}) {
    const std::string bytes = encode(original);
    const uint64_t needed = spec_decode_memory(original, largest_raw_size(bytes));
    SCOPED_TRACE("needs " + std::to_string(needed));
    ProgressiveMesh decoded;
    ReadOptions options;
    options.max_memory = needed;
    Status status = read_pm(bytes, decoded, options);
    ASSERT_TRUE(status.is_ok()) << status.message();
    expect_identical(original, decoded);
    options.max_memory = needed - 1;
    ProgressiveMesh untouched = triangle_mesh();
    status = read_pm(bytes, untouched, options);
    EXPECT_EQ(status.code(), ErrorCode::kResourceLimit);
    EXPECT_EQ(status.message(), "decoding needs " + memory_text(needed) +
                                    " of memory, the limit is " + memory_text(needed - 1));
    expect_identical(triangle_mesh(), untouched);
    options.max_memory = 0;  // no bound
    EXPECT_TRUE(read_pm(bytes, decoded, options).is_ok());
  }
}

// What the bound counts for the mesh is what the decoded mesh holds: every array at its
// exact size (no growth slack), strings within their bytes plus a NUL each.
TEST(PmCodecMemory, DecodedArraysAreAllocatedExactly) {
  const ProgressiveMesh original = with_attributes(generated_mesh(5000));
  ProgressiveMesh pm;
  ASSERT_TRUE(read_pm(encode(original), pm).is_ok());
  auto exact = [](const auto& vector) { return vector.capacity() == vector.size(); };
  EXPECT_TRUE(exact(pm.positions));
  EXPECT_TRUE(exact(pm.base_faces));
  EXPECT_TRUE(exact(pm.splits));
  EXPECT_TRUE(exact(pm.moved_faces));
  EXPECT_TRUE(exact(pm.welds));
  EXPECT_TRUE(exact(pm.carried_faces));
  EXPECT_TRUE(exact(pm.colors));
  EXPECT_TRUE(exact(pm.uvs));
  EXPECT_TRUE(exact(pm.normals));
  EXPECT_TRUE(exact(pm.face_uvs));
  EXPECT_TRUE(exact(pm.face_normals));
  EXPECT_TRUE(exact(pm.face_materials));
  EXPECT_TRUE(exact(pm.moved_uvs));
  EXPECT_TRUE(exact(pm.moved_normals));
  EXPECT_TRUE(exact(pm.material_names));
  EXPECT_TRUE(exact(pm.material_libraries));
  // zstd's decompression context stays within the 256 KiB §7.1 counts for it.
  ZSTD_DCtx* dctx = ZSTD_createDCtx();
  ASSERT_NE(dctx, nullptr);
  const std::string frame = encode(original).substr(detail::kHeaderSize + 24);
  std::string out(1 << 20, '\0');
  ZSTD_decompressDCtx(dctx, out.data(), out.size(), frame.data(), frame.size());
  EXPECT_LE(ZSTD_sizeof_DCtx(dctx), 256u * 1024);
  ZSTD_freeDCtx(dctx);
}

// The limit is checked after the section headers and before any payload: a stream whose
// payloads are garbage is refused for its size, not for its content.
TEST(PmCodecMemory, CheckedBeforeAnyDecompression) {
  std::string bytes = encode(small_mesh());
  const SectionSpan base = section_with_tag(bytes, detail::kTagBase);
  bytes[base.offset + base.size - 1] ^= 0x55;  // BASE's content checksum
  EXPECT_ERROR(decode(bytes), ErrorCode::kChecksumMismatch);
  ProgressiveMesh pm;
  ReadOptions options;
  options.max_memory = 1000;
  EXPECT_ERROR(read_pm(bytes, pm, options), ErrorCode::kResourceLimit);
}

// Every section header is checked before any payload is decompressed: a damaged frame in
// BASE does not hide a truncated LOOS, and framing errors come first.
TEST(PmCodecHardening, SectionHeadersAreCheckedBeforeAnyPayload) {
  std::string bytes = encode(small_mesh());
  const SectionSpan base = section_with_tag(bytes, detail::kTagBase);
  bytes[base.offset + base.size - 1] ^= 0x55;
  const Status status = decode(bytes.substr(0, bytes.size() - 1));
  EXPECT_EQ(status.code(), ErrorCode::kTruncatedStream);
  EXPECT_NE(status.message().find("section LOOS"), std::string::npos) << status.message();
  std::string trailing = bytes + "x";
  EXPECT_EQ(decode(trailing).message(), "1 trailing bytes after the last section");
}

// Frames must state their content size (RFC 8878 §3.1.1.1.4), and it must be the section's.
TEST(PmCodecHardening, FrameWithoutContentSizeIsRejected) {
  const ProgressiveMesh pm = triangle_mesh();
  const std::string raw = spec_sections(pm)[0].raw;
  ZSTD_CCtx* cctx = ZSTD_createCCtx();
  ASSERT_NE(cctx, nullptr);
  ZSTD_CCtx_setParameter(cctx, ZSTD_c_checksumFlag, 1);
  ZSTD_CCtx_setParameter(cctx, ZSTD_c_contentSizeFlag, 0);
  // Streaming without a pledged size leaves the size out of the frame header.
  std::string frame(ZSTD_compressBound(raw.size()), '\0');
  ZSTD_outBuffer out{frame.data(), frame.size(), 0};
  ZSTD_inBuffer in{raw.data(), raw.size(), 0};
  ASSERT_EQ(ZSTD_compressStream2(cctx, &out, &in, ZSTD_e_end), 0u);
  ZSTD_freeCCtx(cctx);
  frame.resize(out.pos);
  ASSERT_EQ(ZSTD_getFrameContentSize(frame.data(), frame.size()), ZSTD_CONTENTSIZE_UNKNOWN);
  std::string bytes;
  detail::append_header(spec_header(pm, 1), bytes);
  ByteWriter writer(bytes);
  writer.put_u32(detail::kTagBase);
  writer.put_u32(detail::kSectionRequired);
  writer.put_u64(frame.size());
  writer.put_u64(raw.size());
  writer.put_bytes(frame);
  const Status status = decode(bytes);
  EXPECT_EQ(status.code(), ErrorCode::kCorruptStream);
  EXPECT_EQ(status.message(), "section BASE: zstd frame does not state its size");
}

// zstd cannot expand a frame more than 32768 times (§4.2): a raw size beyond that is refused
// from the section header, before a buffer of that size exists.
TEST(PmCodecHardening, RawSizeBeyondZstdsExpansionIsRejected) {
  ProgressiveMesh pm;
  pm.loose_vertex_count = 100000;
  pm.positions.assign(300000, 0.0f);  // 1.2 MB of zeros: a tiny frame
  std::string bytes = encode(pm);
  const SectionSpan loose = section_with_tag(bytes, detail::kTagLoose);
  ASSERT_EQ(raw_size_of(bytes, loose), 1200000u);
  put_u64_at(bytes, loose.offset + 8, 20);  // 20 stored bytes cannot hold 1.2 MB
  const Status status = decode(bytes);
  EXPECT_EQ(status.code(), ErrorCode::kCorruptStream);
  EXPECT_EQ(status.message(), "section LOOS: raw size 1200000 is impossible for 20 stored bytes");
}

// ---------------------------------------------------------------------------------------
// validate(): one minimal violation per rule
// ---------------------------------------------------------------------------------------

// Expects small_mesh() after `edit` to fail validate() with a message containing `needle`.
template <typename Edit>
void expect_invalid(Edit edit, const std::string& needle) {
  ProgressiveMesh pm = small_mesh();
  edit(pm);
  const Status status = validate(pm);
  EXPECT_EQ(status.code(), ErrorCode::kInvalidArgument) << "expected: " << needle;
  const std::string& message = status.message();
  EXPECT_NE(message.find(needle), std::string::npos) << message;
}

TEST(PmValidate, LiteralMeshesAreValid) {
  EXPECT_TRUE(test::ok(validate(small_mesh())));
  EXPECT_TRUE(test::ok(validate(triangle_mesh())));
  EXPECT_TRUE(test::ok(validate(ProgressiveMesh{})));
  EXPECT_TRUE(test::ok(validate(small_mesh())));
}

TEST(PmValidate, PositionsNotMultipleOfThree) {
  expect_invalid([](ProgressiveMesh& pm) { pm.positions.pop_back(); }, "not a multiple of 3");
}

TEST(PmValidate, PositionsCountDiffersFromCounts) {
  expect_invalid([](ProgressiveMesh& pm) { pm.loose_vertex_count = 1; },
                 "positions has 9 vertices, expected 8");
}

TEST(PmValidate, FaceArraysNotMultipleOfThree) {
  expect_invalid([](ProgressiveMesh& pm) { pm.base_faces.push_back(0); },
                 "base_faces has 13 indices");
  expect_invalid([](ProgressiveMesh& pm) { pm.carried_faces.push_back(0); },
                 "carried_faces has 4 indices");
}

TEST(PmValidate, BaseFaceIndexOutOfRange) {
  expect_invalid([](ProgressiveMesh& pm) { pm.base_faces[4] = 5; },
                 "base face 1 uses vertex 5 of 5");
}

TEST(PmValidate, BaseFaceRepeatsAVertex) {
  expect_invalid([](ProgressiveMesh& pm) { pm.base_faces[2] = 0; },
                 "base face 0 (0, 1, 0) repeats a vertex");
}

TEST(PmValidate, SplitUMustPrecedeV) {
  expect_invalid([](ProgressiveMesh& pm) { pm.splits[0].u = 5; }, "split 0 has u 5 of 5 vertices");
}

TEST(PmValidate, SplitVlOutOfRange) {
  expect_invalid([](ProgressiveMesh& pm) { pm.splits[1].vl = 6; },
                 "split 1 has vl 6 of 6 vertices");
}

TEST(PmValidate, SplitVrOutOfRange) {
  expect_invalid([](ProgressiveMesh& pm) { pm.splits[0].vr = 7; },
                 "split 0 has vr 7 of 5 vertices");
}

TEST(PmValidate, SplitNeedsVlOrVr) {
  expect_invalid([](ProgressiveMesh& pm) { pm.splits[1].vr = kNoVertex; },
                 "split 1 has neither vl nor vr");
}

TEST(PmValidate, SplitUEqualsVl) {
  expect_invalid([](ProgressiveMesh& pm) { pm.splits[0].vl = 0; }, "split 0 has u 0 equal to vl");
}

TEST(PmValidate, SplitUEqualsVr) {
  // Also the rule "new faces repeat no index": fr would be (5, 6, 5).
  expect_invalid([](ProgressiveMesh& pm) { pm.splits[1].vr = 5; }, "split 1 has u 5 equal to vr");
}

TEST(PmValidate, SplitVlEqualsVr) {
  expect_invalid([](ProgressiveMesh& pm) { pm.splits[0].vl = 3; },
                 "split 0 has vl equal to vr (3)");
}

TEST(PmValidate, MovedRangesMustBeConsecutive) {
  expect_invalid([](ProgressiveMesh& pm) { pm.splits[1].moved_begin = 0; },
                 "split 1 moved faces begin at 0, expected 1");
}

TEST(PmValidate, MovedRangeBeyondMovedFaces) {
  expect_invalid([](ProgressiveMesh& pm) { pm.splits[1].moved_count = 2; },
                 "split 1 moved faces end at 3 of 2");
}

TEST(PmValidate, MovedFacesNotAllUsed) {
  expect_invalid([](ProgressiveMesh& pm) { pm.moved_faces.push_back(0); },
                 "the splits move 2 faces but moved_faces has 3");
}

TEST(PmValidate, MovedFaceOutOfRange) {
  // Split 0 sees the 4 base faces only: face 4 is appended by split 0 itself.
  expect_invalid([](ProgressiveMesh& pm) { pm.moved_faces[0] = 4; }, "split 0 moves face 4 of 4");
}

TEST(PmValidate, MovedFaceTwiceInOneSplit) {
  expect_invalid(
      [](ProgressiveMesh& pm) {
        pm.moved_faces = {1, 1, 4};
        pm.splits[0].moved_count = 2;
        pm.splits[1].moved_begin = 2;
      },
      "split 0 moves face 1 twice");
}

TEST(PmValidate, MovedFaceMustHoldU) {
  // Face 3 is (1, 3, 2): no vertex 0.
  expect_invalid([](ProgressiveMesh& pm) { pm.moved_faces[0] = 3; },
                 "split 0 moves face 3 (1, 3, 2), which does not hold u 0 exactly once");
  // Face 1 was (0, 2, 3) but split 0 turned its 0 into 5, so split 1 (u = 5) may move it
  // while a split with u = 0 no longer can.
  ProgressiveMesh pm = small_mesh();
  pm.moved_faces[1] = 1;
  EXPECT_TRUE(test::ok(validate(pm)));
}

TEST(PmValidate, ErrorsMustBeFiniteAndNonNegative) {
  expect_invalid([](ProgressiveMesh& pm) { pm.splits[1].error = -0.25f; }, "split 1 has error");
  expect_invalid([](ProgressiveMesh& pm) { pm.splits[1].error = std::nanf(""); },
                 "not a finite value");
  expect_invalid(
      [](ProgressiveMesh& pm) { pm.splits[0].error = std::numeric_limits<float>::infinity(); },
      "not a finite value");
}

TEST(PmValidate, ErrorsMustNotIncrease) {
  expect_invalid([](ProgressiveMesh& pm) { pm.splits[1].error = 0.75f; },
                 "above the previous split's");
}

TEST(PmValidate, WeldVerticesMustBeBaseVertices) {
  expect_invalid([](ProgressiveMesh& pm) { pm.welds[0].copy = 5; },
                 "weld 0 (5 -> 1) uses a vertex outside");
  expect_invalid([](ProgressiveMesh& pm) { pm.welds[0].canonical = 6; },
                 "weld 0 (4 -> 6) uses a vertex outside");
}

TEST(PmValidate, WeldToItself) {
  expect_invalid([](ProgressiveMesh& pm) { pm.welds[0].canonical = 4; },
                 "weld 0 welds vertex 4 to itself");
}

TEST(PmValidate, WeldCopyTwice) {
  expect_invalid(
      [](ProgressiveMesh& pm) {
        pm.welds.push_back(Weld{4, 2});
      },
      "weld 1 welds vertex 4 a second time");
}

TEST(PmValidate, WeldCanonicalIsACopy) {
  // The later weld makes weld 0's canonical a copy: checked after all copies are known.
  expect_invalid(
      [](ProgressiveMesh& pm) {
        pm.welds.push_back(Weld{1, 2});
      },
      "weld 0 has canonical vertex 1, itself a copy");
}

TEST(PmValidate, CarriedFaceIndexOutOfRange) {
  expect_invalid([](ProgressiveMesh& pm) { pm.carried_faces[2] = 5; },
                 "carried face 0 uses vertex 5 of 5");
  // A repeated index is what carried faces are for.
  ProgressiveMesh pm = small_mesh();
  pm.carried_faces = {3, 3, 3};
  EXPECT_TRUE(test::ok(validate(pm)));
}

TEST(PmValidate, TooManyVerticesForIds) {
  // Counts whose sum reaches kNoVertex, with positions to match, would need 48 GB: the
  // sum check comes before the size check, so mismatched positions are reported instead.
  ProgressiveMesh pm;
  pm.base_vertex_count = 0xFFFFFFFFu;
  pm.loose_vertex_count = 1;
  const std::string message = validate(pm).message();
  EXPECT_NE(message.find("expected 4294967296"), std::string::npos) << message;
}

}  // namespace
}  // namespace pm

// SplitFans::Prefetch only reads ahead: with walks started on every kind of vertex (a fan,
// one without faces, one beyond the mesh, none) and splits made while they run, every fan
// is what it is without it.
TEST(SplitFans, PrefetchLeavesTheFansAsTheyAre) {
  using pm::detail::SplitFans;
  // A hexagon of faces around vertex 0 (ring 1..6), and vertex 7 with none.
  const auto build = [](SplitFans& fans) {
    fans.reset(9, 8);
    for (uint32_t k = 1; k <= 6; ++k) fans.add_face(0, k, k % 6 + 1);
  };
  SplitFans plain, fetched;
  build(plain);
  build(fetched);
  std::vector<uint32_t> values(3 * 8, 7);
  values.reserve(3 * 9);
  SplitFans::Prefetch prefetch(fetched, &values);
  const uint32_t walks[] = {0, 7, 1, 1000000, SplitFans::kNone, 3, 0, 6};
  const auto same_fans = [&](uint32_t vertex_count) {
    for (uint32_t u = 0; u < vertex_count; ++u) {
      SplitFans::Fan a, b;
      const bool has_a = plain.fan(u, a), has_b = fetched.fan(u, b);
      EXPECT_EQ(has_a, has_b) << "vertex " << u;
      EXPECT_EQ(a.ring, b.ring) << "vertex " << u;
      EXPECT_EQ(a.faces, b.faces) << "vertex " << u;
      EXPECT_EQ(a.closed, b.closed) << "vertex " << u;
    }
  };
  for (int round = 0; round < 3; ++round) {
    for (const uint32_t u : walks) prefetch.step(u);
    same_fans(8);
  }
  // Split 0 -> 0 and 8, vertex 8 taking faces 0 and 1 (between ring vertices 1 and 3).
  const uint32_t moved[] = {0, 1};
  plain.split(0, 8, 1, 3, moved, 2);
  fetched.split(0, 8, 1, 3, moved, 2);
  values.insert(values.end(), {1, 2, 3});
  for (int step = 0; step < 40; ++step) prefetch.step(walks[step % 8] == 7 ? 8 : walks[step % 8]);
  same_fans(9);
  SplitFans::Fan fan;
  ASSERT_TRUE(fetched.fan(8, fan));
  EXPECT_EQ(fan.faces.size(), 4u);  // faces 0 and 1, and the new (8, 0, 1) and (0, 8, 3)
}

// A split that names u's fan and the arc's first place keeps the corner lists in fan order
// (split_arc): every fan afterwards, of every vertex, is the one the plain split (the moved
// faces alone, lists in any order) leaves, with the same faces, over a long run of random
// splits of interior (closed) and boundary (open) fans, arcs of every length among them.
TEST(SplitFans, ArcSplitsLeaveTheFansPlainSplitsLeave) {
  using pm::detail::SplitFans;
  constexpr uint32_t kSide = 9;  // (kSide + 1)^2 grid vertices, two triangles a square
  const uint32_t grid_vertices = (kSide + 1) * (kSide + 1);
  constexpr uint32_t kSplits = 3000;
  SplitFans arc_split, plain;
  for (SplitFans* fans : {&arc_split, &plain}) {
    fans->reset(grid_vertices + kSplits, 2 * kSide * kSide + 2 * kSplits);
    for (uint32_t y = 0; y < kSide; ++y) {
      for (uint32_t x = 0; x < kSide; ++x) {
        const uint32_t a = y * (kSide + 1) + x, b = a + 1, c = a + kSide + 1, d = c + 1;
        fans->add_face(a, b, d);
        fans->add_face(a, d, c);
      }
    }
  }
  // The base mesh's corners are searched once each, then kept in fan order.
  for (uint32_t w = 0; w < grid_vertices; ++w) {
    SplitFans::Fan fan;
    ASSERT_TRUE(arc_split.fan(w, fan));
  }
  const std::size_t base_searches = arc_split.searches();
  EXPECT_GT(base_searches, grid_vertices / 2);
  std::mt19937 random(20261125);
  uint32_t closed_splits = 0, open_splits = 0, whole_open_ends = 0;
  for (uint32_t v = grid_vertices; v < grid_vertices + kSplits; ++v) {
    SplitFans::Fan fan;
    uint32_t u = 0;
    do {
      u = std::uniform_int_distribution<uint32_t>(0, v - 1)(random);
    } while (!plain.fan(u, fan) || fan.faces.size() < 2);
    const std::size_t n = fan.faces.size();
    std::size_t first = 0, end = 0;
    uint32_t vl = SplitFans::kNone, vr = SplitFans::kNone;
    if (fan.closed) {
      first = std::uniform_int_distribution<std::size_t>(0, n - 1)(random);
      end = (first + std::uniform_int_distribution<std::size_t>(1, n - 1)(random)) % n;
      vl = fan.ring[first];
      vr = fan.ring[end];
      ++closed_splits;
    } else {
      // Places 0 .. n; vl none is place 0 and vr none place n, not both.
      do {
        first = std::uniform_int_distribution<std::size_t>(0, n - 1)(random);
        end = std::uniform_int_distribution<std::size_t>(first + 1, n)(random);
      } while (first == 0 && end == n);
      const bool vl_none = first == 0 && random() % 2 == 0;
      const bool vr_none = !vl_none && end == n && random() % 2 == 0;
      vl = vl_none ? SplitFans::kNone : fan.ring[first];
      vr = vr_none ? SplitFans::kNone : fan.ring[end];
      whole_open_ends += vl_none || vr_none;
      ++open_splits;
    }
    std::vector<uint32_t> moved;
    ASSERT_TRUE(SplitFans::arc(fan, first, end, moved));
    SplitFans::Fan arc_fan;
    ASSERT_TRUE(arc_split.fan(u, arc_fan));
    ASSERT_EQ(arc_fan.ring, fan.ring);
    ASSERT_EQ(arc_fan.faces, fan.faces);
    arc_split.split(u, v, vl, vr, moved.data(), moved.size(), &arc_fan, first);
    plain.split(u, v, vl, vr, moved.data(), moved.size());
    // The fans around the split: u, v, the ring's vertices.
    std::vector<uint32_t> touched = {u, v};
    touched.insert(touched.end(), fan.ring.begin(), fan.ring.end());
    for (const uint32_t w : touched) {
      SplitFans::Fan a, b;
      const bool has_a = arc_split.fan(w, a), has_b = plain.fan(w, b);
      ASSERT_EQ(has_a, has_b) << "split " << v << ", vertex " << w;
      ASSERT_EQ(a.ring, b.ring) << "split " << v << ", vertex " << w;
      ASSERT_EQ(a.faces, b.faces) << "split " << v << ", vertex " << w;
      ASSERT_EQ(a.closed, b.closed) << "split " << v << ", vertex " << w;
    }
  }
  EXPECT_EQ(arc_split.searches(), base_searches);  // every fan since was a walk
  EXPECT_GT(plain.searches(), std::size_t{kSplits});
  ASSERT_EQ(arc_split.face_count(), plain.face_count());
  for (uint32_t f = 0; f < plain.face_count(); ++f) {
    ASSERT_TRUE(std::equal(plain.face(f), plain.face(f) + 3, arc_split.face(f))) << "face " << f;
  }
  for (uint32_t w = 0; w < grid_vertices + kSplits; ++w) {
    SplitFans::Fan a, b;
    ASSERT_EQ(arc_split.fan(w, a), plain.fan(w, b)) << "vertex " << w;
    ASSERT_EQ(a.ring, b.ring) << "vertex " << w;
    ASSERT_EQ(a.faces, b.faces) << "vertex " << w;
  }
  EXPECT_GT(closed_splits, 1000u);
  EXPECT_GT(open_splits, 100u);
  EXPECT_GT(whole_open_ends, 20u);
}
