// The 2.0 .pm stream (formats/pm-format.md): round trips of literal and encoded progressive
// meshes, chunking, one-ring coding, quantization, decoding as bytes arrive, prefixes
// (truncated streams and max_splits), golden files of every version, adversarial streams.
#include <gtest/gtest.h>
#include <zstd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <memory>
#include <numeric>
#include <set>
#include <string>
#include <thread>
#include <tuple>
#include <type_traits>
#include <vector>

#include "../formats/byte_io.h"
#include "../formats/pm_layout.h"
#include "../formats/range_coder.h"
#include "core/memory_pages.h"
#include "pm/advanced/pm_stream.h"
#include "pm/advanced/stream_order.h"
#include "pm/encoder.h"
#include "pm/lod.h"
#include "pm/mesh_io.h"
#include "pm/pm_codec.h"
#include "pm/progressive_mesh.h"
#include "pm/surface_distance.h"
#include "pm_literals.h"
#include "sorted_moves.h"
#include "test_util.h"

namespace pm {
namespace {

using namespace literals;  // NOLINT

using test::with_sorted_moves;

std::string write(const ProgressiveMesh& pm, WriteOptions options = {}) {
  options.zstd_level = 3;
  std::string bytes;
  const Status status = write_pm(pm, options, bytes);
  EXPECT_TRUE(status.is_ok()) << status.message();
  return bytes;
}

ProgressiveMesh read(const std::string& bytes, ReadOptions options = {}, ReadResult* result = nullptr) {
  ProgressiveMesh pm;
  const Status status = read_pm(bytes, pm, options, result);
  EXPECT_TRUE(status.is_ok()) << status.message();
  return pm;
}

void expect_round_trip(const ProgressiveMesh& pm, const WriteOptions& options = {}) {
  const std::string bytes = write(pm, options);
  ASSERT_GE(bytes.size(), 12u);
  EXPECT_EQ(static_cast<uint8_t>(bytes[8]), 2);  // major 2
  expect_identical(with_sorted_moves(read(bytes)), with_sorted_moves(pm));
}

std::vector<ProgressiveMesh> literal_meshes() {
  return {ProgressiveMesh{}, triangle_mesh(), small_mesh(), attributed_mesh(),
          generated_mesh(300), with_attributes(generated_mesh(700)), with_attributes(small_mesh())};
}

ProgressiveMesh encoded(const std::string& path) {
  Mesh mesh;
  EXPECT_TRUE(read_mesh(path, mesh).is_ok()) << path;
  ProgressiveMesh pm;
  EncodeOptions options;
  const Status status = encode(mesh, options, pm);
  EXPECT_TRUE(status.is_ok()) << status.message();
  return pm;
}

// Meshes the encoder made: every sample, and with ../shared/meshes, spot (UV seams) and
// fandisk (sharp features).
std::vector<ProgressiveMesh> encoded_meshes() {
  std::vector<ProgressiveMesh> meshes;
  for (const std::string& path : test::sample_mesh_paths()) meshes.push_back(encoded(path));
  if (test::shared_meshes_available()) {
    for (const char* name : {"spot.obj", "fandisk.obj"}) meshes.push_back(encoded(test::shared_mesh_path(name)));
  } else {
    test::warn_no_shared_meshes();
  }
  return meshes;
}

// ---------------------------------------------------------------------------------------

TEST(PmStream, LiteralMeshesRoundTripWithEveryChunkSize) {
  for (const ProgressiveMesh& pm : literal_meshes()) {
    for (uint32_t chunk : {1u, 7u, 4096u}) {
      for (uint16_t minor : {0, 1, 2}) {
        SCOPED_TRACE("splits " + std::to_string(pm.splits.size()) + ", chunks of " +
                     std::to_string(chunk) + ", 2." + std::to_string(minor));
        WriteOptions options;
        options.chunk_splits = chunk;
        options.minor_version = minor;
        expect_round_trip(pm, options);
      }
    }
  }
}

TEST(PmStream, EncodedMeshesRoundTripAndAreSmallerThanFormat1) {
  for (const ProgressiveMesh& pm : encoded_meshes()) {
    SCOPED_TRACE("splits " + std::to_string(pm.splits.size()));
    expect_round_trip(pm);
    for (int bits : {0, 14}) {  // 2.0 too, lossless and quantized
      WriteOptions options;
      options.minor_version = 0;
      options.position_bits = bits;
      const std::string bytes = write(pm, options);
      EXPECT_EQ(static_cast<uint8_t>(bytes[10]), 0);
      if (bits == 0) expect_identical(with_sorted_moves(read(bytes)), with_sorted_moves(pm));
      options.minor_version = 1;
      const ProgressiveMesh v21 = read(write(pm, options)), v20 = read(bytes);
      EXPECT_EQ(bits_of(v21.positions), bits_of(v20.positions));  // the same grid values
    }
    // The one-ring coding leaves out the moved faces and the global ids of vl and vr, and
    // the positions are residuals: a 2.0 stream is much smaller than a 1.1 stream.
    std::string v1, v2;
    ASSERT_TRUE(detail::write_pm_v1(pm, 19, v1).is_ok());
    WriteOptions options;
    ASSERT_TRUE(write_pm(pm, options, v2).is_ok());
    // Attribute tables and the splits' corner codes are stored as in 1.1 (zstd, no model of
    // their own yet: issue 5), so the gain shows on the geometry. Where they are most of the
    // stream (samples/textured.obj: TABL 10 kB, the chunks 37 kB of 48 kB), the two sizes
    // are within a few per mille, and which is smaller depends on the order of the
    // collapses (zstd finds more or less to share in 1.1's global ids): 2.0 went from 0.5%
    // smaller to 0.8% larger with issue 10's tie order, 2.1 is 1.006 times 1.1 with the seam
    // drift's. Within 2% is what is checked there.
    const bool geometry_only = !pm.has_uvs() && !pm.has_normals();
    if (pm.splits.size() > 1000) {
      EXPECT_LT(v2.size(), geometry_only ? v1.size() * 6 / 10 : v1.size() * 102 / 100)
          << v2.size() << " vs " << v1.size();
    }
  }
}

TEST(PmStream, ChunksFollowThePlanAndTheIndexDescribesThem) {
  const ProgressiveMesh pm = generated_mesh(3000);
  WriteOptions options;
  options.chunk_splits = 1024;
  const std::string bytes = write(pm, options);
  PmInfo info;
  ASSERT_TRUE(read_pm_info(bytes, info).is_ok());
  EXPECT_EQ(info.major, 2);
  // 256, 512, then 1024 until the end.
  std::vector<uint32_t> sizes;
  for (const PmInfo::Chunk& chunk : info.chunks) sizes.push_back(chunk.splits);
  EXPECT_EQ(sizes, (std::vector<uint32_t>{256, 512, 1024, 1024, 184}));
  uint32_t level = 0;
  uint64_t previous_end = 0;
  for (const PmInfo::Chunk& chunk : info.chunks) {
    level += chunk.splits;
    EXPECT_EQ(chunk.faces_after, faces_at_level(pm, level));
    EXPECT_EQ(chunk.vertices_after, vertices_at_level(pm, level));
    EXPECT_EQ(chunk.error_after, error_at_level(pm, level));
    EXPECT_GT(chunk.stream_end, previous_end);
    previous_end = chunk.stream_end;
  }
  // Nothing follows the last chunk here (no loose vertices).
  EXPECT_EQ(info.chunks.back().stream_end, bytes.size());
}

TEST(PmStream, QuantizedPositionsLieOnTheGridWithinHalfAStep) {
  for (const ProgressiveMesh& pm : encoded_meshes()) {
    for (int bits : {4, 11, 14, 24}) {
      SCOPED_TRACE(std::to_string(bits) + " bits");
      WriteOptions options;
      options.position_bits = bits;
      options.uv_bits = bits;
      options.normal_bits = bits;
      const std::string bytes = write(pm, options);
      ProgressiveMesh q = read(bytes);
      // Connectivity and ids are untouched; values move by at most half a step.
      ProgressiveMesh expected = pm;
      const auto within = [&](const std::vector<float>& a, const std::vector<float>& b, std::size_t components) {
        ASSERT_EQ(a.size(), b.size());
        float extent = 0;  // the grid spans the bounding box's longest side
        for (std::size_t c = 0; c < components; ++c) {
          float lo = INFINITY, hi = -INFINITY;
          for (std::size_t i = c; i < a.size(); i += components) lo = std::min(lo, a[i]), hi = std::max(hi, a[i]);
          if (!a.empty()) extent = std::max(extent, hi - lo);
        }
        const double step = extent / double((1u << bits) - 1);
        for (std::size_t i = 0; i < a.size(); ++i) {
          ASSERT_LE(std::abs(double(a[i]) - double(b[i])), 0.5 * step * 1.0001 + 1e-7 * std::abs(a[i])) << i;
        }
      };
      within(pm.positions, q.positions, 3);
      within(pm.uvs, q.uvs, 2);
      within(pm.normals, q.normals, 3);
      expected.positions = q.positions;
      expected.uvs = q.uvs;
      expected.normals = q.normals;
      expect_identical(with_sorted_moves(q), with_sorted_moves(expected));
      // Quantizing again changes nothing: the values are grid points.
      expect_identical(read(write(q, options)), q);
      PmInfo info;
      ASSERT_TRUE(read_pm_info(bytes, info).is_ok());
      EXPECT_EQ(info.position_bits, uint32_t(bits));
    }
  }
}

TEST(PmStream, ErrorBitsRoundEachErrorUpAndKeepTheRest) {
  // Literal errors: 1.03 and 0.3 round up to 1 + 1/16 and 1.25 / 4 with 5 significant bits;
  // 1, a power of two, and 0.75 (1.5 / 2) have fewer and stay.
  ProgressiveMesh pm = generated_mesh(6);
  const float errors[] = {1.03f, 1.0f, 0.75f, 0.3f, 0.3f, 0.0f};
  for (std::size_t i = 0; i < pm.splits.size(); ++i) pm.splits[i].error = errors[i];
  WriteOptions options;
  options.error_bits = 5;
  ProgressiveMesh rounded = read(write(pm, options));
  const std::vector<float> expected = {1.0625f, 1.0f, 0.75f, 0.3125f, 0.3125f, 0.0f};
  std::vector<float> got;
  for (const VertexSplit& split : rounded.splits) got.push_back(split.error);
  EXPECT_EQ(got, expected);
  // Everything else is the stream without rounding.
  ProgressiveMesh exact = read(write(pm));
  for (std::size_t i = 0; i < pm.splits.size(); ++i) exact.splits[i].error = expected[i];
  expect_identical(with_sorted_moves(rounded), with_sorted_moves(exact));

  // Over many chunks: each error at least the exact one, at most 1/16 above it, with 5
  // significant bits; the header's and the index's errors are the splits' own.
  const ProgressiveMesh many = generated_mesh(3000);
  options.chunk_splits = 1024;
  const std::string bytes = write(many, options);
  const ProgressiveMesh decoded = read(bytes);
  ASSERT_EQ(decoded.splits.size(), many.splits.size());
  int changed = 0;
  for (std::size_t i = 0; i < many.splits.size(); ++i) {
    const float e = many.splits[i].error, r = decoded.splits[i].error;
    ASSERT_GE(r, e) << i;
    ASSERT_LE(r, e * (1.0f + 1.0f / 16)) << i;
    ASSERT_LE(test::significant_bits(r), 5) << i << ": " << r;
    changed += r != e;
  }
  EXPECT_GT(changed, 2900);
  PmInfo info;
  ASSERT_TRUE(read_pm_info(bytes, info).is_ok());
  EXPECT_EQ(info.max_error, decoded.splits[0].error);
  uint32_t level = 0;
  for (const PmInfo::Chunk& chunk : info.chunks) {
    level += chunk.splits;
    EXPECT_EQ(chunk.error_after, error_at_level(decoded, level));
  }
  // Fewer bits, fewer bytes: the errors stream is most of what changes.
  WriteOptions every_bit = options;
  every_bit.error_bits = 0;
  EXPECT_LT(bytes.size(), write(many, every_bit).size());
  // 24 bits are every bit, as 0 is; out of range is refused.
  options.error_bits = 24;
  EXPECT_EQ(write(many, options), write(many, every_bit));
  expect_identical(with_sorted_moves(read(write(many, options))), with_sorted_moves(many));
  std::string out;
  for (int bits : {-1, 25}) {
    options.error_bits = bits;
    EXPECT_EQ(write_pm(many, options, out).code(), ErrorCode::kInvalidArgument) << bits;
  }
}

TEST(PmStream, LooseVerticesWithoutABaseMesh) {
  ProgressiveMesh pm;
  pm.loose_vertex_count = 2;
  pm.positions = {1, 2, 3, -4, 5.5f, 6};
  for (int bits : {0, 8}) {
    WriteOptions options;
    options.position_bits = bits;
    const ProgressiveMesh decoded = read(write(pm, options));
    EXPECT_EQ(decoded.loose_vertex_count, 2u);
    if (bits == 0) expect_identical(decoded, pm);
    ASSERT_EQ(decoded.positions.size(), 6u);
    EXPECT_NEAR(decoded.positions[4], 5.5f, 0.05f);
  }
}

TEST(PmStream, QuantizingNonFiniteValuesIsRefused) {
  ProgressiveMesh pm = small_mesh();
  pm.positions[7] = std::numeric_limits<float>::infinity();
  WriteOptions options;
  options.position_bits = 12;
  std::string bytes;
  EXPECT_EQ(write_pm(pm, options, bytes).code(), ErrorCode::kInvalidArgument);
  options.position_bits = 0;
  EXPECT_TRUE(write_pm(pm, options, bytes).is_ok());  // lossless keeps any bits
  for (int bits : {-1, 1, 3, 25, 32}) {
    options.position_bits = bits;
    EXPECT_EQ(write_pm(pm, options, bytes).code(), ErrorCode::kInvalidArgument) << bits;
  }
}

TEST(PmStream, PiecesOfAnySizeDecodeAsTheWhole) {
  for (const ProgressiveMesh& pm : {with_attributes(generated_mesh(900)), attributed_mesh()}) {
    WriteOptions options;
    options.chunk_splits = 64;
    const std::string bytes = write(pm, options);
    const ProgressiveMesh whole = read(bytes);
    uint64_t state = 12345;
    for (int round = 0; round < 3; ++round) {
      PmStreamReader reader;
      std::size_t offset = 0;
      uint64_t faces = 0;
      std::size_t splits = 0;
      while (offset < bytes.size()) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        const std::size_t piece = round == 0 ? 1 : 1 + (state >> 33) % (round == 1 ? 50 : 5000);
        ASSERT_TRUE(reader.append(std::string_view(bytes).substr(offset, piece)).is_ok());
        offset += piece;
        // Every state is a valid progressive mesh, refined further than the last.
        if (reader.has_base()) {
          ASSERT_TRUE(test::ok(validate(reader.mesh())));
          EXPECT_GE(reader.decoded_face_count(), faces);
          EXPECT_GE(reader.mesh().splits.size(), splits);
          EXPECT_EQ(reader.decoded_face_count(), faces_at_level(reader.mesh(), reader.mesh().splits.size()));
          faces = reader.decoded_face_count();
          splits = reader.mesh().splits.size();
        }
      }
      ASSERT_TRUE(reader.finish().is_ok());
      EXPECT_TRUE(reader.complete());
      expect_identical(reader.mesh(), whole);
    }
  }
}

// A cut anywhere after the base mesh gives the finest level whose chunks arrived whole; a
// cut before it is an error; without allow_truncated every cut is an error.
TEST(PmStream, EveryCutGivesAValidCoarserMeshOrACleanError) {
  std::vector<ProgressiveMesh> meshes = encoded_meshes();
  meshes.push_back(with_attributes(generated_mesh(2000)));  // not a surface: no topology to keep
  for (const ProgressiveMesh& pm : meshes) {
    const bool surface = &pm != &meshes.back();
    WriteOptions options;
    options.chunk_splits = 300;
    const std::string bytes = write(pm, options);
    PmInfo info;
    ASSERT_TRUE(read_pm_info(bytes, info).is_ok());
    const Mesh full = extract_level(pm, pm.splits.size());
    const test::TopologySummary input_topology = test::summarize_topology(full);
    int decoded = 0, refused = 0;
    for (int k = 0; k < 100; ++k) {
      const std::size_t cut = bytes.size() * k / 100 + (k * 7919) % 13;
      if (cut >= bytes.size()) continue;
      const std::string prefix = bytes.substr(0, cut);
      ProgressiveMesh strict;
      EXPECT_EQ(read_pm(prefix, strict).code(), ErrorCode::kTruncatedStream) << cut;
      ReadOptions lenient;
      lenient.allow_truncated = true;
      ProgressiveMesh prefix_pm;
      ReadResult result;
      const Status status = read_pm(prefix, prefix_pm, lenient, &result);
      if (!status) {
        EXPECT_EQ(status.code(), ErrorCode::kTruncatedStream) << status.message();
        // Only a cut before the first chunk is complete is refused.
        EXPECT_LT(cut, info.chunks.front().stream_end);
        EXPECT_NE(status.message().find("truncated in"), std::string::npos);
        ++refused;
        continue;
      }
      ++decoded;
      EXPECT_TRUE(result.truncated);
      EXPECT_FALSE(result.warning.empty());
      // Whole chunks only: the splits are a prefix of the full sequence, at a chunk's end.
      const std::size_t n = prefix_pm.splits.size();
      uint64_t boundary = 0;
      bool at_boundary = n == 0;
      for (const PmInfo::Chunk& chunk : info.chunks) {
        boundary += chunk.splits;
        at_boundary = at_boundary || boundary == n;
      }
      EXPECT_TRUE(at_boundary) << n;
      ASSERT_LE(n, pm.splits.size());
      for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(prefix_pm.splits[i].u, pm.splits[i].u);
      // Its finest level is the full sequence's level n, and keeps the input's topology.
      const Mesh level = extract_level(prefix_pm, n);
      EXPECT_EQ(test::canonical_faces(level), test::canonical_faces(extract_level(pm, n)));
      if (surface) {
        EXPECT_TRUE(test::keeps_topology(input_topology, test::summarize_topology(level)));
      }
    }
    EXPECT_GT(decoded, 0);
    EXPECT_GT(refused, 0);   // the header is cut at offset 0
  }
}

TEST(PmStream, MaxSplitsDecodesOnlyTheChunksNeeded) {
  const ProgressiveMesh pm = with_attributes(generated_mesh(3000));
  WriteOptions options;
  options.chunk_splits = 512;
  const std::string bytes = write(pm, options);
  const ProgressiveMesh whole = read(bytes);
  for (uint64_t wanted : {0ull, 1ull, 256ull, 257ull, 2000ull, 3000ull}) {
    ReadOptions read_options;
    read_options.max_splits = wanted;
    ReadResult result;
    const ProgressiveMesh part = read(bytes, read_options, &result);
    // The chunk ends: 256, 768, 1280, 1792, 2304, 2816, 3000.
    const std::vector<uint64_t> ends = {0, 256, 768, 1280, 1792, 2304, 2816, 3000};
    const uint64_t expected = *std::lower_bound(ends.begin(), ends.end(), wanted);
    EXPECT_EQ(part.splits.size(), expected) << wanted;
    EXPECT_EQ(result.partial, expected < 3000);
    EXPECT_FALSE(result.truncated);
    EXPECT_EQ(extract_level(part, part.splits.size()).face_count(),
              extract_level(whole, part.splits.size()).face_count());
    // A damaged chunk after the ones needed is not even decompressed.
    if (expected < 3000) {
      std::string damaged = bytes;
      damaged[bytes.size() - 30] ^= 0x55;
      ProgressiveMesh again;
      EXPECT_TRUE(read_pm(damaged, again, read_options).is_ok());
    }
  }
}

// A reader asked for every split (pmdec --ratio 1, --faces N at or past the full count)
// reads what follows the last chunk too: full detail keeps the vertices no face uses, as a
// reader without a limit does. (It used to stop after the last chunk and drop them.)
TEST(PmStream, MaxSplitsOfEverySplitKeepsTheLooseVertices) {
  WriteOptions options;
  options.chunk_splits = 1;  // two chunks, one split each
  const std::string bytes = write(small_mesh(), options);
  const ProgressiveMesh whole = read(bytes);
  ASSERT_EQ(whole.loose_vertex_count, 2u);
  const Mesh full = extract_level(whole, 2);
  // 9 vertices, less the welded copy of 1; the loose ones (7, 8) last.
  ASSERT_EQ(full.vertex_count(), 8u);
  EXPECT_EQ(std::vector<float>(full.positions.end() - 6, full.positions.end()),
            (std::vector<float>{3.0f, 3.0f, 3.0f, -3.0f, 1e-30f, 1e30f}));
  for (uint64_t wanted : {2ull, 3ull}) {
    ReadOptions read_options;
    read_options.max_splits = wanted;
    ReadResult result;
    const ProgressiveMesh part = read(bytes, read_options, &result);
    EXPECT_FALSE(result.partial) << wanted;
    EXPECT_EQ(part.loose_vertex_count, 2u) << wanted;
    const Mesh level = extract_level(part, level_for_faces(part, full.face_count()));
    EXPECT_EQ(level.positions, full.positions) << wanted;
    EXPECT_EQ(level.triangles, full.triangles) << wanted;
  }
  // One split short of the end: a level below full detail, without them, as before.
  ReadOptions first_chunk;
  first_chunk.max_splits = 1;
  ReadResult result;
  const ProgressiveMesh part = read(bytes, first_chunk, &result);
  EXPECT_TRUE(result.partial);
  EXPECT_EQ(part.splits.size(), 1u);
  EXPECT_EQ(extract_level(part, 1).vertex_count(), 5u);  // 0-3 and 5 (4, a copy of 1, merged)
}

// Every face asked for is full detail, even past a last split that adds no face; fewer
// faces give the first level that has them, as before.
TEST(PmStream, LevelForEveryFaceIsFullDetail) {
  ProgressiveMesh pm = small_mesh();
  VertexSplit faceless;  // only the level functions read it: no face moves, none appended
  faceless.u = 6;
  faceless.vl = faceless.vr = kNoVertex;
  faceless.moved_begin = 2;
  pm.splits.push_back(faceless);
  ASSERT_EQ(faces_at_level(pm, 3), 8u);  // 4 base + 1 carried, then 2 and 1 appended
  EXPECT_EQ(level_for_faces(pm, 8), 3u);
  EXPECT_EQ(level_for_faces(pm, 9), 3u);
  EXPECT_EQ(level_for_faces(pm, 7), 1u);
  EXPECT_EQ(level_for_faces(pm, 6), 1u);
  EXPECT_EQ(level_for_faces(pm, 5), 0u);
}

TEST(PmStream, EveryByteFlipIsAnErrorOrHarmless) {
  const std::string bytes = write(attributed_mesh());
  const ProgressiveMesh original = read(bytes);
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    for (uint8_t mask : {0x01, 0x80, 0xFF}) {
      std::string damaged = bytes;
      damaged[i] = static_cast<char>(damaged[i] ^ mask);
      ProgressiveMesh pm;
      const Status status = read_pm(damaged, pm);
      if (status.is_ok()) {
        expect_identical(pm, original);  // a bit zstd does not use
      } else {
        EXPECT_FALSE(status.message().empty());
      }
    }
  }
}

