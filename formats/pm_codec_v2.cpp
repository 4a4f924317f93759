// The .pm stream of format 2.0: a fixed header with a CRC-32, then zstd-compressed
// sections: the base mesh and what every level shares (BASE, WELD, CARY, TABL), an index of
// the chunks (INDX), the vertex splits in chunks of a few thousand (CHNK), and what only
// full detail has (LOOS, ORDR). formats/pm-format.md is normative; section numbers in
// comments (§) refer to it.
//
// Progressive by construction (Hoppe 1996, §3, "progressive transmission"): a reader
// decodes the sections as they arrive, so a stream cut anywhere after the base mesh gives
// the finest level it holds whole, and a reader that wants a coarse level stops after the
// chunks that hold it.
//
// Compact: a split names vl and vr by their places in u's ring of faces, and its moved
// faces are those between them (split_fans.h; Hoppe 1998, "Efficient implementation of
// progressive meshes", §4); the new vertex's position is predicted by the mean of its
// neighbours in the refined mesh (the "Laplacian" prediction of Taubin, Guéziec, Horn and
// Lazarus 1998, "Progressive forest split compression", §5) and stored as the difference,
// in the order-preserving integers of the float bits (lossless) or on a quantization grid
// (Deering 1995, "Geometry compression", §4: uniform quantization over a bounding box).
// Each field is a stream of its own in the chunk, which zstd compresses better than
// interleaved records.
//
// 2.1 (§5.10) codes four of those streams with an adaptive binary range coder
// (range_coder.h) instead of leaving them to zstd: u as the gap from the previous u of its
// layer (the encoder orders each chunk in layers of independent splits, by u: Pajarola and
// Rossignac 2000, "Compressed progressive meshes", §3), vl and vr with models per ring size,
// and the position residuals with models per neighbourhood spread, on a grid in u's normal
// frame (the coordinate along the normal predicted from the other two): zstd sees bytes,
// not the distributions these fields have. 2.0 streams are still read (and written on request).
//
// The reader trusts nothing, as the 1.x reader: every count is capped, every section header
// is checked before its payload is decompressed, the memory a decode needs is computed from
// checked numbers before it is allocated, and the decoded mesh goes through validate()
// (less its replay of the moved faces, which decoding did: validate_decoded.h).
//
// This file drives the stream: write_pm_v2 chooses the grids and decimals, has each section
// written and compresses them; PmStreamReader takes bytes as they come and hands each section
// to its reader. The parts of the stream are in formats/v2/, each file with the writer's and
// the reader's halves side by side: header.cpp (header, section order and bounds, index,
// read_pm_info), base_mesh.cpp (BASE, WELD, CARY, LOOS, ORDR), tables.cpp (TABL, the wedge
// coders' start), chunks.cpp (CHNK), positions.cpp and positions.h (grids, decimals,
// predictions); format.h is the vocabulary they share, writer.h and reader.h the two sides.
#include <zstd.h>

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstring>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <new>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

#include "byte_io.h"
#include "core/in_turn.h"
#include "core/no_throw.h"
#include "levels/validate_decoded.h"
#include "pm/advanced/pm_stream.h"
#include "pm/pm_codec.h"
#include "pm_layout.h"
#include "split_fans.h"
#include "v2/format.h"
#include "v2/positions.h"
#include "v2/reader.h"
#include "v2/writer.h"

