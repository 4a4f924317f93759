// The .pm stream: reader and writer. The byte layout is specified in
// formats/pm-format.md, which is normative; this code follows it.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "pm/progressive_mesh.h"
#include "pm/status.h"

namespace pm {

// The version write_pm writes. read_pm reads it and every 1.x stream (1.0, 1.1).
inline constexpr uint16_t kFormatMajor = 2;
// 2.0: chunked splits, one-ring coding, quantization; 2.1: u, vl, vr and positions range-coded;
// 2.2: the splits' corner attributes range-coded as wedges, new values where first used;
// 2.3: lossless positions that are decimals (as text formats write them) on a decimal grid
// or as numbers of significant decimals; 2.4: those numbers predicted by their values, and new
// texture coordinates through the moved face that holds the new vertex.
inline constexpr uint16_t kFormatMinor = 4;

struct WriteOptions {
  // 1..22. 18 by default: 19 made files no smaller (within 0.03% on the shared meshes) and
  // took a tenth more of pmenc's time (tests/bench/README.md, "Size").
  int zstd_level = 18;
  // Quantization (lossy, by the caller's choice; 0 keeps every float bit): positions on a
  // uniform grid of 2^position_bits steps over the bounding box's longest side, texture
  // coordinates and normals on grids of 2^uv_bits / 2^normal_bits steps over their tables'
  // ranges. Each is 0 or 4..24. The decoded mesh holds the grid points. With position_bits
  // 0, positions that are all decimals (as text formats write them: "0.037830") go on the
  // grid of their decimals (format 2.3), bit for bit, where that grid is coarser than the
  // floats' own steps; positions that are all decimals of a few significant digits ("%g"),
  // as those decimals, likewise; and so are lossless texture-coordinate and normal tables.
  int position_bits = 0;
  int uv_bits = 0;
  int normal_bits = 0;
  // Each split's error (the bound a reader chooses levels by) with this many significant
  // bits, rounded up so that it stays a bound (lossy, by the caller's choice, like the grids
  // above; a level chosen by error can only be finer than with every bit): 0 keeps every
  // bit; 1..24. On a grid, the errors' low bits are far below the grid's step and cost a bit
  // or two per split; pmenc keeps kQuantizedErrorBits (pm/advanced/pm_stream.h) with --quantize.
  int error_bits = 0;
  // The splits are stored in chunks of at most this many (each compressed on its own, with
  // an index, so that a reader decodes only the prefix it needs): the first chunks are
  // smaller (256, 512, ...) so that a stream cut early still refines. 1..2^20.
  uint32_t chunk_splits = 4096;
  // The minor version to write: 4 (2.4, the default), 3 (2.3), 2 (2.2), 1 (2.1) or 0 (2.0), for
  // readers that predate the newer ones (the older are larger).
  uint16_t minor_version = kFormatMinor;
  // Threads compressing the sections (0: the machine's cores). The bytes are the same for
  // any number.
  unsigned threads = 0;
};

// Serializes pm (which must be valid) to bytes, as format 2.4 (or 2.3, 2.2, 2.1, 2.0,
// WriteOptions::minor_version). Errors: kInvalidArgument when validate(pm) fails, a material name
// or library holds a NUL, an option is out of range, or positions to quantize are not finite;
// kResourceLimit when a count exceeds the format's limits (2^30; 2^20 materials and libraries) or a
// string is longer than 4096 bytes. `bytes` is untouched on error.
[[nodiscard]] Status write_pm(const ProgressiveMesh& pm, const WriteOptions& options, std::string& bytes);

// Whether the stream can hold these material names and libraries (§5.9, §7.2: at most 2^20
// of each, each at most 4096 bytes without NUL). encode() checks this first, so that a name
// the format cannot store fails before the work, not at write_pm. Errors:
// kInvalidArgument (a NUL), kResourceLimit (too long, too many).
[[nodiscard]] Status check_material_strings(const std::vector<std::string>& names,
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
  // A 2.x stream cut short (a download in progress, `head -c`) decodes to the finest level
  // it holds whole, when this is set and the cut falls after the base mesh (the header,
  // BASE, WELD, CARY, TABL and INDX sections); ReadResult says so. Otherwise, and for 1.x
  // streams, a cut stream is kTruncatedStream.
  bool allow_truncated = false;
  // Decode only the splits up to this level (2.x streams: the chunks that hold them; the
  // rest of the stream is neither decompressed nor checked beyond its section headers).
  // The mesh may hold more splits (the rest of the last chunk needed), never fewer; without
  // all splits, it has no loose vertices and no stored order (they belong to full detail);
  // with all of them (max_splits at or past the stream's count), it is the whole stream.
  uint64_t max_splits = UINT64_MAX;
};

// What read_pm decoded, when the stream or the request left out a part of it.
struct ReadResult {
  bool truncated = false;    // the stream ended early (allow_truncated)
  // The mesh holds fewer splits than the stream (truncated or max_splits); from a 2.2 stream,
  // its texture-coordinate and normal tables then hold only the entries that had arrived.
  bool partial = false;
  uint32_t chunks_decoded = 0, chunk_count = 0;  // 2.x streams
  std::string warning;       // one line when truncated: where the stream ends
};

// Parses and validates a stream. Errors: kTruncatedStream, kCorruptStream,
// kChecksumMismatch, kUnsupportedVersion, kResourceLimit. Never reads out of bounds.
[[nodiscard]] Status read_pm(std::string_view bytes, ProgressiveMesh& pm, const ReadOptions& options,
               ReadResult* result);
[[nodiscard]] Status read_pm(std::string_view bytes, ProgressiveMesh& pm, const ReadOptions& options);
[[nodiscard]] Status read_pm(std::string_view bytes, ProgressiveMesh& pm);  // default ReadOptions

// Decodes a 2.x stream as it arrives (Hoppe 1996, §3: progressive transmission): feed it
// bytes in order, in pieces of any size; every section that is complete is decoded at
// once, so mesh() refines chunk by chunk. Streams of version 1.x are decoded whole, when
// they have fully arrived.
// Ownership: owns its buffers and the decoded mesh until take() hands the mesh over;
// movable (a moved-from reader may only be destroyed or assigned to), not copyable.
class PmStreamReader {
 public:
  explicit PmStreamReader(const ReadOptions& options = {});
  ~PmStreamReader();
  PmStreamReader(const PmStreamReader&) = delete;
  PmStreamReader& operator=(const PmStreamReader&) = delete;
  PmStreamReader(PmStreamReader&& other) noexcept;
  PmStreamReader& operator=(PmStreamReader&& other) noexcept;