TEST(PmStream, TrailingBytesUnknownSectionsAndReservedFields) {
  const std::string bytes = write(small_mesh());
  ProgressiveMesh pm;
  EXPECT_EQ(read_pm(bytes + "x", pm).code(), ErrorCode::kCorruptStream);
  // An optional section of another tool is skipped; a required one is refused.
  for (uint32_t flags : {0u, 1u}) {
    std::string extra;
    ASSERT_TRUE(detail::append_section(detail::make_tag("XTRA"), flags, "hello", 5, 3, extra).is_ok());
    const Status status = read_pm(bytes + extra, pm);
    EXPECT_EQ(status.code(), flags == 0 ? ErrorCode::kOk : ErrorCode::kCorruptStream) << status.message();
  }
  // Header fields a 2.0 reader must refuse, each with its CRC made good again.
  const auto with_header_byte = [&](std::size_t offset, uint8_t value) {
    std::string damaged = bytes;
    damaged[offset] = static_cast<char>(value);
    const uint32_t crc = detail::crc32(std::string_view(damaged).substr(0, 92));
    for (int k = 0; k < 4; ++k) damaged[92 + k] = static_cast<char>(crc >> (8 * k));
    ProgressiveMesh out;
    return read_pm(damaged, out).code();
  };
  EXPECT_EQ(with_header_byte(12, 1), ErrorCode::kCorruptStream);  // flags
  EXPECT_EQ(with_header_byte(87, 1), ErrorCode::kCorruptStream);  // reserved byte
  EXPECT_EQ(with_header_byte(88, 8), ErrorCode::kCorruptStream);  // an unknown option
  EXPECT_EQ(with_header_byte(84, 3), ErrorCode::kCorruptStream);  // 3 position bits
  // small_mesh()'s positions are significant decimals (2.3, options bit 2): not in a 2.2 stream.
  ASSERT_EQ(static_cast<uint8_t>(bytes[88]), 4);
  EXPECT_EQ(with_header_byte(10, 2), ErrorCode::kCorruptStream);
  EXPECT_EQ(with_header_byte(8, 3), ErrorCode::kUnsupportedVersion);  // major 3
}