namespace pm::detail::v2 {
namespace {

Status check_writable_v2(const ProgressiveMesh& pm, const WriteOptions& options) {
  for (const auto& [count, what] :
       {std::pair{uint64_t{pm.base_vertex_count}, "base vertices"},
        {pm.base_face_count(), "base faces"}, {pm.splits.size(), "splits"},
        {uint64_t{pm.loose_vertex_count}, "loose vertices"}, {pm.welds.size(), "welds"},
        {pm.carried_faces.size() / 3, "carried faces"}, {pm.moved_faces.size(), "moved faces"},
        {pm.uv_count(), "texture coordinates"}, {pm.normal_count(), "normals"}}) {
    if (count > kMaxCount) {
      return Status(ErrorCode::kResourceLimit, std::to_string(count) + " " + what +
                                                   " (the format holds at most " +
                                                   std::to_string(kMaxCount) + ")");
    }
  }
  if (Status status = check_material_strings_impl(pm.material_names, pm.material_libraries); !status) {
    return status;
  }
  if (options.zstd_level < 1 || options.zstd_level > ZSTD_maxCLevel()) {
    return Status(ErrorCode::kInvalidArgument, "zstd level " + std::to_string(options.zstd_level) +
                                                   " is outside 1.." + std::to_string(ZSTD_maxCLevel()));
  }
  for (const auto& [bits, what] : {std::pair{options.position_bits, "position"},
                                   {options.uv_bits, "texture coordinate"},
                                   {options.normal_bits, "normal"}}) {
    if (!valid_bits(static_cast<uint32_t>(bits)) || bits < 0) {
      return Status(ErrorCode::kInvalidArgument, std::string(what) + " quantization of " +
                                                     std::to_string(bits) +
                                                     " bits (0 for none, or 4 to 24)");
    }
  }
  if (options.error_bits < 0 || options.error_bits > 24) {
    return Status(ErrorCode::kInvalidArgument, "errors of " + std::to_string(options.error_bits) +
                                                   " significant bits (0 for every bit, or 1 to 24)");
  }
  if (options.minor_version > kNewestMinor) {
    return Status(ErrorCode::kInvalidArgument, "format 2." + std::to_string(options.minor_version) +
                                                   " (this writer writes 2.0 to 2.4)");
  }
  if (options.chunk_splits < 1 || options.chunk_splits > (1u << 20)) {
    return Status(ErrorCode::kInvalidArgument, "chunks of " + std::to_string(options.chunk_splits) +
                                                   " splits (1 to 1048576)");
  }
  return Status::ok();
}

// The writer's sections compressed as they are made (write_pm_v2): `threads - 1` helper
// threads take each section as soon as it is added, and the caller joins them in finish()
// for those left. Each section is one zstd frame of its own (pm_layout.h, append_section),
// so the stream does not depend on which thread compressed what.
class SectionCompressor {
 public:
  SectionCompressor(std::size_t slots, unsigned threads, int zstd_level)
      : raws_(slots), tags_(slots, 0), compressed_(slots), statuses_(slots), level_(zstd_level) {
    // No more threads to be had: those started, and finish() on the caller's, do the rest.
    if (threads > 1) start_threads(helpers_, threads - 1, [this] { work(); });
  }
  SectionCompressor(const SectionCompressor&) = delete;
  SectionCompressor& operator=(const SectionCompressor&) = delete;
  // On an exception in the caller (out of memory): the helpers stop with what they have.
  ~SectionCompressor() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      queue_.clear();
      done_ = true;
    }
    ready_.notify_all();
    for (std::thread& helper : helpers_) helper.join();
  }