  // The next bytes. An error (damage, a limit) is final: later calls return it again.
  [[nodiscard]] Status append(std::string_view bytes);
  // The end of the stream: kTruncatedStream (with the same message as read_pm) when it
  // ended before it was complete, unless options.allow_truncated and the base mesh arrived.
  [[nodiscard]] Status finish(ReadResult* result = nullptr);

  // Whether the base mesh has been decoded (mesh() is then a valid progressive mesh).
  bool has_base() const;
  // Whether the whole stream has been decoded.
  bool complete() const;
  // The progressive mesh decoded so far: the base mesh and the splits of the complete
  // chunks (valid once has_base()). Faces at its finest level: full_face_count(), below.
  const ProgressiveMesh& mesh() const;
  // Faces of the finest level decoded so far (base + the splits' faces; carried faces
  // included), and of the whole stream (from the header, once it has arrived).
  uint64_t decoded_face_count() const;
  uint64_t stream_face_count() const;

  // Hands the decoded mesh over, without a copy, once finish() has succeeded (what read_pm
  // returns): the reader then holds nothing, mesh() is empty and every later call returns
  // kInvalidArgument. Before a successful finish(): kInvalidArgument (or the reader's error),
  // and `out` is untouched.
  [[nodiscard]] Status take(ProgressiveMesh& out);

 private:
  friend Status read_pm(std::string_view, ProgressiveMesh&, const ReadOptions&, ReadResult*);
  friend Status read_pm_info(std::string_view, struct PmInfo&);
  struct State;
  State* state_;
};

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
  // Added with format 2.0 (zero in 1.x streams): quantization bits (0 = lossless), whether
  // the input's vertex and face order is stored, and the chunk index: for each chunk, its
  // splits, and the vertices, faces and error bound of the level after it.
  uint32_t position_bits = 0, uv_bits = 0, normal_bits = 0;
  bool keeps_order = false;
  // Added with format 2.3: the positions are lossless, on a grid of decimals of
  // position_bits bits (the input's values were decimals, as text formats write them).
  bool positions_decimal = false;
  // Added with format 2.3: the positions are lossless, coded as decimals of a few significant
  // digits (the input's values were such decimals: "0.0832331", "-52.9283").
  bool positions_significant = false;
  // Added with format 2.3: the texture-coordinate (normal) table is lossless, coded as
  // decimals of a few significant digits.
  bool uvs_significant = false, normals_significant = false;
  struct Chunk {
    uint32_t splits = 0;
    uint64_t vertices_after = 0, faces_after = 0;  // as vertices_at_level / faces_at_level
    float error_after = 0;
    uint64_t stream_end = 0;  // byte offset in the stream just past this chunk
  };
  std::vector<Chunk> chunks;
};
// Reads and checks the header (magic, checksum, version, count limits, and that the stream
// is long enough for the counts) and, in a 2.x stream, the chunk index (the sections before
// it are skipped, not decompressed); `bytes` may be a prefix of the stream that holds them.
// Same errors as read_pm.
[[nodiscard]] Status read_pm_info(std::string_view bytes, PmInfo& info);

}  // namespace pm