// The stream with the first CHNK's stream `k` (§5.7) replaced by `replacement`.
std::string with_chunk_stream(const std::string& bytes, int k, const std::string& replacement) {
  std::size_t offset = 96;
  while (offset + 24 <= bytes.size()) {
    uint64_t stored = 0, raw_size = 0;
    for (int b = 0; b < 8; ++b) stored |= uint64_t{static_cast<uint8_t>(bytes[offset + 8 + b])} << (8 * b);
    for (int b = 0; b < 8; ++b) raw_size |= uint64_t{static_cast<uint8_t>(bytes[offset + 16 + b])} << (8 * b);
    if (bytes.compare(offset, 4, "CHNK") == 0) {
      std::string raw(raw_size, '\0');
      EXPECT_EQ(ZSTD_decompress(raw.data(), raw.size(), bytes.data() + offset + 24, stored), raw_size);
      // Ten varint64 lengths, then the streams.
      std::vector<uint64_t> lengths(10);
      std::size_t at = 0;
      for (uint64_t& length : lengths) {
        for (int shift = 0;; shift += 7) {
          const auto byte = static_cast<uint8_t>(raw[at++]);
          length |= uint64_t{byte & 0x7Fu} << shift;
          if ((byte & 0x80) == 0) break;
        }
      }
      std::vector<std::string> streams;
      for (uint64_t length : lengths) {
        streams.push_back(raw.substr(at, length));
        at += length;
      }
      streams[k] = replacement;
      std::string rebuilt;
      for (const std::string& stream : streams) {
        for (uint64_t v = stream.size(); ; v >>= 7) {
          rebuilt.push_back(static_cast<char>((v & 0x7F) | (v >= 0x80 ? 0x80 : 0)));
          if (v < 0x80) break;
        }
      }
      for (const std::string& stream : streams) rebuilt += stream;
      std::string section;
      EXPECT_TRUE(detail::append_section(detail::make_tag("CHNK"), 1, rebuilt, rebuilt.size(), 3, section).is_ok());
      return bytes.substr(0, offset) + section + bytes.substr(offset + 24 + stored);
    }
    offset += 24 + stored;
  }
  ADD_FAILURE() << "no CHNK";
  return bytes;
}

// Residuals at the edge of 64 bits, planes with a spare top byte: clean errors, no overflow.
TEST(PmStream, HostileResidualsAndPlanesAreRefused) {
  WriteOptions v20;
  v20.minor_version = 0;
  const std::string bytes = write(small_mesh(), v20);  // chunk 0: 2 splits, 6 position codes
  ProgressiveMesh pm;
  // The stream rebuilt unchanged still decodes (the surgery itself is sound).
  {
    std::string same = with_chunk_stream(bytes, 9, "");
    EXPECT_TRUE(read_pm(same, pm).is_ok());
  }
  const std::string huge = std::string(1, '\x08') + std::string(8 * 6, '\xFF');
  EXPECT_EQ(read_pm(with_chunk_stream(bytes, 5, huge), pm).code(), ErrorCode::kCorruptStream);
  std::string just_over = std::string(1, '\x05') + std::string(5 * 6, '\0');
  for (int i = 0; i < 6; ++i) just_over[1 + 4 * 6 + i] = 0x03;  // codes of 3 * 2^32: beyond
  EXPECT_EQ(read_pm(with_chunk_stream(bytes, 5, just_over), pm).code(), ErrorCode::kCorruptStream);
  std::string spare = std::string(1, '\x02') + std::string(2 * 6, '\0');  // top plane all zero
  EXPECT_EQ(read_pm(with_chunk_stream(bytes, 5, spare), pm).code(), ErrorCode::kCorruptStream);
  // Errors: a code beyond any difference of two floats' bits.
  EXPECT_EQ(read_pm(with_chunk_stream(bytes, 4, "\xff\xff\xff\xff\xff\xff\xff\xff\xff\x01\x00"), pm).code(),
            ErrorCode::kCorruptStream);
}

// 2.1's range codes (§5.10): every damaged, cut, lengthened or out-of-range code is a clean
// kCorruptStream (or, where the damage still decodes to a valid mesh, harmless).
TEST(PmStream, HostileRangeCodesAreRefused) {
  WriteOptions quantized;
  quantized.position_bits = 12;  // with the normal coordinate's prediction
  for (const std::string& bytes :
       {write(with_attributes(generated_mesh(600))), write(generated_mesh(600), quantized)}) {
    ProgressiveMesh pm;
    for (int k : {0, 1, 2, 5, 8, 9}) {  // u, vl, vr, positions, 2.2's corner ids
      if (k >= 8 && bytes == write(generated_mesh(600), quantized)) continue;  // no attributes
      SCOPED_TRACE("stream " + std::to_string(k));
      EXPECT_EQ(read_pm(with_chunk_stream(bytes, k, ""), pm).code(), ErrorCode::kCorruptStream);
      EXPECT_EQ(read_pm(with_chunk_stream(bytes, k, std::string(5, '\0')), pm).code(),
                ErrorCode::kCorruptStream);
      EXPECT_EQ(read_pm(with_chunk_stream(bytes, k, "\x01" + std::string(40, '\0')), pm).code(),
                ErrorCode::kCorruptStream);  // first byte not 0
      EXPECT_EQ(
          read_pm(with_chunk_stream(bytes, k, std::string(1, '\0') + std::string(4, '\xFF')), pm)
              .code(),
          ErrorCode::kCorruptStream);  // code = range
      // All ones: endless exp-Golomb prefixes, u beyond v, ring codes beyond the ring.
      EXPECT_EQ(
          read_pm(with_chunk_stream(bytes, k, std::string(1, '\0') + std::string(4000, '\xFE')), pm)
              .code(),
          ErrorCode::kCorruptStream);
      // Random bytes: never a crash; an error, or (rarely) a valid mesh.
      uint32_t seed = 12345u + static_cast<uint32_t>(k);
      for (int trial = 0; trial < 200; ++trial) {
        std::string noise(1 + trial % 300, '\0');
        for (std::size_t b = 1; b < noise.size(); ++b) {
          seed = seed * 1664525u + 1013904223u;
          noise[b] = static_cast<char>(seed >> 24);
        }
        const Status status = read_pm(with_chunk_stream(bytes, k, noise), pm);
        EXPECT_TRUE(status.is_ok() || status.code() == ErrorCode::kCorruptStream)
            << status.message();
      }
    }
  }
}

// order_attribute_tables: the tables in the order of first use along the corners (base,
// carried, then split by split its moved corners and new faces' corners), unused entries
// last; every level's corners keep their values. A progressive mesh that keeps the input's
// order is left alone.
TEST(PmStream, AttributeTablesInFirstUseOrderKeepEveryCornersValue) {
  ProgressiveMesh pm = with_attributes(generated_mesh(300));
  // Two entries no corner uses, first: they go last.
  pm.uvs.insert(pm.uvs.begin(), {9.0f, 9.5f, 8.0f, 8.5f});
  for (std::vector<uint32_t>* ids : {&pm.face_uvs, &pm.moved_uvs}) {
    for (uint32_t& id : *ids) id = id == kNoAttribute ? id : id + 2;
  }
  ProgressiveMesh ordered = pm;
  order_attribute_tables(ordered);
  ASSERT_TRUE(test::ok(validate(ordered)));
  EXPECT_NE(ordered.face_uvs, pm.face_uvs);  // the literal's ids are not in that order
  for (const std::size_t level : {std::size_t{0}, pm.splits.size() / 2, pm.splits.size()}) {
    SCOPED_TRACE("level " + std::to_string(level));
    const Mesh before = extract_level(pm, level), after = extract_level(ordered, level);
    ASSERT_EQ(after.triangles, before.triangles);
    ASSERT_EQ(after.uv_indices.size(), before.uv_indices.size());
    ASSERT_EQ(after.normal_indices.size(), before.normal_indices.size());
    for (std::size_t c = 0; c < before.uv_indices.size(); ++c) {
      ASSERT_EQ(before.uv_indices[c] == kNoAttribute, after.uv_indices[c] == kNoAttribute);
      if (before.uv_indices[c] == kNoAttribute) continue;
      for (int k = 0; k < 2; ++k)
        EXPECT_EQ(after.uvs[2 * after.uv_indices[c] + k], before.uvs[2 * before.uv_indices[c] + k]);
    }
    for (std::size_t c = 0; c < before.normal_indices.size(); ++c) {
      ASSERT_EQ(before.normal_indices[c] == kNoAttribute, after.normal_indices[c] == kNoAttribute);
      if (before.normal_indices[c] == kNoAttribute) continue;
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(after.normals[3 * after.normal_indices[c] + k],
                  before.normals[3 * before.normal_indices[c] + k]);
      }
    }
  }
  // First use in corner order: each new id is the next one.
  std::vector<uint32_t> order(ordered.face_uvs.begin(), ordered.face_uvs.begin() + ordered.base_faces.size());
  order.insert(order.end(), ordered.face_uvs.end() - ordered.carried_faces.size(), ordered.face_uvs.end());
  std::size_t next_corner = ordered.base_faces.size();
  for (const VertexSplit& split : ordered.splits) {
    order.insert(order.end(), ordered.moved_uvs.begin() + split.moved_begin,
                 ordered.moved_uvs.begin() + split.moved_begin + split.moved_count);
    for (uint32_t k = 0; k < 3 * split.new_face_count(); ++k) order.push_back(ordered.face_uvs[next_corner++]);
  }
  uint32_t met = 0;
  std::set<uint32_t> seen;
  for (uint32_t id : order) {
    if (id == kNoAttribute || seen.count(id) != 0) continue;
    EXPECT_EQ(id, met);
    seen.insert(id);
    ++met;
  }
  ASSERT_EQ(met + 2, ordered.uv_count());
  EXPECT_EQ(std::vector<float>(ordered.uvs.end() - 4, ordered.uvs.end()),
            (std::vector<float>{9.0f, 9.5f, 8.0f, 8.5f}));
  // Keeping the input's order keeps the tables'.
  ProgressiveMesh kept = attributed_mesh();
  kept.input_vertices = {0, 1, 2, 3, 5, 6, 7, 8};
  kept.input_faces = {21, 19, 17, 12, 9, 6, 3, 2};
  ProgressiveMesh kept_ordered = kept;
  order_attribute_tables(kept_ordered);
  expect_identical(kept_ordered, kept);
}