  void add(std::size_t slot, uint32_t tag, std::string raw) {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      tags_[slot] = tag;
      raws_[slot] = std::move(raw);
      queue_.push_back(slot);
    }
    ready_.notify_one();
  }

  // Compresses the rest here, waits for the helpers, then appends the first `count`
  // sections to `out` in their order; the first failure instead.
  Status finish(std::size_t count, std::string& out) {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      done_ = true;
    }
    ready_.notify_all();
    work();
    for (std::thread& helper : helpers_) helper.join();
    helpers_.clear();
    if (failure_) std::rethrow_exception(failure_);
    for (std::size_t i = 0; i < count; ++i) {
      if (!statuses_[i]) return statuses_[i];
      out += compressed_[i];
      std::string().swap(compressed_[i]);
    }
    return Status::ok();
  }

 private:
  void work() {
    SectionWriter writer;  // this thread's zstd context, for every section it takes
    for (;;) {
      std::size_t slot = 0;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        ready_.wait(lock, [&] { return !queue_.empty() || done_; });
        if (queue_.empty()) return;
        slot = queue_.front();
        queue_.pop_front();
      }
      try {
        const std::string& raw = raws_[slot];
        statuses_[slot] =
            writer.append(tags_[slot], kSectionRequired, raw, raw.size(), level_, compressed_[slot]);
        std::string().swap(raws_[slot]);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(mutex_);
        if (!failure_) failure_ = std::current_exception();
        queue_.clear();
      }
    }
  }

  std::vector<std::string> raws_;
  std::vector<uint32_t> tags_;
  std::vector<std::string> compressed_;
  std::vector<Status> statuses_;
  const int level_;
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<std::size_t> queue_;
  bool done_ = false;
  std::exception_ptr failure_;
  std::vector<std::thread> helpers_;
};

