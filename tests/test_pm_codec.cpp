// The .pm codec (formats/pm-format.md) and validate().
//
// Round trips of small literal progressive meshes, field by field; a reference encoder
// written from the spec (not from pm_codec.cpp) whose streams the reader must accept;
// adversarial streams: every truncation, every single-byte flip, trailing bytes, bad
// magic, versions, reserved bits, hostile counts and sizes; one validate() test per rule.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "../formats/byte_io.h"
#include "../formats/pm_layout.h"
#include "pm/encoder.h"
#include "pm/mesh_io.h"
#include "pm/pm_codec.h"
#include "pm/progressive_mesh.h"
#include "test_util.h"

namespace pm {
namespace {

using detail::ByteWriter;

// ---------------------------------------------------------------------------------------
// Literal meshes
// ---------------------------------------------------------------------------------------

// A tetrahedron 0-1-2-3 plus vertex 4, a copy of vertex 1 (welded), refined by two splits:
//
//   split 0 creates 5 from u = 0 (interior: vl = 2, vr = 3); face 1 (0, 2, 3) moves to 5,
//           then appends face 4 = (5, 0, 2) and face 5 = (0, 5, 3).
//   split 1 creates 6 from u = 5 (boundary: vl = none, vr = 3); it moves face 4, which
//           split 0 created, and appends face 6 = (5, 6, 3).
//
// One carried face (2, 2, 3) and two loose vertices (7, 8).
ProgressiveMesh small_mesh() {
  ProgressiveMesh pm;
  pm.base_vertex_count = 5;
  pm.loose_vertex_count = 2;
  pm.positions = {
      0.0f,   0.0f,   0.0f,   // 0
      1.0f,   0.0f,   0.0f,   // 1
      0.0f,   1.0f,   0.0f,   // 2
      0.0f,   0.0f,   1.0f,   // 3
      1.0f,   0.0f,   0.0f,   // 4: copy of 1
      -0.5f,  0.5f,   0.25f,  // 5: split 0
      -0.75f, 0.5f,   0.5f,   // 6: split 1
      3.0f,   3.0f,   3.0f,   // 7: loose
      -3.0f,  1e-30f, 1e30f,  // 8: loose
  };
  pm.base_faces = {0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2};
  VertexSplit split0;
  split0.u = 0;
  split0.vl = 2;
  split0.vr = 3;
  split0.error = 0.5f;
  split0.moved_begin = 0;
  split0.moved_count = 1;
  VertexSplit split1;
  split1.u = 5;
  split1.vl = kNoVertex;
  split1.vr = 3;
  split1.error = 0.25f;
  split1.moved_begin = 1;
  split1.moved_count = 1;
  pm.splits = {split0, split1};
  pm.moved_faces = {1, 4};
  pm.welds = {Weld{4, 1}};
  pm.carried_faces = {2, 2, 3};
  return pm;
}

// A single triangle and nothing else: only BASE is written.
ProgressiveMesh triangle_mesh() {
  ProgressiveMesh pm;
  pm.base_vertex_count = 3;
  pm.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  pm.base_faces = {0, 1, 2};
  return pm;
}

// A deterministic, larger mesh: a triangle fan refined by `split_count` splits at random
// vertices, so ids pass 127 and 16383 and the varints take 2 and 3 bytes.
ProgressiveMesh generated_mesh(uint32_t split_count) {
  uint64_t state = 0x9E3779B97F4A7C15ull;
  auto next = [&state](uint32_t bound) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<uint32_t>((state >> 33) % bound);
  };
  ProgressiveMesh pm;
  const uint32_t ring = 8;
  pm.base_vertex_count = ring + 1;
  for (uint32_t i = 0; i <= ring; ++i) {
    pm.positions.insert(pm.positions.end(), {std::cos(float(i)), std::sin(float(i)), 0.0f});
  }
  for (uint32_t i = 0; i < ring; ++i)
    pm.base_faces.insert(pm.base_faces.end(), {ring, i, (i + 1) % ring});
  std::vector<uint32_t> faces = pm.base_faces;
  float error = 10.0f;
  for (uint32_t i = 0; i < split_count; ++i) {
    const uint32_t v = pm.base_vertex_count + i;
    // u from a random face, so it has faces to move.
    const uint32_t face = next(static_cast<uint32_t>(faces.size() / 3));
    const uint32_t corner = next(3);
    VertexSplit split;
    split.u = faces[3 * face + corner];
    const uint32_t other1 = faces[3 * face + (corner + 1) % 3];
    const uint32_t other2 = faces[3 * face + (corner + 2) % 3];
    split.vl = next(4) == 0 ? kNoVertex : other1;
    split.vr = split.vl == kNoVertex || next(3) != 0 ? other2 : kNoVertex;
    split.error = error;
    error *= 0.999f;
    split.moved_begin = static_cast<uint32_t>(pm.moved_faces.size());
    for (uint32_t f = 0; f < faces.size() / 3; ++f) {
      uint32_t* corners = &faces[3 * f];
      const bool has_u = corners[0] == split.u || corners[1] == split.u || corners[2] == split.u;
      if (has_u && next(2) == 0) {
        pm.moved_faces.push_back(f);
        for (int c = 0; c < 3; ++c) {
          if (corners[c] == split.u) corners[c] = v;
        }
      }
    }
    split.moved_count = static_cast<uint32_t>(pm.moved_faces.size()) - split.moved_begin;
    if (split.vl != kNoVertex) faces.insert(faces.end(), {v, split.u, split.vl});
    if (split.vr != kNoVertex) faces.insert(faces.end(), {split.u, v, split.vr});
    pm.splits.push_back(split);
    pm.positions.insert(pm.positions.end(), {float(next(1000)) / 7.0f, float(i), -1.0f});
  }
  return pm;
}

std::string bits_of(const std::vector<float>& values) {
  return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float));
}