// 2.2 (§5.11): with the tables in the order the stream meets their entries, a corner that
// introduces an entry names it for almost nothing and its value is predicted from its face,
// so the stream is much smaller than 2.1's, which decodes to the same mesh. Tables in any
// other order still round-trip (an entry is named by its rank among those not met yet).
TEST(PmStream, Version22CodesAttributesInFirstUseOrderCompactly) {
  std::vector<std::pair<std::string, Mesh>> inputs = {{"seamed grid", test::seamed_grid(24)}};
  if (test::shared_meshes_available()) {
    Mesh spot;
    ASSERT_TRUE(read_mesh(test::shared_mesh_path("spot.obj"), spot).is_ok());
    inputs.emplace_back("spot", std::move(spot));
  } else {
    test::warn_no_shared_meshes();
  }
  for (const auto& [name, input] : inputs) {
    SCOPED_TRACE(name);
    ProgressiveMesh pm;
    ASSERT_TRUE(encode(input, EncodeOptions{}, pm).is_ok());
    ASSERT_TRUE(pm.has_uvs());
    for (const int uv_bits : {0, 10}) {
      SCOPED_TRACE("uv bits " + std::to_string(uv_bits));
      WriteOptions options;
      options.position_bits = 14;
      options.uv_bits = uv_bits;
      options.normal_bits = uv_bits == 0 ? 0 : 8;
      options.minor_version = 2;
      const std::string v22 = write(pm, options);
      EXPECT_EQ(static_cast<uint8_t>(v22[10]), 2);  // minor 2
      options.minor_version = 1;
      const std::string v21 = write(pm, options);
      expect_identical(with_sorted_moves(read(v22)), with_sorted_moves(read(v21)));
      // Measured: the seamed grid 0.86 (lossless) and 0.69; spot 0.73 and 0.51.
      const double bound = name == "spot" ? (uv_bits == 0 ? 0.8 : 0.6) : (uv_bits == 0 ? 0.9 : 0.75);
      EXPECT_LT(double(v22.size()), bound * double(v21.size())) << v22.size() << " against " << v21.size();
      std::printf("%s, uv bits %d: 2.2 %zu bytes, 2.1 %zu\n", name.c_str(), uv_bits, v22.size(), v21.size());
      // The tables reversed: the same mesh, in more bytes.
      ProgressiveMesh reversed = pm;
      const auto reverse = [](std::vector<float>& table, std::vector<uint32_t>& face_ids,
                              std::vector<uint32_t>& moved_ids, std::size_t components) {
        const auto count = static_cast<uint32_t>(table.size() / components);
        std::vector<float> values(table.size());
        for (uint32_t id = 0; id < count; ++id) {
          for (std::size_t c = 0; c < components; ++c)
            values[components * (count - 1 - id) + c] = table[components * id + c];
        }
        table = values;
        for (std::vector<uint32_t>* ids : {&face_ids, &moved_ids}) {
          for (uint32_t& id : *ids) id = id == kNoAttribute ? id : count - 1 - id;
        }
      };
      reverse(reversed.uvs, reversed.face_uvs, reversed.moved_uvs, 2);
      reverse(reversed.normals, reversed.face_normals, reversed.moved_normals, 3);
      options.minor_version = 2;
      const std::string reversed_bytes = write(reversed, options);
      expect_identical(with_sorted_moves(read(reversed_bytes)),
                       with_sorted_moves(read(write(reversed, [&] {
                         WriteOptions v21_options = options;
                         v21_options.minor_version = 1;
                         return v21_options;
                       }()))));
      EXPECT_GT(reversed_bytes.size(), v22.size());
    }
  }
}

// A textured mesh's 2.2 stream in chunks of 64 splits: many prefixes, each with part of
// the table entries.
std::string seamed_grid_in_small_chunks() {
  ProgressiveMesh pm;
  EXPECT_TRUE(encode(test::seamed_grid(24), EncodeOptions{}, pm).is_ok());
  WriteOptions options;
  options.chunk_splits = 64;
  return write(pm, options);
}

// 2.2 (§7): a prefix holds only the table entries its splits introduced (and those listed
// up front), renumbered in order: its finest level has every corner's value, and no entry
// whose value has not arrived.
TEST(PmStream, APrefixOf22HasOnlyTheEntriesItsSplitsIntroduced) {
  const std::string bytes = seamed_grid_in_small_chunks();
  const ProgressiveMesh whole = read(bytes);
  for (const uint32_t splits : {1u, 200u}) {
    SCOPED_TRACE(std::to_string(splits) + " splits wanted");
    ReadOptions prefix_options;
    prefix_options.max_splits = splits;
    ReadResult result;
    const ProgressiveMesh prefix = read(bytes, prefix_options, &result);
    ASSERT_TRUE(result.partial);
    ASSERT_LT(prefix.splits.size(), whole.splits.size());
    EXPECT_LT(prefix.uv_count(), whole.uv_count());
    const Mesh level = extract_level(prefix, prefix.splits.size());
    const Mesh expected = extract_level(whole, prefix.splits.size());
    ASSERT_EQ(level.triangles, expected.triangles);
    // Every corner has the value it has in the whole stream's level.
    for (std::size_t c = 0; c < expected.uv_indices.size(); ++c) {
      ASSERT_EQ(level.uv_indices[c] == kNoAttribute, expected.uv_indices[c] == kNoAttribute);
      if (level.uv_indices[c] == kNoAttribute) continue;
      const uint32_t a = level.uv_indices[c], b = expected.uv_indices[c];
      EXPECT_EQ(level.uvs[2 * a], expected.uvs[2 * b]);
      EXPECT_EQ(level.uvs[2 * a + 1], expected.uvs[2 * b + 1]);
    }
  }
}

// A streaming decoder in a binding lives in a heap object: the reader moves with its state,
// and take() hands the finished mesh over without a copy, once.
static_assert(std::is_nothrow_move_constructible_v<PmStreamReader>);
static_assert(std::is_nothrow_move_assignable_v<PmStreamReader>);
static_assert(!std::is_copy_constructible_v<PmStreamReader>);