Status write_pm_v2(const ProgressiveMesh& pm, const WriteOptions& options, std::string& bytes) {
  if (Status valid = validate(pm); !valid) {
    return Status(ErrorCode::kInvalidArgument,
                  "cannot write an invalid progressive mesh: " + valid.message());
  }
  if (Status status = check_writable_v2(pm, options); !status) return status;
  Writer w(pm, options);
  Header2& h = w.h;
  h.base_vertex_count = pm.base_vertex_count;
  h.base_face_count = static_cast<uint32_t>(pm.base_face_count());
  h.split_count = static_cast<uint32_t>(pm.splits.size());
  h.loose_vertex_count = pm.loose_vertex_count;
  h.weld_count = static_cast<uint32_t>(pm.welds.size());
  h.carried_face_count = static_cast<uint32_t>(pm.carried_faces.size() / 3);
  h.moved_face_count = static_cast<uint32_t>(pm.moved_faces.size());
  for (const VertexSplit& split : pm.splits) h.split_face_count += split.new_face_count();
  h.chunk_count = static_cast<uint32_t>(plan_chunks(h.split_count, options.chunk_splits).size());
  h.minor = options.minor_version;
  if (h.minor >= 2) w.plan_tables();
  h.max_error = w.error_before(0);
  h.attributes = (pm.has_uvs() ? kAttributeUvIds : 0) | (pm.has_normals() ? kAttributeNormalIds : 0) |
                 (pm.has_materials() ? kAttributeMaterialIds : 0);
  h.options = pm.keeps_order() ? kOptionKeepsOrder : 0;
  h.color_components = pm.color_components;
  h.uv_count = static_cast<uint32_t>(pm.uv_count());
  h.normal_count = static_cast<uint32_t>(pm.normal_count());
  h.material_count = static_cast<uint32_t>(pm.material_names.size());
  h.material_library_count = static_cast<uint32_t>(pm.material_libraries.size());
  for (const auto* strings : {&pm.material_names, &pm.material_libraries}) {
    for (const std::string& text : *strings) h.material_string_bytes += static_cast<uint32_t>(text.size());
  }
  // Quantization (§5.3): the grids first, so that every value is known on its grid.
  const auto grid_of = [](const std::vector<float>& values, std::size_t components, int bits,
                          Grid& grid, const char* what) {
    if (bits == 0) return Status::ok();
    if (!make_grid(values.data(), values.size() / components, components, bits, grid)) {
      return Status(ErrorCode::kInvalidArgument, std::string("cannot quantize ") + what +
                                                     " that are not finite numbers");
    }
    return Status::ok();
  };
  if (Status s = grid_of(pm.positions, 3, options.position_bits, w.position_grid, "positions"); !s) return s;
  if (Status s = grid_of(pm.uvs, 2, options.uv_bits, w.uv_grid, "texture coordinates"); !s) return s;
  if (Status s = grid_of(pm.normals, 3, options.normal_bits, w.normal_grid, "normals"); !s) return s;
  h.position_bits = static_cast<uint8_t>(options.position_bits);
  // 2.3, lossless (§5.3): the positions on their decimal grid, or as significant decimals,
  // when they are such decimals: whichever is the coarser where most of them lie (fixed
  // places, "-0.037830", make a grid; "%g" makes significant digits: fandisk's "15.3644" and
  // "1e-06" would need a grid of 10^-6 steps, 40.3 KB as significant decimals against 47.6).
  double grid_gain = 0, significant_gain = 0;
  const bool lossless = options.position_bits == 0 && h.minor >= 3;
  Grid decimal_grid;
  SignificantDecimals significant;
  std::vector<uint32_t> significant_units;
  const bool gridded = lossless && make_decimal_grid(pm.positions.data(), pm.positions.size() / 3, 3,
                                                     decimal_grid, grid_gain);
  const bool numbered =
      lossless && make_significant_decimals(pm.positions.data(), pm.positions.size(), significant,
                                            significant_units, significant_gain);
  if (gridded && !(numbered && significant_gain > grid_gain)) {
    w.position_grid = std::move(decimal_grid);
    h.position_bits = static_cast<uint8_t>(w.position_grid.bits);
    h.options |= kOptionDecimalPositions;
  } else if (numbered) {
    w.significant = significant;
  }
  h.uv_bits = static_cast<uint8_t>(pm.uvs.empty() ? 0 : options.uv_bits);
  h.normal_bits = static_cast<uint8_t>(pm.normals.empty() ? 0 : options.normal_bits);
  if (pm.uvs.empty()) w.uv_grid.bits = 0;
  if (pm.normals.empty()) w.normal_grid.bits = 0;
  // 2.3, lossless tables (§5.4): as significant decimals when they are.
  for (int kind = 0; kind < 2 && h.minor >= 3; ++kind) {
    const std::vector<float>& values = mesh_table(pm, kind);
    double gain = 0;
    if (h.table_bits(kind) == 0 && !values.empty() &&
        make_significant_decimals(values.data(), values.size(), w.table_significant[kind],
                                  w.table_numbers[kind], gain)) {
      h.options |= significant_table_option(kind);
    }
  }
  w.positions.components = 3;
  w.positions.grid = h.position_bits != 0 ? &w.position_grid : nullptr;
  if (w.significant.digits != 0) {
    h.options |= kOptionSignificantPositions;
    w.positions.significant = &w.significant;
    w.positions.mean_of_values = h.minor >= 4;  // 2.4 (§5.3)
    w.positions.units = std::move(significant_units);
  } else {
    w.positions.units.resize(pm.positions.size());
    for (std::size_t i = 0; i < pm.positions.size(); ++i) {
      w.positions.units[i] = w.positions.from_float(pm.positions[i], i % 3);
    }
  }
  w.colors.components = pm.color_components;
  w.colors.units.resize(pm.colors.size());
  for (std::size_t i = 0; i < pm.colors.size(); ++i) w.colors.units[i] = ordered_from_float(pm.colors[i]);

  // Each section compressed on its own (zstd at level 18 is the writer's largest cost after
  // the chunks' sequential replay of the fans), on other threads while the next sections
  // are made; the bytes are the same for any number of threads.
  const std::vector<uint32_t> tags = expected_sections(h);
  SectionCompressor compressor(tags.size() + h.chunk_count, thread_count(options.threads),
                               options.zstd_level);
  std::size_t slot = 0;
  for (uint32_t tag : tags) {
    if (tag == kTagBase) compressor.add(slot++, tag, w.base());
    if (tag == kTagWelds) compressor.add(slot++, tag, w.welds());
    if (tag == kTagCarried) compressor.add(slot++, tag, w.carried());
    if (tag == kTagTables) compressor.add(slot++, tag, w.tables());
    if (tag == kTagIndex) {
      // INDX precedes its chunks in the stream but is complete only after the last one.
      const std::size_t index_slot = slot++;
      std::string index;
      w.chunks([&](std::string&& chunk) { compressor.add(slot++, kTagChunk, std::move(chunk)); },
               index);
      compressor.add(index_slot, tag, std::move(index));
    }
    if (tag == kTagLoose) compressor.add(slot++, tag, w.loose());
    if (tag == kTagOrder) compressor.add(slot++, tag, w.order());
  }
  std::string out;
  append_header2(h, out);
  if (Status s = compressor.finish(slot, out); !s) return s;
  bytes = std::move(out);
  return Status::ok();
}

}  // namespace
}  // namespace pm::detail::v2