// Every field, floats by bit pattern.
void expect_identical(const ProgressiveMesh& a, const ProgressiveMesh& b) {
  EXPECT_EQ(a.base_vertex_count, b.base_vertex_count);
  EXPECT_EQ(a.loose_vertex_count, b.loose_vertex_count);
  EXPECT_EQ(bits_of(a.positions), bits_of(b.positions));
  EXPECT_EQ(a.base_faces, b.base_faces);
  ASSERT_EQ(a.splits.size(), b.splits.size());
  for (std::size_t i = 0; i < a.splits.size(); ++i) {
    SCOPED_TRACE("split " + std::to_string(i));
    EXPECT_EQ(a.splits[i].u, b.splits[i].u);
    EXPECT_EQ(a.splits[i].vl, b.splits[i].vl);
    EXPECT_EQ(a.splits[i].vr, b.splits[i].vr);
    EXPECT_EQ(bits_of({a.splits[i].error}), bits_of({b.splits[i].error}));
    EXPECT_EQ(a.splits[i].moved_begin, b.splits[i].moved_begin);
    EXPECT_EQ(a.splits[i].moved_count, b.splits[i].moved_count);
  }
  EXPECT_EQ(a.moved_faces, b.moved_faces);
  ASSERT_EQ(a.welds.size(), b.welds.size());
  for (std::size_t i = 0; i < a.welds.size(); ++i) {
    EXPECT_EQ(a.welds[i].copy, b.welds[i].copy);
    EXPECT_EQ(a.welds[i].canonical, b.welds[i].canonical);
  }
  EXPECT_EQ(a.carried_faces, b.carried_faces);
}