TEST(PmStream, AReaderMovedMidStreamFinishesAndHandsItsMeshOver) {
  const ProgressiveMesh pm = with_attributes(generated_mesh(900));
  WriteOptions options;
  options.chunk_splits = 64;
  const std::string bytes = write(pm, options);
  const ProgressiveMesh whole = read(bytes);
  PmStreamReader first;
  ASSERT_TRUE(first.append(std::string_view(bytes).substr(0, bytes.size() / 2)).is_ok());
  ASSERT_TRUE(first.has_base());
  const std::size_t splits_before = first.mesh().splits.size();
  ProgressiveMesh early;
  EXPECT_EQ(first.take(early).code(), ErrorCode::kInvalidArgument);  // not finished
  EXPECT_EQ(early.vertex_count(), 0u);

  PmStreamReader second(std::move(first));
  EXPECT_EQ(second.mesh().splits.size(), splits_before);
  auto held = std::make_unique<PmStreamReader>();
  *held = std::move(second);
  ASSERT_TRUE(held->append(std::string_view(bytes).substr(bytes.size() / 2)).is_ok());
  ASSERT_TRUE(held->finish().is_ok());
  ProgressiveMesh taken;
  ASSERT_TRUE(held->take(taken).is_ok());
  expect_identical(taken, whole);
  // The reader holds nothing after that.
  EXPECT_EQ(held->mesh().vertex_count(), 0u);
  ProgressiveMesh again;
  EXPECT_EQ(held->take(again).code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(held->append("x").code(), ErrorCode::kInvalidArgument);
}

// The same in the middle of a stream (pmdec --stdin --every N): mesh() after some chunks
// is what finish() makes of that prefix, with no entry whose value has not arrived, and
// decoding goes on to the whole stream afterwards.
TEST(PmStream, AMeshInTheMiddleOfA22StreamHasOnlyTheEntriesThatArrived) {
  const std::string bytes = seamed_grid_in_small_chunks();
  const ProgressiveMesh whole = read(bytes);
  PmStreamReader reader;
  std::size_t checked = 0;
  for (std::size_t at = 0; at < bytes.size(); at += 97) {
    ASSERT_TRUE(reader.append(std::string_view(bytes).substr(at, 97)).is_ok());
    if (!reader.has_base() || reader.complete()) continue;
    const ProgressiveMesh& middle = reader.mesh();
    if (middle.splits.empty() || middle.splits.size() == whole.splits.size()) continue;
    ReadOptions prefix_options;
    prefix_options.max_splits = static_cast<uint32_t>(middle.splits.size());
    ReadResult result;
    const ProgressiveMesh prefix = read(bytes, prefix_options, &result);
    ASSERT_TRUE(result.partial);
    ASSERT_EQ(prefix.splits.size(), middle.splits.size());
    EXPECT_LT(middle.uv_count(), whole.uv_count());
    expect_identical(middle, prefix);
    EXPECT_TRUE(test::ok(validate(middle)));
    ++checked;
  }
  EXPECT_GE(checked, 3u);
  ASSERT_TRUE(reader.finish().is_ok());
  expect_identical(reader.mesh(), whole);
}

// measure_pm_sizes: the header and the sections add up to the stream; the chunks' streams
// are those the stream has; 1.x streams and damaged ones are refused.
TEST(PmStream, SizesAddUpToTheStream) {
  for (const ProgressiveMesh& pm : {with_attributes(generated_mesh(700)), generated_mesh(300)}) {
    WriteOptions options;
    options.chunk_splits = 100;
    const std::string bytes = write(pm, options);
    PmSizes sizes;
    ASSERT_TRUE(measure_pm_sizes(bytes, sizes).is_ok());
    uint64_t total = sizes.header;
    for (const auto& [tag, size] : sizes.sections) total += size;
    EXPECT_EQ(total, bytes.size());
    EXPECT_EQ(sizes.chunks, chunk_plan(uint32_t(pm.splits.size()), 100).size());
    ASSERT_EQ(sizes.chunk_streams.size(), 10u);
    ASSERT_EQ(sizes.chunk_streams_compressed.size(), 10u);
    EXPECT_EQ(sizes.chunk_streams[5].first, "positions");
    EXPECT_GT(sizes.chunk_streams[5].second, 3 * pm.splits.size());  // 3 coordinates a split, > 8 bits each
    EXPECT_EQ(sizes.chunk_streams[8].second > 0, pm.has_uvs());
    EXPECT_EQ(sizes.chunk_streams[9].second > 0, pm.has_normals());
    for (std::size_t k = 0; k < 10; ++k)
      EXPECT_EQ(sizes.chunk_streams_compressed[k] > 0, sizes.chunk_streams[k].second > 0) << k;
  }
  std::string v1;
  ASSERT_TRUE(detail::write_pm_v1(small_mesh(), 19, v1).is_ok());
  PmSizes sizes;
  EXPECT_EQ(measure_pm_sizes(v1, sizes).code(), ErrorCode::kUnsupportedVersion);
  std::string damaged = write(small_mesh());
  damaged.resize(damaged.size() - 3);
  EXPECT_EQ(measure_pm_sizes(damaged, sizes).code(), ErrorCode::kTruncatedStream);
}

TEST(PmStream, MemoryLimitIsCheckedBeforeDecoding) {
  const std::string bytes = write(generated_mesh(5000));
  ReadOptions options;
  options.max_memory = 10000;
  ProgressiveMesh pm;
  const Status status = read_pm(bytes, pm, options);
  EXPECT_EQ(status.code(), ErrorCode::kResourceLimit);
  EXPECT_NE(status.message().find("the limit is"), std::string::npos);
  options.max_memory = 100 << 20;
  EXPECT_TRUE(read_pm(bytes, pm, options).is_ok());
}

// The triangles of an n x n grid of (n + 1)^2 vertices, row by row.
void add_grid_triangles(Mesh& m, int n) {
  const auto id = [n](int i, int j) { return static_cast<uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.triangles.insert(m.triangles.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.insert(m.triangles.end(), {id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
}

// A surface whose positions are decimals with `places` places (the floats a text file's
// "0.013" and the like parse to: (float)(k / 10^places), k an integer), on an n x n grid of
// spacing `spacing` / 10^places; `far`, when not 0, moves the last vertex that far along x.
Mesh decimal_surface(int n, int places, int spacing, double far = 0) {
  Mesh m;
  const double scale = std::pow(10.0, places);
  const auto decimal = [&](int64_t k) { return static_cast<float>(static_cast<double>(k) / scale); };
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const auto wave = static_cast<int64_t>(std::lround(3 * spacing * std::sin(0.7 * i) * std::cos(0.4 * j)));
      m.positions.insert(m.positions.end(), {decimal(int64_t{spacing} * i), decimal(int64_t{spacing} * j + i % 3),
                                             decimal(wave)});
    }
  if (far != 0) m.positions[m.positions.size() - 3] = decimal(std::llround(far * scale));
  add_grid_triangles(m, n);
  return m;
}

// A surface whose positions are decimals of 6 significant digits over 14 decades ("%g":
// 195.046, 0.0160330, -6.96100e-06), which no decimal grid of 30 bits holds.
Mesh significant_surface(int n) {
  Mesh m;
  const auto decimal = [](int64_t mantissa, int exponent) {
    return static_cast<float>(static_cast<double>(mantissa) / std::pow(10.0, exponent));
  };
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const int64_t bump = 100000 + 997 * ((i * j) % 700);
      m.positions.insert(m.positions.end(), {decimal(100000 + 3173 * i, 3), decimal(100000 + 2011 * j, 7),
                                             decimal((i + j) % 2 == 0 ? bump : -bump, 10)});
    }
  add_grid_triangles(m, n);
  return m;
}

std::vector<uint32_t> float_bits(const std::vector<float>& values) {
  std::vector<uint32_t> out(values.size());
  if (!values.empty()) std::memcpy(out.data(), values.data(), values.size() * sizeof(float));  // never null
  return out;
}

// 2.3 (pm-format.md §5.3): lossless positions that are decimals go on the grid of their
// decimals, or are coded as decimals of their few significant digits, bit for bit, in fewer
// bytes than their float bits; positions that are not (one float off a decimal, a negative
// zero, floats coarser than the decimals) keep their bits.
TEST(PmStream, Version23StoresDecimalPositionsOnTheirGridLosslessly) {
  struct Case {
    const char* name;
    Mesh mesh;
    bool decimal;
    uint32_t bits;  // the grid's, when decimal
    bool significant = false;
  };
  std::vector<Case> cases;
  cases.push_back({"3 places", decimal_surface(30, 3, 13), true, 9});  // x up to 0.390: 390 < 2^9
  cases.push_back({"6 places, 25 bits", decimal_surface(30, 6, 1300, 30.0), true, 25});
  cases.push_back({"6 significant digits", significant_surface(30), false, 0, true});
  // Both fit: a grid would take 10^-6 steps for the one "1e-06", where 5 significant digits
  // step 10^-4 at 3.9001 (as fandisk's "15.3644" and "1e-06"): the coarser is taken.
  Mesh both = decimal_surface(30, 4, 1300);
  both.positions[5] = 1e-06f;
  cases.push_back({"a grid or significant digits", both, false, 0, true});
  Mesh off_by_an_ulp = decimal_surface(30, 3, 13);
  off_by_an_ulp.positions[40] = std::nextafter(off_by_an_ulp.positions[40], 1.0f);
  cases.push_back({"one float off", off_by_an_ulp, false, 0});
  Mesh negative_zero = decimal_surface(30, 3, 13);
  negative_zero.positions[2] = -0.0f;
  cases.push_back({"a negative zero", negative_zero, false, 0});
  Mesh far_away = decimal_surface(30, 6, 13);  // 3000.000013: a float's step there is 2.4e-4
  for (float& x : far_away.positions) x += 3000.0f;
  cases.push_back({"floats coarser than the decimals", far_away, false, 0});
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    ProgressiveMesh pm;
    ASSERT_TRUE(encode(c.mesh, EncodeOptions{}, pm).is_ok());
    WriteOptions v23_options;
    v23_options.minor_version = 3;
    const std::string v23 = write(pm, v23_options);
    EXPECT_EQ(static_cast<uint8_t>(v23[10]), 3);  // minor 3
    PmInfo info;
    ASSERT_TRUE(read_pm_info(v23, info).is_ok());
    EXPECT_EQ(info.positions_decimal, c.decimal);
    EXPECT_EQ(info.positions_significant, c.significant);
    EXPECT_EQ(info.position_bits, c.bits);
    const ProgressiveMesh decoded = read(v23);
    EXPECT_EQ(float_bits(decoded.positions), float_bits(pm.positions));
    EXPECT_EQ(float_bits(extract_level(decoded, decoded.splits.size()).positions),
              float_bits(extract_level(pm, pm.splits.size()).positions));
    // Every level as 2.2 gives it, and a smaller stream where the grid is used.
    WriteOptions v22_options;
    v22_options.minor_version = 2;
    const std::string v22 = write(pm, v22_options);
    expect_identical(with_sorted_moves(decoded), with_sorted_moves(read(v22)));
    if (c.decimal || c.significant) {
      EXPECT_LT(double(v23.size()), 0.8 * double(v22.size())) << v23.size() << " against " << v22.size();
    } else {
      EXPECT_EQ(v23.size(), v22.size());
    }
    std::printf("%s: 2.3 %zu bytes, 2.2 %zu\n", c.name, v23.size(), v22.size());
  }
  if (!test::shared_meshes_available()) return test::warn_no_shared_meshes();
  // The bunny's "-0.037830": 6 places, an 18-bit grid; measured 0.61 of 2.2's bytes.
  Mesh bunny;
  ASSERT_TRUE(read_mesh(test::shared_mesh_path("stanford-bunny.obj"), bunny).is_ok());
  ProgressiveMesh pm;
  ASSERT_TRUE(encode(bunny, EncodeOptions{}, pm).is_ok());
  WriteOptions v22_options;
  v22_options.minor_version = 2;
  WriteOptions v23_options;
  v23_options.minor_version = 3;
  const std::string v23 = write(pm, v23_options), v22 = write(pm, v22_options);
  PmInfo info;
  ASSERT_TRUE(read_pm_info(v23, info).is_ok());
  EXPECT_TRUE(info.positions_decimal);
  EXPECT_EQ(info.position_bits, 18u);
  EXPECT_LT(double(v23.size()), 0.7 * double(v22.size())) << v23.size() << " against " << v22.size();
  const ProgressiveMesh decoded = read(v23);
  EXPECT_EQ(float_bits(extract_level(decoded, decoded.splits.size()).positions),
            float_bits(extract_level(pm, pm.splits.size()).positions));
}

// The stream with header bytes changed (offset, value), its CRC made good again.
std::string with_header_bytes(std::string bytes, std::initializer_list<std::pair<std::size_t, uint8_t>> changes) {
  for (const auto& [offset, value] : changes) bytes[offset] = static_cast<char>(value);
  const uint32_t crc = detail::crc32(std::string_view(bytes).substr(0, 92));
  for (int k = 0; k < 4; ++k) bytes[92 + k] = static_cast<char>(crc >> (8 * k));
  return bytes;
}

// What read_pm says of a stream (its message printed, when not ok).
ErrorCode code(const std::string& bytes) {
  ProgressiveMesh out;
  const Status status = read_pm(bytes, out);
  if (!status) std::printf("  %s\n", status.message().c_str());
  return status.code();
}

// The stream with the payload of its section `tag` changed by `change` (and compressed again).
template <typename Change>
std::string with_section_payload(const std::string& bytes, const char (&tag)[5], Change change) {
  for (std::size_t offset = 96; offset + 24 <= bytes.size();) {
    uint64_t stored = 0, raw_size = 0;
    for (int b = 0; b < 8; ++b) stored |= uint64_t{static_cast<uint8_t>(bytes[offset + 8 + b])} << (8 * b);
    for (int b = 0; b < 8; ++b) raw_size |= uint64_t{static_cast<uint8_t>(bytes[offset + 16 + b])} << (8 * b);
    if (bytes.compare(offset, 4, tag) == 0) {
      std::string raw(raw_size, '\0');
      EXPECT_EQ(ZSTD_decompress(raw.data(), raw.size(), bytes.data() + offset + 24, stored), raw_size);
      change(raw);
      std::string section;
      EXPECT_TRUE(detail::append_section(detail::make_tag(tag), 1, raw, raw.size(), 3, section).is_ok());
      return bytes.substr(0, offset) + section + bytes.substr(offset + 24 + stored);
    }
    offset += 24 + stored;
  }
  ADD_FAILURE() << "no " << tag;
  return bytes;
}
template <typename Change>
std::string with_base_payload(const std::string& bytes, Change change) {
  return with_section_payload(bytes, "BASE", change);
}

// Hostile decimal grids: the option in a 2.2 stream or without grid bits, more than 24 bits
// without it, more than 30 with it, too many places, a first value beyond 2^52: each a clean
// kCorruptStream.
TEST(PmStream, HostileDecimalGridsAreRefused) {
  ProgressiveMesh pm;
  ASSERT_TRUE(encode(decimal_surface(8, 3, 13), EncodeOptions{}, pm).is_ok());
  const std::string bytes = write(pm);
  PmInfo info;
  ASSERT_TRUE(read_pm_info(bytes, info).is_ok());
  ASSERT_TRUE(info.positions_decimal);
  // The surgery itself is sound.
  EXPECT_EQ(code(with_base_payload(bytes, [](std::string&) {})), ErrorCode::kOk);
  EXPECT_EQ(code(with_header_bytes(bytes, {{10, 2}})), ErrorCode::kCorruptStream);  // a 2.2 stream
  EXPECT_EQ(code(with_header_bytes(bytes, {{84, 0}})), ErrorCode::kCorruptStream);  // no grid bits
  EXPECT_EQ(code(with_header_bytes(bytes, {{84, 31}})), ErrorCode::kCorruptStream);  // 31 bits
  EXPECT_EQ(code(with_header_bytes(bytes, {{84, 25}, {88, 0}})), ErrorCode::kCorruptStream);  // 25 bits, float grid
  EXPECT_EQ(code(with_base_payload(bytes, [](std::string& raw) { raw[0] = 16; })), ErrorCode::kCorruptStream);
  EXPECT_EQ(code(with_base_payload(bytes, [](std::string& raw) { raw[8] = 0x10; })), ErrorCode::kCorruptStream);
  EXPECT_EQ(code(with_base_payload(bytes, [](std::string& raw) { raw[8] = static_cast<char>(0xF0); })),
            ErrorCode::kCorruptStream);
  EXPECT_EQ(code(with_base_payload(bytes, [](std::string& raw) { raw.resize(12); })), ErrorCode::kCorruptStream);
}

// Hostile significant decimals: the option on a grid, digits 0 or 10, a first exponent
// beyond -60 to 40, base positions beyond a float: each a clean kCorruptStream.
TEST(PmStream, HostileSignificantDecimalsAreRefused) {
  ProgressiveMesh pm;
  ASSERT_TRUE(encode(significant_surface(6), EncodeOptions{}, pm).is_ok());
  const std::string bytes = write(pm);
  PmInfo info;
  ASSERT_TRUE(read_pm_info(bytes, info).is_ok());
  ASSERT_TRUE(info.positions_significant);
  EXPECT_EQ(code(with_header_bytes(bytes, {{84, 12}})), ErrorCode::kCorruptStream);  // on a grid
  EXPECT_EQ(code(with_base_payload(bytes, [](std::string&) {})), ErrorCode::kOk);
  EXPECT_EQ(code(with_base_payload(bytes, [](std::string& raw) { raw[0] = 0; })), ErrorCode::kCorruptStream);
  EXPECT_EQ(code(with_base_payload(bytes, [](std::string& raw) { raw[0] = 10; })), ErrorCode::kCorruptStream);
  EXPECT_EQ(code(with_base_payload(bytes, [](std::string& raw) { raw[1] = 41; })), ErrorCode::kCorruptStream);
  EXPECT_EQ(code(with_base_payload(bytes, [](std::string& raw) { raw[1] = -61; })), ErrorCode::kCorruptStream);
  // First exponent 40: every nonzero number is a decimal of 10^45 or more, beyond a float.
  EXPECT_EQ(code(with_base_payload(bytes, [](std::string& raw) { raw[1] = 40; })), ErrorCode::kCorruptStream);
  // Other digits and first exponents within the bounds make the same numbers other decimals:
  // 2.4's predictions from their values (§5.3) must take them without harm (the sanitizer
  // run checks the arithmetic), the stream decoding to other floats or refused as corrupt.
  for (const int digits : {1, 2, 9}) {
    for (const int first : {-60, -30, 0, 30}) {
      SCOPED_TRACE(std::to_string(digits) + " digits from 10^" + std::to_string(first));
      const ErrorCode patched = code(with_base_payload(bytes, [&](std::string& raw) {
        raw[0] = static_cast<char>(digits);
        raw[1] = static_cast<char>(first);
      }));
      EXPECT_TRUE(patched == ErrorCode::kOk || patched == ErrorCode::kCorruptStream);
    }
  }
}

// The values of `tables` (a mesh's positions, texture coordinates or normals) rounded to
// `digits` significant decimals, as "%g" writes them.
void round_to_significant_decimals(std::initializer_list<std::vector<float>*> tables, int digits) {
  for (std::vector<float>* values : tables) {
    for (float& x : *values) {
      char text[32];
      std::snprintf(text, sizeof text, "%.*e", digits - 1, double{x});
      x = std::strtof(text, nullptr);
    }
  }
}

// pm's stream in `minor` and in `older`: the first checked against pm's floats bit for bit,
// both decoded to the same mesh; {newer, older}.
std::pair<std::string, std::string> streams_in_minors(const ProgressiveMesh& pm, uint16_t minor, uint16_t older) {
  WriteOptions options;
  options.minor_version = minor;
  const std::string newer = write(pm, options);
  EXPECT_EQ(static_cast<uint8_t>(newer[10]), minor);
  const ProgressiveMesh decoded = read(newer);
  EXPECT_EQ(float_bits(decoded.positions), float_bits(pm.positions));
  EXPECT_EQ(float_bits(decoded.uvs), float_bits(pm.uvs));
  EXPECT_EQ(float_bits(decoded.normals), float_bits(pm.normals));
  options.minor_version = older;
  std::string old = write(pm, options);
  expect_identical(with_sorted_moves(decoded), with_sorted_moves(read(old)));
  std::printf("2.%d %zu bytes, 2.%d %zu\n", minor, newer.size(), older, old.size());
  return {newer, std::move(old)};
}

// 2.3 (§5.4): lossless texture-coordinate and normal tables of decimals ("vt 0.800375
// 0.667457") are coded as the numbers of their significant decimals, bit for bit and smaller;
// hostile records are refused.
TEST(PmStream, Version23StoresDecimalTablesAsSignificantDecimals) {
  Mesh input = test::seamed_grid(24);
  round_to_significant_decimals({&input.uvs, &input.normals}, 6);
  ProgressiveMesh pm;
  ASSERT_TRUE(encode(input, EncodeOptions{}, pm).is_ok());
  ASSERT_TRUE(pm.has_uvs() && pm.has_normals());
  const auto [v23, v22] = streams_in_minors(pm, 3, 2);
  PmInfo info;
  ASSERT_TRUE(read_pm_info(v23, info).is_ok());
  EXPECT_TRUE(info.uvs_significant);
  EXPECT_TRUE(info.normals_significant);
  EXPECT_LT(v23.size(), v22.size());
  // Every prefix (chunks of 64 splits) decodes, with the entries known so far.
  WriteOptions small_chunks;
  small_chunks.chunk_splits = 64;
  const std::string chunked = write(pm, small_chunks);
  ReadOptions prefix;
  prefix.max_splits = pm.splits.size() / 2;
  const ProgressiveMesh half = read(chunked, prefix);
  EXPECT_TRUE(test::ok(validate(half)));
  EXPECT_LT(half.splits.size(), pm.splits.size());
  // A quantized table is not also significant; a record of 0 or 10 digits, a first exponent
  // beyond 40, a value no decimal has: each a clean kCorruptStream.
  EXPECT_EQ(code(with_header_bytes(v23, {{85, 10}})), ErrorCode::kCorruptStream);  // uv_bits 10
  EXPECT_EQ(code(with_section_payload(v23, "TABL", [](std::string&) {})), ErrorCode::kOk);
  EXPECT_EQ(code(with_section_payload(v23, "TABL", [](std::string& raw) { raw[0] = 0; })),
            ErrorCode::kCorruptStream);
  EXPECT_EQ(code(with_section_payload(v23, "TABL", [](std::string& raw) { raw[0] = 10; })),
            ErrorCode::kCorruptStream);
  EXPECT_EQ(code(with_section_payload(v23, "TABL", [](std::string& raw) { raw[1] = 41; })),
            ErrorCode::kCorruptStream);
  EXPECT_EQ(code(with_section_payload(v23, "TABL", [](std::string& raw) { raw[1] = 40; })),
            ErrorCode::kCorruptStream);
}

// 2.4 (§5.3, §5.10, §5.11): significant decimals are predicted by their values (the mean of
// the neighbours' values, u's normal frame, texture maps of values) and new texture
// coordinates through the arc face that holds v: the same floats, bit for bit, every level
// as 2.3 gives it, in fewer bytes. The surface whose z crosses zero at every vertex is where
// 2.3's means of numbers were furthest off (between -1e-5 and 1e-5 lie all the decades down
// to the first).
TEST(PmStream, Version24PredictsSignificantDecimalsByTheirValues) {
  struct Case {
    const char* name;
    Mesh mesh;
    double at_most;  // of 2.3's bytes
  };
  // A wave about the origin (every coordinate crosses zero), with texture coordinates that
  // are no affine map of the positions.
  const int n = 40;
  Mesh wave;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = (i - n / 2) * 0.0137 + 0.002 * std::sin(1.3 * j);
      const double y = (j - n / 2) * 0.0113 + 0.002 * std::cos(0.9 * i);
      const double z = 0.05 * std::sin(0.31 * i + 0.2) * std::cos(0.23 * j - 0.4);
      wave.positions.insert(wave.positions.end(), {float(x), float(y), float(z)});
      wave.uvs.insert(wave.uvs.end(), {float(0.5 + x + 0.8 * x * x), float(0.45 + y + 0.6 * x * y + z)});
    }
  add_grid_triangles(wave, n);
  wave.uv_indices = wave.triangles;
  round_to_significant_decimals({&wave.positions, &wave.uvs}, 6);
  std::vector<Case> cases;
  cases.push_back({"a wave across zero", wave, 0.95});
  if (test::shared_meshes_available()) {
    Mesh spot;
    ASSERT_TRUE(read_mesh(test::shared_mesh_path("spot.obj"), spot).is_ok());
    cases.push_back({"spot", spot, 0.95});
  } else {
    test::warn_no_shared_meshes();
  }
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    ProgressiveMesh pm;
    ASSERT_TRUE(encode(c.mesh, EncodeOptions{}, pm).is_ok());
    const auto [v24, v23] = streams_in_minors(pm, 4, 3);
    PmInfo info;
    ASSERT_TRUE(read_pm_info(v24, info).is_ok());
    EXPECT_TRUE(info.positions_significant);
    EXPECT_TRUE(info.uvs_significant);
    EXPECT_LT(double(v24.size()), c.at_most * double(v23.size())) << v24.size() << " against " << v23.size();
  }
}

