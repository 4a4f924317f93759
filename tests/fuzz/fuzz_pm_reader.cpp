// libFuzzer target: the .pm reader (read_pm, read_pm_info) and, on every stream it accepts,
// the level-of-detail API and a write/read round trip (see fuzz_common.h), attributes
// (format 1.1) included.
//
// A .pm stream is sealed twice over: a CRC-32 on the header and a zstd content checksum on
// each section. Blind mutations almost never get past them, so the section decoders and
// validate() would see nothing but the seeds. The custom mutator below therefore also
// mutates the stream as its writer would have produced it: a header field, re-sealed with
// its CRC, or a section's decompressed payload, recompressed with a fresh checksum (the
// approach of the zlib/PNG fuzzers for their CRCs). A quarter of the mutations stay blind,
// for the framing: section headers, sizes, tags, truncation, trailing bytes.
#include <zstd.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "../../formats/byte_io.h"
#include "../../formats/pm_layout.h"
#include "fuzz_common.h"
#include "pm/advanced/pm_stream.h"

extern "C" size_t LLVMFuzzerMutate(uint8_t* data, size_t size, size_t max_size);

namespace pm::fuzz {
namespace {

uint32_t get_u32(std::string_view bytes, std::size_t offset) {
  uint32_t value = 0;
  for (int i = 3; i >= 0; --i) value = value << 8 | static_cast<uint8_t>(bytes[offset + i]);
  return value;
}

uint64_t get_u64(std::string_view bytes, std::size_t offset) {
  return uint64_t{get_u32(bytes, offset)} | uint64_t{get_u32(bytes, offset + 4)} << 32;
}

void put_u32(std::string& bytes, std::size_t offset, uint32_t value) {
  for (int i = 0; i < 4; ++i) bytes[offset + i] = static_cast<char>(value >> (8 * i));
}

void reseal_header(std::string& bytes) {
  put_u32(bytes, detail::kHeaderCrcOffset,
          detail::crc32(std::string_view(bytes).substr(0, detail::kHeaderCrcOffset)));
}

struct Section {
  uint32_t tag = 0;
  uint32_t flags = 0;
  uint64_t raw_size = 0;
  std::string_view frame;
};

// The sections of a stream whose framing is intact (the header's contents are not checked).
bool split_sections(std::string_view bytes, std::vector<Section>& sections) {
  if (bytes.size() < detail::kHeaderSize ||
      bytes.substr(0, sizeof detail::kMagic) != std::string_view(detail::kMagic, 8)) {
    return false;
  }
  std::size_t pos = detail::kHeaderSize;
  while (bytes.size() - pos >= detail::kSectionHeaderSize) {
    Section section;
    section.tag = get_u32(bytes, pos);
    section.flags = get_u32(bytes, pos + 4);
    const uint64_t stored = get_u64(bytes, pos + 8);
    section.raw_size = get_u64(bytes, pos + 16);
    pos += detail::kSectionHeaderSize;
    if (stored > bytes.size() - pos) return false;
    section.frame = bytes.substr(pos, static_cast<std::size_t>(stored));
    pos += static_cast<std::size_t>(stored);
    sections.push_back(section);
  }
  return pos == bytes.size() && !sections.empty();
}

// The payload of a valid frame of at most `max_size` bytes.
bool decompress(std::string_view frame, std::size_t max_size, std::string& raw) {
  const unsigned long long size = ZSTD_getFrameContentSize(frame.data(), frame.size());
  if (size == ZSTD_CONTENTSIZE_UNKNOWN || size == ZSTD_CONTENTSIZE_ERROR || size > max_size) {
    return false;
  }
  raw.resize(static_cast<std::size_t>(size));
  const size_t result = ZSTD_decompress(raw.data(), raw.size(), frame.data(), frame.size());
  return !ZSTD_isError(result) && result == raw.size();
}

// One header count, flag or version field changed to a value likely to matter.
void mutate_header_field(std::string& bytes, std::minstd_rand& rng) {
  // u16 major+minor at 8; the 1.1 attribute fields at 56..80; reserved bytes at 84 and 88.
  static constexpr std::size_t kFields[] = {8,  12, 16, 20, 24, 28, 32, 36, 40, 44, 48,
                                            52, 56, 60, 64, 68, 72, 76, 80, 84, 88};
  const std::size_t offset = kFields[rng() % std::size(kFields)];
  const uint32_t old = get_u32(bytes, offset);
  const uint32_t candidates[] = {old + 1,
                                 old - 1,
                                 old ^ (uint32_t{1} << (rng() % 32)),
                                 static_cast<uint32_t>(rng() % 8),
                                 old * 2,
                                 detail::kMaxCount,
                                 static_cast<uint32_t>(rng()) << 1 ^ static_cast<uint32_t>(rng())};
  const uint32_t value = candidates[rng() % std::size(candidates)];
  put_u32(bytes, offset, value);
}

std::size_t mutate(uint8_t* data, std::size_t size, std::size_t max_size, unsigned seed) {
  std::minstd_rand rng(seed);
  const unsigned choice = rng() % 8;
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  std::vector<Section> sections;
  if (choice < 2 || !split_sections(input, sections)) return LLVMFuzzerMutate(data, size, max_size);

  std::string out(input.substr(0, detail::kHeaderSize));
  if (choice == 2) {
    mutate_header_field(out, rng);
    out.append(input.substr(detail::kHeaderSize));
  } else {
    const std::size_t target = rng() % sections.size();
    std::string raw;
    if (!decompress(sections[target].frame, max_size * 64, raw)) {
      return LLVMFuzzerMutate(data, size, max_size);
    }
    const std::size_t raw_size = raw.size();
    const std::size_t raw_capacity = raw_size * 2 + 64;
    raw.resize(raw_capacity);
    raw.resize(LLVMFuzzerMutate(reinterpret_cast<uint8_t*>(raw.data()), raw_size, raw_capacity));
    for (std::size_t s = 0; s < sections.size(); ++s) {
      const Section& section = sections[s];
      if (s != target) {  // copied as is, section header and frame
        out.append(section.frame.data() - detail::kSectionHeaderSize,
                   detail::kSectionHeaderSize + section.frame.size());
        continue;
      }
      // Now and then the declared size is left stale, to exercise that check too.
      const uint64_t declared = rng() % 16 == 0 ? section.raw_size : raw.size();
      if (!detail::append_section(section.tag, section.flags, raw, declared, 1, out)) {
        return LLVMFuzzerMutate(data, size, max_size);
      }
      // The header repeats split 0's error, the first of SPLT's trailing f32 errors: keep
      // it in step, or every SPLT mutation would fail on that before reaching validate().
      const uint32_t splits = get_u32(out, 24);
      if (section.tag == detail::kTagSplits && splits > 0 && raw.size() >= 4 * uint64_t{splits}) {
        put_u32(out, 52, get_u32(raw, raw.size() - 4 * std::size_t{splits}));
      }
    }
  }
  reseal_header(out);
  if (out.size() > max_size) return LLVMFuzzerMutate(data, size, max_size);
  std::memcpy(data, out.data(), out.size());
  return out.size();
}

}  // namespace
}  // namespace pm::fuzz