namespace pm {

Status PmStreamReader::State::process(std::string_view bytes, std::size_t& used) {
  used = 0;
  while (true) {
    const std::string_view rest = bytes.substr(used);
    if (stage == kHeader) {
      // The magic is checked as soon as its bytes arrive: a stream that is not one fails
      // at once, not when 96 bytes have come.
      const std::size_t magic = std::min(rest.size(), sizeof kMagic);
      if (std::memcmp(rest.data(), kMagic, magic) != 0) return corrupt("not a .pm stream (bad magic)");
      if (rest.size() < 12) return Status::ok();
      const uint16_t major = static_cast<uint16_t>(static_cast<uint8_t>(rest[8]) |
                                                   static_cast<uint8_t>(rest[9]) << 8);
      if (major != kMajor2) {
        stage = kVersion1;  // decoded whole, at finish()
        continue;
      }
      if (rest.size() < kHeaderSize) return Status::ok();
      if (Status s = start(rest); !s) return s;
      used += kHeaderSize;
      continue;
    }
    if (stage == kVersion1) return Status::ok();  // nothing used: finish() reads it all
    if (stage == kDone) {
      // Only optional sections of other tools may follow the last known one (§4.3).
      SectionHeader section;
      if (rest.empty() || stopped || !read_section_header(rest, section)) return Status::ok();
      if (!is_valid_tag(section.tag) || is_v2_tag(section.tag) ||
          (section.flags & kSectionRequired) != 0) {
        return corrupt(std::to_string(rest.size()) + " bytes follow the last section");
      }
      if (rest.size() - kSectionHeaderSize < section.stored_size) return Status::ok();
      used += kSectionHeaderSize + static_cast<std::size_t>(section.stored_size);
      continue;
    }
    // A reader that has the splits it wants stops before the next chunk.
    if (expected[next] == kTagChunk && pm.splits.size() >= options.max_splits) {
      stage = kDone;
      stopped = true;
      raw = std::string();
      fans = SplitFans();
      continue;
    }
    // A section: its 24-byte header, then its frame.
    SectionHeader section;
    if (!read_section_header(rest, section)) return Status::ok();
    const uint32_t tag = section.tag, flags = section.flags;
    const uint64_t stored = section.stored_size, raw_size = section.raw_size;
    if (!is_valid_tag(tag)) return corrupt("section header: bad tag " + tag_name(tag));
    if (!is_v2_tag(tag)) {
      if ((flags & kSectionRequired) != 0) {
        return Status(h.minor > kNewestMinor ? ErrorCode::kUnsupportedVersion : ErrorCode::kCorruptStream,
                      "section " + tag_name(tag) + ": required, and unknown to this reader");
      }
      if (rest.size() - kSectionHeaderSize < stored) return Status::ok();  // wait, then skip
      used += kSectionHeaderSize + static_cast<std::size_t>(stored);
      continue;
    }
    if (Status s = check_section(tag, flags, stored, raw_size); !s) return s;
    if (rest.size() - kSectionHeaderSize < stored) return Status::ok();  // the frame has not arrived
    const std::string where = section_name(tag, chunks_decoded);
    if (Status s = decompress_frame(where, rest.substr(kSectionHeaderSize, stored), raw_size,
                                    dctx.get(), raw);
        !s) {
      return s;
    }
    ByteReader payload(raw, where, ErrorCode::kCorruptStream);
    if (Status s = decode(tag, payload); !s) return s;
    if (!payload.at_end()) {
      return corrupt(where + ": " + std::to_string(payload.remaining()) + " bytes left over");
    }
    used += kSectionHeaderSize + static_cast<std::size_t>(stored);
    ++next;
    if (next < expected.size() && expected[next] == kTagChunk && !base_done) base_done = true;
    if (next == expected.size()) {
      stage = kDone;
      base_done = true;
    } else if (tag == kTagChunk && pm.splits.size() >= options.max_splits &&
               expected[next] == kTagChunk) {
      // Stopped before the next chunk. After the last one, the sections of full detail
      // (the loose vertices, the input's order) are read: every split means full detail.
      stage = kDone;
      stopped = true;
    }
    if (stage == kDone) {
      raw = std::string();
      fans = SplitFans();
    }
  }
}

Status PmStreamReader::State::decode(uint32_t tag, ByteReader& in) {
  detach_carried();
  bool ok = true;
  if (tag == kTagBase) ok = decode_base(in);
  if (tag == kTagWelds) ok = decode_welds(in);
  if (tag == kTagCarried) ok = decode_carried(in);
  if (tag == kTagTables) ok = decode_tables(in);
  if (tag == kTagIndex) ok = decode_index(in);
  if (tag == kTagChunk) ok = decode_chunk(in);
  if (tag == kTagLoose) ok = decode_loose(in);
  if (tag == kTagOrder) ok = decode_order(in);
  return ok ? Status::ok() : in.status();
}

PmStreamReader::PmStreamReader(const ReadOptions& options) : state_(new State) {
  state_->options = options;
}
PmStreamReader::~PmStreamReader() { delete state_; }
PmStreamReader::PmStreamReader(PmStreamReader&& other) noexcept : state_(other.state_) {
  other.state_ = nullptr;
}
PmStreamReader& PmStreamReader::operator=(PmStreamReader&& other) noexcept {
  if (this != &other) {
    delete state_;
    state_ = other.state_;
    other.state_ = nullptr;
  }
  return *this;
}

Status PmStreamReader::append(std::string_view bytes) {
  State& s = *state_;
  if (!s.status) return s.status;
  try {
    std::size_t used = 0;
    Status status;
    if (s.buffer.empty()) {
      status = s.process(bytes, used);
      if (status && used < bytes.size() && !(s.stage == State::kDone && s.stopped)) {
        s.buffer.assign(bytes.substr(used));
      }
      s.consumed += used;
    } else {
      s.buffer.append(bytes);
      status = s.process(s.buffer, used);
      s.buffer.erase(0, used);
      s.consumed += used;
      if (s.stage == State::kDone && s.stopped) s.buffer = std::string();
    }
    if (!status) return s.fail(status);
  } catch (const std::bad_alloc&) {
    return s.fail(Status(ErrorCode::kResourceLimit, "out of memory"));
  }
  return Status::ok();
}

Status PmStreamReader::finish(ReadResult* result) {
  State& s = *state_;
  try {
    return s.finish(result);
  } catch (const std::bad_alloc&) {
    return s.fail(Status(ErrorCode::kResourceLimit, "out of memory"));
  }
}

Status PmStreamReader::State::finish(ReadResult* result) {
  State& s = *this;
  if (!s.status) return s.status;
  ReadResult r;
  const bool version1 = s.stage == State::kVersion1;
  if (version1) {
    // A 1.x stream is decoded whole: its sections are not chunks.
    ProgressiveMesh pm;
    if (Status status = read_pm_v1(s.buffer, pm, s.options); !status) return s.fail(status);
    s.pm = std::move(pm);
    s.stage = State::kDone;
    s.base_done = true;
    s.buffer = std::string();
  } else if (s.stage == State::kDone && !s.stopped && !s.buffer.empty()) {
    return s.fail(corrupt(std::to_string(s.buffer.size()) + " bytes follow the last section"));
  } else if (s.stage != State::kDone) {
    const std::string where = s.stage == State::kHeader
                                  ? "the header"
                                  : section_name(s.expected[s.next], s.chunks_decoded);
    const std::string message = "truncated in " + where + " (the stream ends at byte " +
                                std::to_string(s.consumed + s.buffer.size()) + ")";
    if (!s.options.allow_truncated || !s.base_done) {
      return s.fail(Status(ErrorCode::kTruncatedStream, message));
    }
    r.truncated = true;
    r.warning = message + ": decoded " + std::to_string(s.pm.splits.size()) + " of " +
                std::to_string(s.h.split_count) + " splits";
    s.stage = State::kDone;
    s.buffer = std::string();
    s.fans = SplitFans();
  }
  s.attach_carried();
  if (!version1) {
    r.partial = s.pm.splits.size() < s.h.split_count;
    if (r.partial && s.has_unknown_entries()) {
      s.drop_unknown_entries(s.pm);
      s.wedges_ready = false;  // the coders' ids are the stream's: no more of this
    }
    r.chunks_decoded = static_cast<uint32_t>(s.chunks_decoded);
    r.chunk_count = s.h.chunk_count;
  }
  // A 2.x stream's splits were replayed as they were decoded: validate() less its own replay.
  std::string message;
  bool valid = false;
  if (version1) {
    const Status checked = validate(s.pm);
    valid = checked.is_ok();
    message = checked.message();
  } else {
    valid = detail::validate_decoded(s.pm, &message);
  }
  if (!valid) return s.fail(corrupt(message));
  if (result != nullptr) *result = r;
  s.finished = true;
  return Status::ok();
}

Status PmStreamReader::take(ProgressiveMesh& out) {
  State& s = *state_;
  if (!s.status) return s.status;
  if (!s.finished) {
    return Status(ErrorCode::kInvalidArgument, "the stream is not finished: call finish() first");
  }
  out = std::move(s.pm);
  s.pm = ProgressiveMesh();
  s.trimmed = ProgressiveMesh();
  s.taken = true;
  s.status = Status(ErrorCode::kInvalidArgument, "the decoded mesh was taken");
  return Status::ok();
}

bool PmStreamReader::has_base() const { return state_->base_done; }
bool PmStreamReader::complete() const {
  return state_->stage == State::kDone && !state_->stopped;
}
const ProgressiveMesh& PmStreamReader::mesh() const {
  State& s = *state_;
  if (s.taken) return s.pm;  // empty
  s.attach_carried();
  // 2.2 (§7): in the middle of a stream, entries that later splits introduce have no value
  // yet (0 in s.pm, which decoding goes on filling): the caller gets a copy without them,
  // as finish() leaves a prefix.
  // Once per decoded chunk: mesh() is asked for several times for one level.
  if (s.has_unknown_entries()) {
    if (s.trimmed_chunks != s.chunks_decoded) {
      s.trimmed = s.pm;
      s.drop_unknown_entries(s.trimmed);
      s.trimmed_chunks = s.chunks_decoded;
    }
    return s.trimmed;
  }
  return s.pm;
}
uint64_t PmStreamReader::decoded_face_count() const {
  return state_->stage == State::kVersion1 ? 0 : state_->decoded_faces;
}
uint64_t PmStreamReader::stream_face_count() const {
  return state_->stage == State::kHeader ? 0 : state_->h.faces();
}

// ---------------------------------------------------------------------------------------
// The entry points: 2.0 is written; both majors are read.

Status check_material_strings(const std::vector<std::string>& names,
                              const std::vector<std::string>& libraries) {
  return detail::no_throw([&] { return check_material_strings_impl(names, libraries); });
}

Status write_pm(const ProgressiveMesh& pm, const WriteOptions& options, std::string& bytes) {
  return detail::no_throw([&] { return write_pm_v2(pm, options, bytes); });
}

Status read_pm(std::string_view bytes, ProgressiveMesh& pm, const ReadOptions& options,
               ReadResult* result) {
  return detail::no_throw([&] {
    PmStreamReader reader(options);
    if (Status status = reader.append(bytes); !status) return status;
    if (Status status = reader.finish(result); !status) return status;
    return reader.take(pm);
  });
}
Status read_pm(std::string_view bytes, ProgressiveMesh& pm, const ReadOptions& options) {
  return read_pm(bytes, pm, options, nullptr);
}
Status read_pm(std::string_view bytes, ProgressiveMesh& pm) {
  return read_pm(bytes, pm, ReadOptions{}, nullptr);
}

namespace {

Status measure_sizes(std::string_view bytes, PmSizes& sizes, const ReadOptions& options) {
  ProgressiveMesh pm;
  if (Status status = read_pm(bytes, pm, options, nullptr); !status) return status;
  if ((static_cast<uint8_t>(bytes[8]) | static_cast<uint8_t>(bytes[9]) << 8) != kMajor2) {
    return Status(ErrorCode::kUnsupportedVersion, "sizes are measured in 2.x streams (this is 1.x)");
  }
  PmSizes r;
  r.header = kHeaderSize;
  for (int k = 0; k < kChunkStreams; ++k) r.chunk_streams.emplace_back(kStreamNames[k], 0);
  r.chunk_streams_compressed.assign(kChunkStreams, 0);
  std::unique_ptr<ZSTD_DCtx, size_t (*)(ZSTD_DCtx*)> dctx(ZSTD_createDCtx(), ZSTD_freeDCtx);
  if (!dctx) return Status(ErrorCode::kInternal, "zstd: cannot create a decompression context");
  std::string raw;
  // read_pm accepted the stream: every section header and frame is whole and valid.
  for (std::size_t offset = kHeaderSize; offset < bytes.size();) {
    SectionHeader section;
    if (!read_section_header(bytes.substr(offset), section)) break;
    const uint64_t size = kSectionHeaderSize + section.stored_size;
    const std::string tag = tag_name(section.tag);
    if (!r.sections.empty() && r.sections.back().first == tag) {
      r.sections.back().second += size;
    } else {
      r.sections.emplace_back(tag, size);
    }
    if (section.tag == kTagChunk) {
      ++r.chunks;
      const std::string where = section_name(section.tag, r.chunks - 1);
      if (Status s = decompress_frame(where, bytes.substr(offset + kSectionHeaderSize, section.stored_size),
                                      section.raw_size, dctx.get(), raw);
          !s) {
        return s;
      }
      ByteReader in(raw, where, ErrorCode::kCorruptStream);
      uint64_t lengths[kChunkStreams];
      for (int k = 0; k < kChunkStreams; ++k) {
        if (!read_varint64(in, lengths[k])) return in.status();
        r.chunk_streams[k].second += lengths[k];
      }
      for (int k = 0; k < kChunkStreams; ++k) {
        std::string_view stream;
        if (!in.read_bytes(lengths[k], stream)) return in.status();
        if (stream.empty()) continue;
        std::string packed(ZSTD_compressBound(stream.size()), '\0');
        const std::size_t n = ZSTD_compress(packed.data(), packed.size(), stream.data(), stream.size(), 19);
        if (ZSTD_isError(n)) return Status(ErrorCode::kInternal, std::string("zstd: ") + ZSTD_getErrorName(n));
        r.chunk_streams_compressed[k] += n;
      }
    }
    offset += size;
  }
  sizes = std::move(r);
  return Status::ok();
}

}  // namespace

Status measure_pm_sizes(std::string_view bytes, PmSizes& sizes, const ReadOptions& options) {
  return detail::no_throw([&] { return measure_sizes(bytes, sizes, options); });
}

}  // namespace pm