// Golden streams of every version, committed: a change that breaks old files fails here.
// PM_REGENERATE_GOLDEN=1 rewrites the current version's files, on purpose.
TEST(PmStream, GoldenFilesOfEveryVersionDecode) {
  const std::string dir = std::string(PM_TEST_DATA_DIR) + "/golden/";
  struct Golden {
    const char* name;
    ProgressiveMesh pm;
  };
  ProgressiveMesh ordered = attributed_mesh();  // with the input's order (ORDR, 2.0 only)
  ordered.input_vertices = {0, 1, 2, 3, 5, 6, 7, 8};
  ordered.input_faces = {21, 19, 17, 12, 9, 6, 3, 2};
  const std::vector<Golden> goldens = {{"small", small_mesh()},
                                       {"attributed", attributed_mesh()},
                                       {"generated", with_attributes(generated_mesh(600))},
                                       {"ordered", ordered}};
  if (std::getenv("PM_REGENERATE_GOLDEN") != nullptr) {
    for (const Golden& g : goldens) {
      std::string v1;
      ASSERT_TRUE(detail::write_pm_v1(g.pm, 19, v1).is_ok());
      if (!g.pm.keeps_order()) test::write_file(dir + g.name + "-v1.1.pm", v1);
      WriteOptions options;
      options.chunk_splits = 128;
      test::write_file(dir + g.name + "-v2." + std::to_string(kFormatMinor) + ".pm", write(g.pm, options));
    }
  }
  // 2.1's normal-coordinate prediction works on grids only: a quantized golden file, whose
  // decoded mesh is the 2.0 writer's (the same grid values, coded without it).
  WriteOptions quantized;
  quantized.chunk_splits = 128;
  quantized.position_bits = 12;
  const ProgressiveMesh surface = generated_mesh(600);
  if (std::getenv("PM_REGENERATE_GOLDEN") != nullptr) {
    WriteOptions v21 = quantized;
    v21.minor_version = 1;
    test::write_file(dir + "quantized-v2.1.pm", write(surface, v21));
  }
  // Files of an encoded sample in several minor versions, from one progressive mesh (all
  // committed, so that a change of the encoder does not change what is compared).
  const auto write_versions = [&](const char* sample, const std::string& stem, WriteOptions options,
                                  std::initializer_list<uint16_t> minors) {
    Mesh mesh;
    ASSERT_TRUE(read_mesh(test::sample_mesh_path(sample), mesh).is_ok());
    ProgressiveMesh pm;
    ASSERT_TRUE(encode(mesh, EncodeOptions{}, pm).is_ok());
    for (const uint16_t minor : minors) {
      options.minor_version = minor;
      test::write_file(dir + stem + "-v2." + std::to_string(minor) + ".pm", write(pm, options));
    }
  };
  // An encoded surface (the sphere sample: closed fans, layers), quantized, in 2.0 and 2.1:
  // the two files decode to the same mesh. Frozen: PM_REGENERATE_GOLDEN_OLD rewrites them.
  if (std::getenv("PM_REGENERATE_GOLDEN_OLD") != nullptr) {
    WriteOptions options;
    options.position_bits = 12;
    options.chunk_splits = 512;
    write_versions("sphere.obj", "sphere-q12", options, {0, 1});
  }
  {
    const ProgressiveMesh v20 = read(test::read_file(dir + "sphere-q12-v2.0.pm"));
    const ProgressiveMesh v21 = read(test::read_file(dir + "sphere-q12-v2.1.pm"));
    EXPECT_GT(v21.splits.size(), 1000u);
    expect_identical(with_sorted_moves(v21), with_sorted_moves(v20));
  }
  // An encoded textured mesh (UV seams, materials), quantized, in 2.1 and 2.2 (the splits'
  // corners as wedges, §5.11) from the same progressive mesh: the two decode the same.
  if (std::getenv("PM_REGENERATE_GOLDEN") != nullptr) {
    WriteOptions options;
    options.position_bits = 12;
    options.uv_bits = 10;
    options.chunk_splits = 64;
    write_versions("textured.obj", "textured-q12", options, {1, 2});
  }
  {
    const ProgressiveMesh v21 = read(test::read_file(dir + "textured-q12-v2.1.pm"));
    const ProgressiveMesh v22 = read(test::read_file(dir + "textured-q12-v2.2.pm"));
    EXPECT_TRUE(v22.has_uvs());
    EXPECT_GT(v22.splits.size(), 100u);
    expect_identical(with_sorted_moves(v22), with_sorted_moves(v21));
  }
  {
    quantized.minor_version = 0;
    const std::string path = dir + "quantized-v2.1.pm";
    ASSERT_TRUE(test::file_exists(path)) << path;
    expect_identical(with_sorted_moves(read(test::read_file(path))),
                     with_sorted_moves(read(write(surface, quantized))));
  }
  // 2.3's and 2.4's positions as decimals (§5.3), each in a file of its own: the file decodes
  // to the mesh, with the header's flags `expect` checks. The current version's files are
  // rewritten by PM_REGENERATE_GOLDEN, older ones by PM_REGENERATE_GOLDEN_OLD.
  const auto decimal_golden = [&](const char* file, uint16_t minor, const ProgressiveMesh& mesh,
                                  const std::function<void(const PmInfo&)>& expect) {
    SCOPED_TRACE(file);
    const std::string path = dir + file;
    if (std::getenv(minor == kFormatMinor ? "PM_REGENERATE_GOLDEN" : "PM_REGENERATE_GOLDEN_OLD") != nullptr) {
      WriteOptions options;
      options.chunk_splits = 128;
      options.minor_version = minor;
      test::write_file(path, write(mesh, options));
    }
    ASSERT_TRUE(test::file_exists(path)) << path;
    const std::string bytes = test::read_file(path);
    PmInfo info;
    ASSERT_TRUE(read_pm_info(bytes, info).is_ok());
    expect(info);
    expect_identical(with_sorted_moves(read(bytes)), with_sorted_moves(mesh));
  };
  // A decimal grid of 26 bits: positions with 5 places, up to 599.
  ProgressiveMesh decimal = with_attributes(generated_mesh(600));
  for (float& x : decimal.positions) {
    x = static_cast<float>(static_cast<double>(std::llround(double{x} * 1e5)) / 1e5);
  }
  decimal_golden("decimal-v2.3.pm", 3, decimal, [](const PmInfo& info) {
    EXPECT_TRUE(info.positions_decimal);
    EXPECT_EQ(info.position_bits, 26u);
  });
  // Significant decimals: positions of 6 significant digits.
  ProgressiveMesh significant = generated_mesh(600);
  round_to_significant_decimals({&significant.positions}, 6);
  decimal_golden("significant-v2.3.pm", 3, significant,
                 [](const PmInfo& info) { EXPECT_TRUE(info.positions_significant); });
  // 2.4: significant decimals predicted by their values, texture coordinates too (whose
  // values, 0 to 300, span three decades).
  ProgressiveMesh significant_attributed = with_attributes(generated_mesh(600));
  significant_attributed.positions = significant.positions;
  decimal_golden("significant-v2.4.pm", 4, significant_attributed, [](const PmInfo& info) {
    EXPECT_TRUE(info.positions_significant);
    EXPECT_TRUE(info.uvs_significant);
  });
  for (const Golden& g : goldens) {
    for (const char* version : {"v1.1", "v2.0", "v2.1", "v2.2", "v2.3", "v2.4"}) {
      if (g.pm.keeps_order() && std::string(version) == "v1.1") continue;  // 1.x has no order
      SCOPED_TRACE(std::string(g.name) + "-" + version);
      const std::string path = dir + g.name + "-" + version + ".pm";
      ASSERT_TRUE(test::file_exists(path)) << path;
      const ProgressiveMesh pm = read(test::read_file(path));
      expect_identical(with_sorted_moves(pm), with_sorted_moves(g.pm));
    }
  }
}