bool identical(const ProgressiveMesh& a, const ProgressiveMesh& b) {
  auto same_splits = [&] {
    for (std::size_t i = 0; i < a.splits.size(); ++i) {
      const VertexSplit &x = a.splits[i], &y = b.splits[i];
      if (x.u != y.u || x.vl != y.vl || x.vr != y.vr || x.moved_begin != y.moved_begin ||
          x.moved_count != y.moved_count || bits_of({x.error}) != bits_of({y.error})) {
        return false;
      }
    }
    return true;
  };
  auto same_welds = [&] {
    for (std::size_t i = 0; i < a.welds.size(); ++i) {
      if (a.welds[i].copy != b.welds[i].copy || a.welds[i].canonical != b.welds[i].canonical) {
        return false;
      }
    }
    return true;
  };
  return a.base_vertex_count == b.base_vertex_count &&
         a.loose_vertex_count == b.loose_vertex_count &&
         bits_of(a.positions) == bits_of(b.positions) && a.base_faces == b.base_faces &&
         a.splits.size() == b.splits.size() && same_splits() && a.moved_faces == b.moved_faces &&
         a.welds.size() == b.welds.size() && same_welds() && a.carried_faces == b.carried_faces;
}

std::string encode(const ProgressiveMesh& pm, int level = 3) {
  std::string bytes;
  WriteOptions options;
  options.zstd_level = level;
  const Status status = write_pm(pm, options, bytes);
  EXPECT_TRUE(status.is_ok()) << status.message();
  return bytes;
}

// ---------------------------------------------------------------------------------------
// Byte surgery
// ---------------------------------------------------------------------------------------

// Header offsets (pm-format.md §3.1).
constexpr std::size_t kMajorOffset = 8, kMinorOffset = 10, kFlagsOffset = 12;
constexpr std::size_t kSplitCountOffset = 24, kSectionCountOffset = 48, kMaxErrorOffset = 52;

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
// A reference encoder written from pm-format.md §5 (independent of pm_codec.cpp).
// ---------------------------------------------------------------------------------------

struct RawSection {
  uint32_t tag;
  std::string raw;
};

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
  return sections;
}

detail::Header spec_header(const ProgressiveMesh& pm, uint32_t section_count) {
  detail::Header h;
  h.major = 1;
  h.minor = 0;
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
  return h;
}

std::string assemble(const detail::Header& header, const std::vector<RawSection>& sections) {
  std::string bytes;
  detail::append_header(header, bytes);
  for (const RawSection& section : sections) {
    const Status status = detail::append_section(section.tag, detail::kSectionRequired, section.raw,
                                                 section.raw.size(), 3, bytes);
    EXPECT_TRUE(status.is_ok()) << status.message();
  }
  return bytes;
}

std::string spec_stream(const ProgressiveMesh& pm) {
  const auto sections = spec_sections(pm);
  return assemble(spec_header(pm, uint32_t(sections.size())), sections);
}

// ---------------------------------------------------------------------------------------
// Round trips
// ---------------------------------------------------------------------------------------