extern "C" size_t LLVMFuzzerCustomMutator(uint8_t* data, size_t size, size_t max_size,
                                          unsigned int seed) {
  return pm::fuzz::mutate(data, size, max_size, seed);
}

namespace pm::fuzz {
namespace {

// fuzz_common.h's identical() compares the geometry; these are the 1.1 fields.
bool same_attributes(const ProgressiveMesh& a, const ProgressiveMesh& b) {
  return a.color_components == b.color_components && same_floats(a.colors, b.colors) &&
         same_floats(a.uvs, b.uvs) && same_floats(a.normals, b.normals) &&
         a.material_names == b.material_names && a.material_libraries == b.material_libraries &&
         a.face_uvs == b.face_uvs && a.face_normals == b.face_normals &&
         a.face_materials == b.face_materials && a.moved_uvs == b.moved_uvs &&
         a.moved_normals == b.moved_normals;
}

// The attributes of what read_pm accepted survive a write/read round trip, and an extracted
// level has them at the right sizes.
void check_attributes(const ProgressiveMesh& pm) {
  std::string bytes;
  if (Status written = write_pm(pm, WriteOptions{1}, bytes); !written) {
    fail("write_pm of a valid progressive mesh: " + written.message());
  }
  ProgressiveMesh decoded;
  if (Status read = read_pm(bytes, decoded); !read)
    fail("read_pm of write_pm's output: " + read.message());
  const ProgressiveMesh a = test::with_sorted_moves(pm), b = test::with_sorted_moves(decoded);
  check(identical(a, b) && same_attributes(a, b),
        "read_pm(write_pm(pm)) differs from pm in its attributes");
  const Mesh mesh = extract_level(pm, pm.split_count() / 2);
  check(validate_attributes(mesh).is_ok(), "extract_level: invalid attributes");
  check(mesh.colors.size() == std::size_t{pm.color_components} * mesh.vertex_count(),
        "extract_level: colour count");
  check(mesh.uv_indices.size() == (pm.has_uvs() ? mesh.triangles.size() : 0),
        "extract_level: uv index count");
  check(mesh.normal_indices.size() == (pm.has_normals() ? mesh.triangles.size() : 0),
        "extract_level: normal index count");
  check(mesh.face_materials.size() == (pm.has_materials() ? mesh.face_count() : 0),
        "extract_level: material count");
}

}  // namespace
}  // namespace pm::fuzz

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pm;
  using namespace pm::fuzz;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  PmInfo info;
  const Status info_status = read_pm_info(bytes, info);
  ProgressiveMesh progressive;
  // Bounded well below libFuzzer's -rss_limit_mb / -malloc_limit_mb (2048 in .ci/fuzz):
  // zstd expands up to 32768 times, so a small stream may honestly need gigabytes, and
  // the reader must refuse it (kResourceLimit) before allocating.
  ReadOptions options;
  options.max_memory = uint64_t{1} << 30;
  const Status status = read_pm(bytes, progressive, options);
  if (!info_status) {
    check_error(info_status, "read_pm_info");
    // read_pm reads the header the same way, so it fails the same way; in a 2.0 stream
    // read_pm_info reads the chunk index too, after sections read_pm may fail on first.
    check(info_status.code() == status.code() || (size > 8 && data[8] == 2 && !status),
          "read_pm and read_pm_info disagree");
    return 0;
  }
  if (!status) {
    check_error(status, "read_pm");
    return 0;
  }
  const ProgressiveMesh& pm = progressive;
  // The reader runs validate() less its replay of the moved faces on a 2.x stream, having
  // replayed them itself (validate_decoded.h): the whole of validate() must agree.
  std::string problem;
  if (Status valid = validate(pm); !valid)
    fail("read_pm returned a mesh validate() refuses: " + valid.message());
  const std::size_t full = pm.split_count();
  check(info.base_vertex_count == pm.base_vertex_count && info.split_count == full &&
            info.base_face_count == pm.base_face_count() &&
            info.loose_vertex_count == pm.loose_vertex_count &&
            info.weld_count == pm.welds.size() &&
            info.carried_face_count == pm.carried_faces.size() / 3 &&
            info.moved_face_count == pm.moved_faces.size(),
        "read_pm_info's counts differ from read_pm's");
  check(info.color_components == pm.color_components && info.uv_count == pm.uv_count() &&
            info.normal_count == pm.normal_count() &&
            info.material_count == pm.material_names.size() &&
            info.material_library_count == pm.material_libraries.size() &&
            info.has_uvs == pm.has_uvs() && info.has_normals == pm.has_normals() &&
            info.has_materials == pm.has_materials(),
        "read_pm_info's attributes differ from read_pm's");
  check(info.full_face_count == faces_at_level(pm, full), "read_pm_info: full face count");
  check(info.full_vertex_count == vertices_at_level(pm, full), "read_pm_info: full vertex count");
  check_levels(pm);
  check_pm_round_trip(pm);
  check_attributes(pm);
  // pmdec --info --sizes: a stream read_pm accepts is measured, and its parts add up.
  if (info.major == 2) {
    PmSizes sizes;
    const Status measured = measure_pm_sizes(bytes, sizes, options);
    check(measured.is_ok(), "measure_pm_sizes refuses a stream read_pm accepts");
    uint64_t total = sizes.header;
    for (const auto& section : sizes.sections) total += section.second;
    check(total == size, "measure_pm_sizes: the sections do not add up to the stream");
  }
  return 0;
}
