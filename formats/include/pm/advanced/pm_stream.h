// The .pm stream beyond reading and writing it (pm/pm_codec.h): pmenc's preset for the
// error bits of a quantized stream, and where a stream's bytes go (pmdec --info --sizes).
// Tools' and benchmarks' needs, not the codec's contract.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "pm/pm_codec.h"
#include "pm/status.h"

namespace pm {

// The error bits pmenc keeps with --quantize (WriteOptions::error_bits): at most 1/16 over
// the exact bound, 0.4% to 2.6% smaller 14-bit streams on the shared meshes.
inline constexpr int kQuantizedErrorBits = 5;

// Where a 2.x stream's bytes go, for `pmdec --info --sizes`: each section's bytes (its
// 24-byte header and zstd frame; the chunks summed), and the chunks' streams (pm-format.md
// §5.7) before zstd, summed over the chunks. The sections and the header add up to the
// stream's size.
struct PmSizes {
  uint64_t header = 0;  // 96
  std::vector<std::pair<std::string, uint64_t>> sections;       // tag, bytes, in stream order
  uint32_t chunks = 0;
  std::vector<std::pair<std::string, uint64_t>> chunk_streams;  // name, raw bytes (§5.7 order)
  // Each chunk's stream compressed alone (zstd level 19), summed: what it costs in the file,
  // about (the file compresses a chunk's streams together, in one frame).
  std::vector<uint64_t> chunk_streams_compressed;
};
// Decodes the whole stream first (the same checks and errors as read_pm); a 1.x stream is
// kUnsupportedVersion (its records are not chunked).
[[nodiscard]] Status measure_pm_sizes(std::string_view bytes, PmSizes& sizes, const ReadOptions& options = {});

}  // namespace pm
