// The .pm byte layout's pieces that both majors share (pm_layout.h; pm-format-1.md and
// pm-format.md §4): section headers, written and read, each section's zstd frame, checked
// before it is decompressed (RFC 8878 §3.1.1: its descriptor, content size and checksum),
// tag names, and the material strings (a varint length then UTF-8 bytes, §5.9 of 1.x, TABL
// in 2.x), with the writer's check of what they may hold.
#include "pm_layout.h"

#include <zstd.h>
#include <zstd_errors.h>

#include <cctype>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "byte_io.h"
#include "pm/pm_codec.h"

namespace pm {
namespace detail {

std::string tag_name(uint32_t tag) {
  static const char kHex[] = "0123456789abcdef";
  std::string name;
  for (int i = 0; i < 4; ++i) {
    const auto c = static_cast<unsigned char>(tag >> (8 * i));
    if (std::isalnum(c)) {
      name.push_back(static_cast<char>(c));
    } else {
      name += "\\x";
      name.push_back(kHex[c >> 4]);
      name.push_back(kHex[c & 15]);
    }
  }
  return name;
}

SectionWriter::SectionWriter() : context_(ZSTD_createCCtx()) {}

Status SectionWriter::append(uint32_t tag, uint32_t flags, std::string_view raw,
                             uint64_t declared_raw_size, int zstd_level, std::string& out) {
  ZSTD_CCtx* cctx = context_.get();
  if (!cctx) return Status(ErrorCode::kInternal, "zstd: cannot create a compression context");
  // Parameters are sticky: each is set again, in case the last section failed half-way.
  (void)ZSTD_CCtx_reset(cctx, ZSTD_reset_session_and_parameters);
  for (const auto& [parameter, value] :
       {std::pair{ZSTD_c_compressionLevel, zstd_level}, std::pair{ZSTD_c_checksumFlag, 1},
        std::pair{ZSTD_c_contentSizeFlag, 1}}) {
    const size_t result = ZSTD_CCtx_setParameter(cctx, parameter, value);
    if (ZSTD_isError(result)) {
      return Status(ErrorCode::kInvalidArgument, std::string("zstd: ") + ZSTD_getErrorName(result));
    }
  }
  // The frame straight after its header's place in `out`, the header written once the
  // frame's size is known: no buffer of its own to fill and copy. `out` is as it was on
  // failure.
  const std::size_t header_at = out.size(), frame_at = header_at + kSectionHeaderSize;
  out.resize(frame_at + ZSTD_compressBound(raw.size()));
  const size_t frame_size =
      ZSTD_compress2(cctx, out.data() + frame_at, out.size() - frame_at, raw.data(), raw.size());
  if (ZSTD_isError(frame_size)) {
    out.resize(header_at);
    return Status(ErrorCode::kInternal,
                  "section " + tag_name(tag) + ": zstd: " + ZSTD_getErrorName(frame_size));
  }
  out.resize(frame_at + frame_size);
  std::string header;
  ByteWriter writer(header);
  write_section_header({tag, flags, frame_size, declared_raw_size}, writer);
  out.replace(header_at, kSectionHeaderSize, header);
  return Status::ok();
}

Status append_section(uint32_t tag, uint32_t flags, std::string_view raw,
                      uint64_t declared_raw_size, int zstd_level, std::string& out) {
  return SectionWriter().append(tag, flags, raw, declared_raw_size, zstd_level, out);
}

// One zstd frame, exactly `frame.size()` bytes, with a content checksum and a content
// size equal to the section's raw size (§4.2), decompressed into `raw`.
Status decompress_frame(const std::string& where, std::string_view frame, uint64_t raw_size,
                        ZSTD_DCtx* dctx, std::string& raw) {
  uint32_t magic = 0;
  if (frame.size() >= 4) ByteReader(frame, where, ErrorCode::kCorruptStream).read_u32(magic);
  if (frame.size() < 5 || magic != ZSTD_MAGICNUMBER) {
    return Status(ErrorCode::kCorruptStream, where + ": payload is not a zstd frame");
  }
  // Frame_Header_Descriptor (RFC 8878 §3.1.1.1.1): bits 0-1 dictionary id size,
  // bit 2 content checksum.
  const auto descriptor = static_cast<uint8_t>(frame[4]);
  if ((descriptor & 0x04) == 0) {
    return Status(ErrorCode::kCorruptStream, where + ": zstd frame has no content checksum");
  }
  if ((descriptor & 0x03) != 0) {
    return Status(ErrorCode::kCorruptStream, where + ": zstd frame needs a dictionary");
  }
  const size_t frame_size = ZSTD_findFrameCompressedSize(frame.data(), frame.size());
  if (ZSTD_isError(frame_size)) {
    return Status(ErrorCode::kCorruptStream,
                  where + ": malformed zstd frame (" + ZSTD_getErrorName(frame_size) + ")");
  }
  if (frame_size != frame.size()) {
    return Status(
        ErrorCode::kCorruptStream,
        where + ": " + std::to_string(frame.size() - frame_size) + " bytes follow the zstd frame");
  }
  // RFC 8878 §3.1.1.1.4: Frame_Content_Size, which must be present and agree with the
  // section header, so that the buffer below is exactly what the frame decodes to.
  const unsigned long long content_size = ZSTD_getFrameContentSize(frame.data(), frame.size());
  if (content_size == ZSTD_CONTENTSIZE_UNKNOWN || content_size == ZSTD_CONTENTSIZE_ERROR) {
    return Status(ErrorCode::kCorruptStream, where + ": zstd frame does not state its size");
  }
  if (content_size != raw_size) {
    return Status(ErrorCode::kCorruptStream,
                  where + ": zstd frame holds " + std::to_string(content_size) +
                      " bytes, the section declares " + std::to_string(raw_size));
  }
  // The buffer keeps its capacity from section to section: read_pm reserved the largest.
  raw.resize(static_cast<std::size_t>(raw_size));
  // A single-pass decode into a buffer of raw_size bytes: zstd stops with an error rather
  // than write past it (dstSize_tooSmall), so no frame decodes beyond its declared size.
  const size_t result =
      ZSTD_decompressDCtx(dctx, raw.data(), raw.size(), frame.data(), frame.size());
  if (ZSTD_isError(result)) {
    if (ZSTD_getErrorCode(result) == ZSTD_error_checksum_wrong) {
      return Status(ErrorCode::kChecksumMismatch, where + ": content checksum mismatch");
    }
    return Status(ErrorCode::kCorruptStream, where + ": zstd: " + ZSTD_getErrorName(result));
  }
  if (result != raw_size) {
    return Status(ErrorCode::kCorruptStream, where + ": zstd frame decoded to " +
                                                 std::to_string(result) + " bytes, expected " +
                                                 std::to_string(raw_size));
  }
  return Status::ok();
}

bool is_valid_tag(uint32_t tag) {
  for (int i = 0; i < 4; ++i) {
    const auto c = static_cast<uint8_t>(tag >> (8 * i));
    if (!((c >= '0' && c <= '9') || (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'))) return false;
  }
  return true;
}

bool read_section_header(std::string_view bytes, SectionHeader& out) {
  if (bytes.size() < kSectionHeaderSize) return false;
  ByteReader fields(bytes.substr(0, kSectionHeaderSize), "section header", ErrorCode::kTruncatedStream);
  fields.read_u32(out.tag);  // cannot fail: all 24 bytes are there
  fields.read_u32(out.flags);
  fields.read_u64(out.stored_size);
  fields.read_u64(out.raw_size);
  return true;
}

void write_section_header(const SectionHeader& header, ByteWriter& out) {
  out.put_u32(header.tag);
  out.put_u32(header.flags);
  out.put_u64(header.stored_size);
  out.put_u64(header.raw_size);
}

std::string byte_count_text(uint64_t bytes) {
  std::string text = std::to_string(bytes) + " bytes";
  if (bytes >= (uint64_t{1} << 20)) {
    text += " (" + std::to_string((bytes + (uint64_t{1} << 19)) >> 20) + " MiB)";
  }
  return text;
}

void put_string(ByteWriter& out, const std::string& text) {
  out.put_varint(static_cast<uint32_t>(text.size()));
  out.put_bytes(text);
}

// Why a material string cannot be stored, or empty (§5.9).
std::string string_problem(std::string_view text) {
  if (text.size() > kMaxStringBytes) {
    return std::to_string(text.size()) + " bytes (at most " + std::to_string(kMaxStringBytes) + ")";
  }
  if (text.find('\0') != std::string_view::npos) return "a NUL character";
  return "";
}

// `count` strings; `budget` is what is left of the header's string bytes.
bool read_strings(ByteReader& in, uint32_t count, const char* what, uint64_t& budget,
                  std::vector<std::string>& strings) {
  strings.reserve(count);
  for (uint32_t i = 0; i < count; ++i) {
    uint32_t length;
    std::string_view text;
    if (!in.read_varint(length)) return false;
    if (length > budget) {
      return in.fail(ErrorCode::kCorruptStream, in.where() + ": " + what + " " + std::to_string(i) +
                                                    " has " + std::to_string(length) +
                                                    " bytes, more than the header's string bytes");
    }
    if (!in.read_bytes(length, text)) return false;
    if (const std::string problem = string_problem(text); !problem.empty()) {
      return in.fail(ErrorCode::kCorruptStream,
                     in.where() + ": " + what + " " + std::to_string(i) + ": " + problem);
    }
    budget -= length;
    strings.emplace_back(text);
  }
  return true;
}

Status check_material_strings_impl(const std::vector<std::string>& names,
                              const std::vector<std::string>& libraries) {
  for (const auto* strings : {&names, &libraries}) {
    const char* what = strings == &names ? "material name " : "material library ";
    if (strings->size() > kMaxMaterials) {
      return Status(ErrorCode::kResourceLimit, std::to_string(strings->size()) + " " + what +
                                                   "strings (at most " +
                                                   std::to_string(kMaxMaterials) + ")");
    }
    for (std::size_t i = 0; i < strings->size(); ++i) {
      const std::string problem = string_problem((*strings)[i]);
      if (problem.empty()) continue;
      // Too long is a limit (like a count); a NUL is a bad argument.
      const bool too_long = (*strings)[i].size() > kMaxStringBytes;
      return Status(too_long ? ErrorCode::kResourceLimit : ErrorCode::kInvalidArgument,
                    what + std::to_string(i) + ": " + problem);
    }
  }
  return Status::ok();
}

}  // namespace detail
}  // namespace pm