// Every golden file is what today's writer writes for the mesh it decodes to, with the
// options its header shows (its minor version, grids and largest chunk; 1.x files by the 1.1
// writer): a change of the writer that changes a byte of a version it still writes is noticed
// here, as the shared meshes' streams are by test_shared_mesh_streams.cpp.
TEST(PmStream, GoldenFilesAreWhatTheWriterWritesAgain) {
  const std::string dir = std::string(PM_TEST_DATA_DIR) + "/golden/";
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  ASSERT_GE(names.size(), 31u);
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    const std::string bytes = test::read_file(dir + name);
    PmInfo info;
    ASSERT_TRUE(read_pm_info(bytes, info).is_ok());
    const ProgressiveMesh pm = read(bytes);
    std::string again;
    if (info.major == 1) {
      ASSERT_TRUE(detail::write_pm_v1(pm, 19, again).is_ok());
    } else {
      WriteOptions options;
      options.minor_version = info.minor;
      // A decimal grid is the writer's own choice, as are significant decimals.
      options.position_bits = info.positions_decimal ? 0 : static_cast<int>(info.position_bits);
      options.uv_bits = static_cast<int>(info.uv_bits);
      options.normal_bits = static_cast<int>(info.normal_bits);
      uint32_t largest_chunk = 0;
      for (const PmInfo::Chunk& chunk : info.chunks) largest_chunk = std::max(largest_chunk, chunk.splits);
      if (largest_chunk != 0) options.chunk_splits = largest_chunk;
      again = write(pm, options);
    }
    EXPECT_TRUE(again == bytes) << "written again: " << again.size() << " bytes, the file has "
                                << bytes.size();
  }
}

// pmenc --keep-order: full detail is the input array for array, in the input's order.
void expect_same_arrays(const Mesh& a, const Mesh& b) {
  EXPECT_EQ(bits_of(a.positions), bits_of(b.positions));
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.color_components, b.color_components);
  EXPECT_EQ(bits_of(a.colors), bits_of(b.colors));
  EXPECT_EQ(bits_of(a.uvs), bits_of(b.uvs));
  EXPECT_EQ(a.uv_indices, b.uv_indices);
  EXPECT_EQ(bits_of(a.normals), bits_of(b.normals));
  EXPECT_EQ(a.normal_indices, b.normal_indices);
  EXPECT_EQ(a.face_materials, b.face_materials);
  EXPECT_EQ(a.material_names, b.material_names);
}

TEST(PmStream, KeepOrderGivesTheInputsArraysAtFullDetail) {
  std::vector<std::string> paths = test::sample_mesh_paths();
  if (test::shared_meshes_available()) {
    for (const char* name : {"spot.obj", "cow.obj", "fandisk.obj"}) paths.push_back(test::shared_mesh_path(name));
  }
  for (const std::string& path : paths)
    for (const Metric metric : {Metric::kQuadric, Metric::kSchroeder}) {
      SCOPED_TRACE(path + (metric == Metric::kSchroeder ? " (schroeder)" : ""));
      Mesh input;
      ASSERT_TRUE(read_mesh(path, input).is_ok());
      EncodeOptions options;
      options.keep_order = true;
      options.metric = metric;
      ProgressiveMesh pm;
      ASSERT_TRUE(encode(input, options, pm).is_ok());
      EXPECT_EQ(pm.input_vertices.size(), input.vertex_count());
      EXPECT_EQ(pm.input_faces.size(), input.face_count());
      const ProgressiveMesh decoded = read(write(pm));
      expect_same_arrays(extract_level(decoded, decoded.splits.size()), input);
      // Coarser levels are as without the order; a prefix does not read it.
      EncodeOptions without_order;
      without_order.metric = metric;
      ProgressiveMesh plain;
      ASSERT_TRUE(encode(input, without_order, plain).is_ok());
      const std::size_t half = plain.splits.size() / 2;
      EXPECT_EQ(test::canonical_faces(extract_level(decoded, half)),
                test::canonical_faces(extract_level(plain, half)));
      // One split per chunk: the prefix ends at `half`. Every split is full detail, and
      // reads the order.
      WriteOptions one_per_chunk;
      one_per_chunk.chunk_splits = 1;
      const std::string chunked = write(pm, one_per_chunk);
      ReadOptions prefix;
      prefix.max_splits = half;
      const ProgressiveMesh coarse = read(chunked, prefix);
      EXPECT_EQ(coarse.splits.size(), half);
      EXPECT_FALSE(coarse.keeps_order() && half < pm.splits.size());
      prefix.max_splits = pm.splits.size();
      const ProgressiveMesh every = read(chunked, prefix);
      expect_same_arrays(extract_level(every, every.splits.size()), input);
    }
}

// A level's triangles as position triples, each rotated to its smallest corner, sorted:
// the same for two meshes that differ only in vertex and face order.
std::vector<std::vector<uint32_t>> sorted_triangles(const Mesh& mesh) {
  std::vector<std::vector<uint32_t>> out;
  for (std::size_t t = 0; t < mesh.face_count(); ++t) {
    std::vector<uint32_t> corners[3];
    for (int c = 0; c < 3; ++c) {
      for (int k = 0; k < 3; ++k) {
        float x = mesh.positions[3 * std::size_t{mesh.triangles[3 * t + c]} + k];
        uint32_t b;
        std::memcpy(&b, &x, 4);
        corners[c].push_back(b);
      }
    }
    const int first = static_cast<int>(std::min_element(corners, corners + 3) - corners);
    std::vector<uint32_t> triangle;
    for (int c = 0; c < 3; ++c)
      triangle.insert(triangle.end(), corners[(first + c) % 3].begin(),
                      corners[(first + c) % 3].end());
    out.push_back(triangle);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The range coder itself (formats/range_coder.h, §5.10): decisions, exp-Golomb values up to
// its limit, trees, round trips that read exactly the bytes written; cut codes are refused.
TEST(PmStream, RangeCoderRoundTripsAndRefusesDamage) {
  std::vector<uint64_t> values;
  uint64_t state = 7;
  for (int i = 0; i < 3000; ++i) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    const int bits = static_cast<int>((state >> 59) % 40);  // 0 .. 39 bits
    values.push_back(((state >> 7) & ((uint64_t{1} << bits) - 1)) + (i % 3 == 0 ? 0 : 1));
  }
  values.push_back((uint64_t{1} << detail::kMaxEgBits) - 2);  // the largest value
  std::string bytes;
  {
    detail::RangeEncoder rc(bytes);
    detail::EgModels eg;
    detail::TreeModels tree;
    detail::BitModel bit;
    for (std::size_t i = 0; i < values.size(); ++i) {
      detail::put_eg(rc, eg, values[i]);
      detail::put_tree(rc, tree, 5, static_cast<uint32_t>(values[i] & 31));
      rc.bit(bit, i % 7 == 0);
    }
    rc.finish();
  }
  const auto decode = [&](const std::string& code, bool& all_equal) {
    detail::RangeDecoder rc(code);
    detail::EgModels eg;
    detail::TreeModels tree;
    detail::BitModel bit;
    all_equal = true;
    for (std::size_t i = 0; i < values.size(); ++i) {
      uint64_t x = 0;
      if (!detail::get_eg(rc, eg, x)) return false;
      all_equal = all_equal && x == values[i] &&
                  detail::get_tree(rc, tree, 5) == (values[i] & 31) && rc.bit(bit) == (i % 7 == 0);
    }
    return rc.ok() && rc.at_end();
  };
  bool equal = false;
  EXPECT_TRUE(decode(bytes, equal));
  EXPECT_TRUE(equal);
  EXPECT_FALSE(decode(bytes.substr(0, bytes.size() - 1), equal));  // cut: reads past the end
  EXPECT_FALSE(decode(bytes + "x", equal));                        // a byte left over
  std::string first = bytes;
  first[0] = 1;  // the first byte of a range code is 0
  EXPECT_FALSE(decode(first, equal));
  // A prefix of 40 ones is refused, not read on.
  // The decoder views its bytes: they must outlive it.
  const std::string ones_code =
      std::string(1, '\0') + std::string(4, '\xFF') + std::string(64, '\xFE');
  detail::RangeDecoder ones(ones_code);
  detail::EgModels eg;
  uint64_t x = 0;
  bool refused = false;
  for (int i = 0; i < 100 && !refused; ++i) refused = !detail::get_eg(ones, eg, x);
  EXPECT_TRUE(refused || !ones.ok());
}

// The huge-page hint (memory_pages.h) is only a hint: whatever the kernel does with it, the
// memory keeps what was written before and takes what is written after, over the aligned
// interior and the unaligned ends alike, and odd ranges (null, empty, small, unaligned) are
// left alone.
TEST(PmStream, HugePageHintsKeepTheMemoryAsItIs) {
  std::vector<uint32_t> values;
  values.reserve((std::size_t{24} << 20) / sizeof(uint32_t) + 3);  // 24 MiB and a bit
  const std::size_t half = values.capacity() / 2;
  for (std::size_t i = 0; i < half; ++i) values.push_back(static_cast<uint32_t>(i * 2654435761u));
  detail::prefer_huge_pages(values);
  detail::prefer_huge_pages(values.data() + 1, values.capacity() * sizeof(uint32_t) - 5);
  detail::prefer_huge_pages(nullptr, std::size_t{1} << 30);
  detail::prefer_huge_pages(values.data(), 0);
  detail::prefer_huge_pages(values.data() + 3, 4096);
  for (std::size_t i = half; i < values.capacity(); ++i) values.push_back(static_cast<uint32_t>(i * 2654435761u));
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < values.size(); ++i) wrong += values[i] != static_cast<uint32_t>(i * 2654435761u);
  EXPECT_EQ(wrong, 0u);
  EXPECT_EQ(values.size(), values.capacity());
}

// The allocator's free memory given back (return_free_memory(), after each encode's loop)
// from many threads at once, as pmenc's batch does. Where malloc is not glibc's (a
// sanitizer's, or an allocator loaded before glibc's), glibc sets its arenas up in the first
// malloc_trim() itself, and two threads doing so at once crashed: AddressSanitizer, a read at
// 0x8 in mtrim (.ci/sanitize's batch test; this test under ASan crashed 18 of 20 runs before
// the calls took turns). In this process the first call comes from those 8 threads.
TEST(PmStream, FreeMemoryIsReturnedFromManyThreadsAtOnce) {
  constexpr int kThreads = 8;
  std::atomic<int> waiting{kThreads};
  std::vector<std::thread> threads;
  for (int i = 0; i < kThreads; ++i)
    threads.emplace_back([&waiting] {
      waiting.fetch_sub(1);
      while (waiting.load() > 0) {
      }
      detail::return_free_memory();
    });
  for (std::thread& thread : threads) thread.join();
  std::vector<uint32_t> after(std::size_t{1} << 20, 7);  // the allocator still serves
  EXPECT_EQ(std::accumulate(after.begin(), after.end(), uint64_t{0}), uint64_t{7} << 20);
}

// The windows the layers are made in: each at most the share of the vertices before it
// (at least one split), never across a chunk's end; infinity: the chunks themselves.
TEST(PmStream, LayerWindowsFollowTheVertexCountInsideTheChunks) {
  // 16 base vertices, 40 splits, a quarter: 16/4, 20/4, 25/4, 31/4, 38/4, then what is left.
  EXPECT_EQ(layer_windows(16, 40, 256, 0.25), (std::vector<uint32_t>{4, 5, 6, 7, 9, 9}));
  // Chunks of 8 cut them: 4 | 4 (20/4 = 5 > 4 left), 6 | 2, 8 | 8 | 8.
  EXPECT_EQ(layer_windows(16, 40, 8, 0.25), (std::vector<uint32_t>{4, 4, 6, 2, 8, 8, 8}));
  EXPECT_EQ(layer_windows(16, 40, 8, INFINITY), chunk_plan(40, 8));
  // Below one split's share: one split per window (no reordering).
  EXPECT_EQ(layer_windows(3, 4, 256, 0.25), (std::vector<uint32_t>{1, 1, 1, 1}));
}

