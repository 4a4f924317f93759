// The .pm stream: reader and writer. The byte layout is specified in
// formats/pm-format.md, which is normative; this code follows it.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "pm/progressive_mesh.h"
#include "pm/status.h"

namespace pm {

inline constexpr uint16_t kFormatMajor = 1;
inline constexpr uint16_t kFormatMinor = 1;  // 1.1: attributes

struct WriteOptions {
  int zstd_level = 19;  // 1..22
};

// Serializes pm (which must be valid) to bytes, as format 1.1. Errors: kInvalidArgument
// when validate(pm) fails, a material name or library holds a NUL, or
// zstd_level is outside 1..22; kResourceLimit when a count exceeds the format's limits
// (2^30; 2^20 materials and libraries) or a string is longer than 4096 bytes. `bytes` is
// untouched on error.
Status write_pm(const ProgressiveMesh& pm, const WriteOptions& options, std::string& bytes);

// Whether the stream can hold these material names and libraries (§5.9, §7.2: at most 2^20
// of each, each at most 4096 bytes without NUL). encode() checks this first, so that a name
// the format cannot store fails before the work, not at write_pm. Errors:
// kInvalidArgument (a NUL), kResourceLimit (too long, too many).
Status check_material_strings(const std::vector<std::string>& names,
                              const std::vector<std::string>& libraries);

struct ReadOptions {
  // Upper bound in bytes on what decoding may allocate for the mesh (0: no bound beyond
  // the format's own limits). Checked against the header's counts before anything is
  // allocated; a stream that needs more is kResourceLimit.
  //
  // What is counted (pm-format.md §7.1): the decoded ProgressiveMesh, every array at its
  // exact size, plus the larger of the decoding transients (the largest section's raw
  // bytes, the corner-id predictor, the zstd context) and validate()'s, plus 4 KiB. The
  // header and the section headers give every term, so the check comes first.
  uint64_t max_memory = 0;
};

// Parses and validates a whole stream. Errors: kTruncatedStream, kCorruptStream,
// kChecksumMismatch, kUnsupportedVersion, kResourceLimit. Never reads out of bounds.
Status read_pm(std::string_view bytes, ProgressiveMesh& pm, const ReadOptions& options);
Status read_pm(std::string_view bytes, ProgressiveMesh& pm);  // default ReadOptions

// The header fields, for `pmdec --info`.
struct PmInfo {
  uint16_t major = 0, minor = 0;
  uint32_t flags = 0;
  uint32_t base_vertex_count = 0, base_face_count = 0, split_count = 0;
  uint32_t loose_vertex_count = 0, weld_count = 0, carried_face_count = 0;
  uint64_t full_vertex_count = 0, full_face_count = 0;
  float max_error = 0;  // error bound of the base mesh
  // Added with the 1.0 codec. full_vertex_count is what the full-detail mesh outputs:
  // base + splits + loose - welds (welded copies are output as their canonical vertex).
  // full_face_count is base faces + split_face_count + carried faces.
  uint32_t moved_face_count = 0;  // total of the splits' moved faces
  uint32_t split_face_count = 0;  // faces the splits add (1 or 2 each)
  uint32_t section_count = 0;
  // Added with format 1.1 (all zero and false in a 1.0 stream): the attributes, as the
  // header declares them. color_components is 0 (none), 3 (rgb) or 4 (rgba) floats per
  // vertex; the counts are the value tables' entries and the material strings; has_* say
  // whether faces refer to them (ProgressiveMesh::has_uvs() etc. of the decoded mesh).
  uint32_t color_components = 0;
  uint32_t uv_count = 0, normal_count = 0;
  uint32_t material_count = 0, material_library_count = 0;
  bool has_uvs = false, has_normals = false, has_materials = false;
};
// Reads and checks the header only (magic, checksum, version, count limits, and that the
// stream is long enough for the counts); sections are not decompressed. Same errors as read_pm.
Status read_pm_info(std::string_view bytes, PmInfo& info);

}  // namespace pm