TEST(PmCodecRoundTrip, SmallMeshIsExact) {
  const ProgressiveMesh original = small_mesh();
  std::string message;
  ASSERT_TRUE(validate(original, &message)) << message;
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
  ASSERT_TRUE(validate(original, &message)) << message;
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
  // pm-format.md §3.1 for small_mesh(): counts 5, 4, 2, 2, 1, 1, moved 2, split faces 3,
  // 5 sections, max error 0.5, 36 reserved zero bytes, then the CRC.
  const std::string bytes = encode(small_mesh());
  const std::string expected_fields =
      std::string("\x89PMESH\r\n", 8) + std::string("\x01\x00\x00\x00", 4) +  // 1.0
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
  EXPECT_EQ(info.minor, 0);
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
  for (const ProgressiveMesh& original : {small_mesh(), triangle_mesh()}) {
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
  for (uint16_t major : {0, 2, 0xFFFF}) {
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
  for (std::size_t offset = detail::kHeaderReservedOffset; offset < detail::kHeaderCrcOffset;
       ++offset) {
    std::string bytes = encode(small_mesh());
    bytes[offset] = 1;
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
    std::string bytes = assemble(header, sections);
    bytes[60] = 42;  // a field of minor 7
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

TEST(PmCodecAdversarial, UnknownSectionsInVersion1_0) {
  const ProgressiveMesh original = small_mesh();
  auto sections = spec_sections(original);
  sections.push_back(RawSection{detail::make_tag("XTRA"), "vendor data"});
  std::string bytes = assemble(spec_header(original, uint32_t(sections.size())), sections);
  const SectionSpan extra = section_with_tag(bytes, detail::make_tag("XTRA"));
  EXPECT_ERROR(decode(bytes), ErrorCode::kUnsupportedVersion);  // written as required
  put_u32_at(bytes, extra.offset + 4, 0);
  ProgressiveMesh decoded;
  ASSERT_TRUE(decode(bytes, &decoded).is_ok());
  expect_identical(original, decoded);
  bytes[extra.offset] = '\x01';  // tags are letters and digits
  EXPECT_ERROR(decode(bytes), ErrorCode::kCorruptStream);
}

// Any single damaged byte is either detected or (were that possible) harmless: never a
// different mesh.
TEST(PmCodecAdversarial, EverySingleByteFlipIsDetected) {
  const ProgressiveMesh original = small_mesh();
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
      EXPECT_NE(status.code(), ErrorCode::kInternal) << "byte " << i << ": " << status.message();
    }
  }
  EXPECT_EQ(accepted, 0);
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
TEST(PmCodecAdversarial, EveryByteFlipOfAnEncodedSampleIsAnErrorOrHarmless) {
  Mesh mesh;
  ASSERT_TRUE(read_mesh(test::sample_mesh_path("nonmanifold.obj"), mesh).is_ok());
  ProgressiveMesh original;
  ASSERT_TRUE(pm::encode(mesh, EncodeOptions{}, original).is_ok());
  const std::string bytes = encode(original, 19);
  const std::vector<SectionSpan> sections = sections_of(bytes);
  ASSERT_EQ(sections.size(), 5u);
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
        // An unknown tag is a section of a later version (it is marked required).
        EXPECT_TRUE(code == ErrorCode::kCorruptStream || code == ErrorCode::kTruncatedStream ||
                    code == ErrorCode::kUnsupportedVersion);
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
// validate(): one minimal violation per rule
// ---------------------------------------------------------------------------------------

// Expects small_mesh() after `edit` to fail validate() with a message containing `needle`.
template <typename Edit>
void expect_invalid(Edit edit, const std::string& needle) {
  ProgressiveMesh pm = small_mesh();
  edit(pm);
  std::string message;
  EXPECT_FALSE(validate(pm, &message)) << "expected: " << needle;
  EXPECT_NE(message.find(needle), std::string::npos) << message;
}

TEST(PmValidate, LiteralMeshesAreValid) {
  std::string message;
  EXPECT_TRUE(validate(small_mesh(), &message)) << message;
  EXPECT_TRUE(validate(triangle_mesh(), &message)) << message;
  EXPECT_TRUE(validate(ProgressiveMesh{}, &message)) << message;
  EXPECT_TRUE(validate(small_mesh(), nullptr));
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
  std::string message;
  EXPECT_TRUE(validate(pm, &message)) << message;
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
  EXPECT_TRUE(validate(pm, nullptr));
}

TEST(PmValidate, TooManyVerticesForIds) {
  // Counts whose sum reaches kNoVertex, with positions to match, would need 48 GB: the
  // sum check comes before the size check, so mismatched positions are reported instead.
  ProgressiveMesh pm;
  pm.base_vertex_count = 0xFFFFFFFFu;
  pm.loose_vertex_count = 1;
  std::string message;
  EXPECT_FALSE(validate(pm, &message));
  EXPECT_NE(message.find("expected 4294967296"), std::string::npos) << message;
}

}  // namespace
}  // namespace pm