// The encoder's layers (layer_splits), in whole chunks and in windows of 1/16 of the
// vertices: the same mesh at every window's end, full detail the input's arrays, a valid
// progressive mesh, and a smaller stream.
TEST(PmStream, LayeredSplitsKeepEveryWindowsMesh) {
  std::vector<std::string> paths = test::sample_mesh_paths();
  if (test::shared_meshes_available()) paths.push_back(test::shared_mesh_path("spot.obj"));
  for (const std::string& path : paths) {
    for (const double share : {double{INFINITY}, 1.0 / 16}) {
      SCOPED_TRACE(path + ", window share " + std::to_string(share));
      Mesh input;
      ASSERT_TRUE(read_mesh(path, input).is_ok());
      EncodeOptions options;
      options.keep_order = true;
      options.layer_window = 0;
      ProgressiveMesh plain, layered;
      ASSERT_TRUE(encode(input, options, plain).is_ok());
      options.layer_window = share;
      WriteOptions chunked;
      chunked.chunk_splits = 256;
      ASSERT_TRUE(encode(input, options, chunked, layered).is_ok());
      ASSERT_TRUE(test::ok(validate(layered)));
      ASSERT_EQ(layered.splits.size(), plain.splits.size());
      expect_same_arrays(extract_level(layered, layered.splits.size()), input);
      const auto S = static_cast<uint32_t>(plain.splits.size());
      std::size_t level = 0, reordered = 0;
      for (uint32_t size : layer_windows(plain.base_vertex_count, S, 256, share)) {
        level += size;
        EXPECT_EQ(layered.splits[level - size].error, plain.splits[level - size].error);
        if (level < plain.splits.size()) {
          EXPECT_EQ(layered.splits[level].error, plain.splits[level].error);
        }
        const Mesh a = extract_level(plain, level), b = extract_level(layered, level);
        EXPECT_EQ(a.face_count(), b.face_count());
        EXPECT_EQ(sorted_triangles(a), sorted_triangles(b));
        for (std::size_t k = level - size; k < level; ++k) {
          reordered += layered.splits[k].u != plain.splits[k].u;
        }
      }
      if (S > 1000) {
        EXPECT_GT(reordered, S / 4);  // the layers did reorder
      }
      expect_identical(with_sorted_moves(read(write(layered))), with_sorted_moves(layered));
      // The written stream's index describes each chunk's level; every split inside a chunk
      // is a valid level too (extract_level validates), with a non-increasing error.
      PmInfo info;
      ASSERT_TRUE(read_pm_info(write(layered, chunked), info).is_ok());
      std::size_t end = 0;
      for (const PmInfo::Chunk& chunk : info.chunks) {
        end += chunk.splits;
        EXPECT_EQ(chunk.faces_after, faces_at_level(plain, end));
        EXPECT_EQ(chunk.vertices_after, vertices_at_level(plain, end));
        EXPECT_EQ(chunk.error_after, error_at_level(plain, end));
      }
      for (std::size_t level = 1; level < layered.splits.size(); level += 97) {
        EXPECT_LE(layered.splits[level].error, layered.splits[level - 1].error);
        EXPECT_EQ(extract_level(layered, level).face_count(), faces_at_level(layered, level));
      }
      // Smaller (without the order, which the layers' u order makes dearer), by the u gaps.
      for (ProgressiveMesh* pm : {&plain, &layered})
        pm->input_vertices.clear(), pm->input_faces.clear();
      WriteOptions q14;
      q14.position_bits = 14;
      const std::string with = write(layered, q14), without = write(plain, q14);
      // (With texture coordinates, the corner codes' "latest id of any corner" predicts
      // worse across a layer than along the simplifier's order: geometry only here.)
      if (plain.splits.size() > 1000 && !plain.has_uvs() && !plain.has_normals()) {
        EXPECT_LT(with.size(), without.size() * 97 / 100);
      }
    }
  }
}

// The default windows (1/16 of the vertices) keep the levels inside them about as close to
// the input as the greedy order's: on fandisk (sharp features) and the bunny (holes), the
// RMS distance of levels in the middle of windows, from 0.3% to 60% of the vertices.
TEST(PmStream, LayerWindowsKeepTheLevelsAsCloseAsTheGreedyOrder) {
  if (!test::shared_meshes_available()) GTEST_SKIP() << "../shared/meshes not found";
  for (const char* name : {"fandisk.obj", "stanford-bunny.obj"}) {
    SCOPED_TRACE(name);
    Mesh input;
    ASSERT_TRUE(read_mesh(test::shared_mesh_path(name), input).is_ok());
    EncodeOptions options;
    options.layer_window = 0;
    ProgressiveMesh plain, layered;
    ASSERT_TRUE(encode(input, options, plain).is_ok());
    options.layer_window = 1.0 / 16;
    ASSERT_TRUE(encode(input, options, layered).is_ok());  // WriteOptions{}'s chunks
    const std::vector<uint32_t> windows =
        layer_windows(plain.base_vertex_count, static_cast<uint32_t>(plain.splits.size()),
                      WriteOptions{}.chunk_splits, options.layer_window);
    std::size_t begin = 0, candidates = 0, compared = 0;
    for (uint32_t size : windows) {
      const std::size_t vertices = plain.base_vertex_count + begin + size / 2;
      begin += size;
      if (size < 4 || vertices < input.vertex_count() / 300) continue;
      if (vertices > input.vertex_count() * 6 / 10) break;
      // Every eighth window's middle level: the windows grow by 1/16 each, so these are
      // spread over the whole range. (Whole-chunk layers fail this: up to 1.36 times.)
      if (++candidates % 8 != 1) continue;
      const std::size_t level = vertices - plain.base_vertex_count;
      SurfaceDistance greedy, windowed;
      ASSERT_TRUE(measure_surface_distance(input, extract_level(plain, level), {}, greedy).is_ok());
      ASSERT_TRUE(
          measure_surface_distance(input, extract_level(layered, level), {}, windowed).is_ok());
      EXPECT_LE(windowed.rms, greedy.rms * 1.08) << "level " << level << " of " << windows.size();
      ++compared;
    }
    EXPECT_GE(compared, 8u);
  }
}

TEST(PmStream, AnOrderThatIsNoBijectionIsInvalid) {
  ProgressiveMesh pm = small_mesh();  // 9 vertices, 1 weld; 8 faces
  pm.input_vertices = {0, 1, 2, 3, 5, 6, 7, 8};
  pm.input_faces = {21, 19, 17, 12, 9, 6, 3, 2};  // 3 * face + rotation
  EXPECT_TRUE(test::ok(validate(pm)));
  expect_round_trip(pm);
  pm.input_vertices[2] = 4;  // the welded copy
  EXPECT_FALSE(validate(pm).is_ok());
  pm.input_vertices[2] = 1;  // twice
  EXPECT_FALSE(validate(pm).is_ok());
  pm.input_vertices[2] = 2;
  pm.input_faces.pop_back();
  EXPECT_FALSE(validate(pm).is_ok());
}

// ---------------------------------------------------------------------------------------
// pmdec on 2.0 streams: cut streams, --stdin --every, chunks read on demand.

struct Encoded {
  test::TempDir dir;
  std::string pm_path, bytes;
  std::size_t input_faces = 0;
};

// sphere.obj (pm_make_samples writes it) through pmenc, in chunks of 64 splits.
void encode_sample(Encoded& e) {
  const std::string input = test::sample_mesh_path("sphere.obj");
  e.input_faces = test::load_simple_obj(input).face_count();
  e.pm_path = e.dir.file("sphere.pm");
  const test::CommandResult r =
      test::run_command({PMENC_PATH, input, "--chunk-splits", "64", "-q", "-o", e.pm_path});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  e.bytes = test::read_file(e.pm_path);
}

TEST(PmdecStream, ACutStreamGivesItsFinestLevelWithExitCode9) {
  Encoded e;
  encode_sample(e);
  const std::string cut = e.dir.file("cut.pm"), out = e.dir.file("cut.obj");
  test::write_file(cut, e.bytes.substr(0, e.bytes.size() * 6 / 10));
  const test::CommandResult r = test::run_command({PMDEC_PATH, cut, "-o", out});
  EXPECT_EQ(r.exit_code, 9) << r.err;
  EXPECT_NE(r.err.find("warning: truncated in section CHNK"), std::string::npos) << r.err;
  const Mesh level = test::load_simple_obj(out);
  EXPECT_GT(level.face_count(), 0u);
  EXPECT_LT(level.face_count(), e.input_faces);
  // A cut in the header or the base mesh: an error, and no output.
  test::write_file(cut, e.bytes.substr(0, 50));
  const std::string none = e.dir.file("none.obj");
  const test::CommandResult bad = test::run_command({PMDEC_PATH, cut, "-o", none});
  EXPECT_EQ(bad.exit_code, 4) << bad.err;
  EXPECT_NE(bad.err.find("truncated in"), std::string::npos) << bad.err;
  EXPECT_FALSE(test::file_exists(none));
}

TEST(PmdecStream, StdinWritesALevelEveryNFacesAndTheFinestAtTheEnd) {
  Encoded e;
  encode_sample(e);
  const std::string every = std::to_string(e.input_faces / 4);
  const test::CommandResult r = test::run_command(
      {PMDEC_PATH, "--stdin", "--every", every, "-o", e.dir.file("lod_{faces}.obj")}, e.bytes);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::size_t n = e.input_faces / 4;
  for (std::size_t k = 1; k * n <= e.input_faces; ++k) {
    const std::string path = e.dir.file("lod_" + std::to_string(k * n) + ".obj");
    ASSERT_TRUE(test::file_exists(path)) << path;
    const std::size_t faces = test::load_simple_obj(path).face_count();
    EXPECT_GE(faces, k * n);
    EXPECT_LE(faces, k * n + 1);  // the coarsest level with that many (a split adds 1 or 2)
  }
  const Mesh full = test::load_simple_obj(e.dir.file("lod_" + std::to_string(e.input_faces) + ".obj"));
  EXPECT_EQ(full.face_count(), e.input_faces);
  // Cut short: levels up to the cut, the finest whole level, exit code 9.
  const test::CommandResult cut = test::run_command(
      {PMDEC_PATH, "--stdin", "-o", e.dir.file("cut_{faces}.obj")}, e.bytes.substr(0, e.bytes.size() / 2));
  EXPECT_EQ(cut.exit_code, 9) << cut.err;
  EXPECT_NE(cut.err.find("warning"), std::string::npos);
  // Usage: no {faces}, or input files as well.
  EXPECT_EQ(test::run_command({PMDEC_PATH, "--stdin", "-o", e.dir.file("x.obj")}, e.bytes).exit_code, 2);
  EXPECT_EQ(test::run_command({PMDEC_PATH, e.pm_path, "--stdin", "-o", e.dir.file("x{faces}.obj")}).exit_code, 2);
}

TEST(PmdecStream, KeepOrderWritesTheInputsOrder) {
  test::TempDir dir;
  const std::string input = test::sample_mesh_path("textured.obj");
  const std::string pm_path = dir.file("t.pm"), out = dir.file("t.obj");
  ASSERT_EQ(test::run_command({PMENC_PATH, input, "--keep-order", "-q", "-o", pm_path}).exit_code, 0);
  const test::CommandResult r = test::run_command({PMDEC_PATH, pm_path, "-q", "-o", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Mesh a, b;
  ASSERT_TRUE(read_mesh(input, a).is_ok());
  ASSERT_TRUE(read_mesh(out, b).is_ok());
  expect_same_arrays(b, a);
  PmInfo info;
  ASSERT_TRUE(read_pm_info(test::read_file(pm_path), info).is_ok());
  EXPECT_TRUE(info.keeps_order);
}

TEST(PmdecStream, ACoarseLevelDecompressesOnlyTheChunksItNeeds) {
  Encoded e;
  encode_sample(e);
  PmInfo info;
  ASSERT_TRUE(read_pm_info(e.bytes, info).is_ok());
  ASSERT_GE(info.chunks.size(), 3u);
  // Damage the last chunk's payload: the coarse level never reads it, full detail does.
  std::string damaged = e.bytes;
  damaged[info.chunks[info.chunks.size() - 2].stream_end + 40] ^= 0x5A;
  const std::string path = e.dir.file("damaged.pm");
  test::write_file(path, damaged);
  const std::string faces = std::to_string(info.chunks.front().faces_after);
  const test::CommandResult coarse =
      test::run_command({PMDEC_PATH, path, "--faces", faces, "-o", e.dir.file("coarse.obj")});
  EXPECT_EQ(coarse.exit_code, 0) << coarse.err;
  EXPECT_EQ(test::load_simple_obj(e.dir.file("coarse.obj")).face_count(), info.chunks.front().faces_after);
  const test::CommandResult full = test::run_command({PMDEC_PATH, path, "-o", e.dir.file("full.obj")});
  EXPECT_EQ(full.exit_code, 4) << full.err;
}

}  // namespace
}  // namespace pm
