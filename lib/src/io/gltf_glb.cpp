// The GLB container: glTF 2.0 specification, Khronos 2017/2021, §4.4 (4.4.1 header, 4.4.2
// chunks). Lengths are 32-bit little-endian; every one is checked against the bytes there are,
// in 64-bit arithmetic, before a chunk is looked at.
#include "io/gltf_glb.h"

#include <cstdint>
#include <cstring>

namespace pm::detail {
namespace {

constexpr uint32_t kGlbMagic = 0x46546C67;      // "glTF"
constexpr uint32_t kChunkJson = 0x4E4F534A;     // "JSON"
constexpr uint32_t kChunkBinary = 0x004E4942;   // "BIN\0"
constexpr std::size_t kHeaderBytes = 12;
constexpr std::size_t kChunkHeaderBytes = 8;

uint32_t read_u32(const char* p) {
  const auto* b = reinterpret_cast<const unsigned char*>(p);
  return uint32_t{b[0]} | uint32_t{b[1]} << 8 | uint32_t{b[2]} << 16 | uint32_t{b[3]} << 24;
}

void append_u32(std::string& out, uint32_t value) {
  for (int shift = 0; shift < 32; shift += 8) out.push_back(static_cast<char>(value >> shift));
}

Status glb_error(const std::string& message) {
  return Status(ErrorCode::kParseError, "glb: " + message);
}

}  // namespace

bool is_glb(std::string_view bytes) {
  return bytes.size() >= 4 && read_u32(bytes.data()) == kGlbMagic;
}

Status split_glb(std::string_view bytes, GlbChunks& chunks) {
  chunks = GlbChunks();
  if (bytes.size() < kHeaderBytes) return glb_error("header cut short (" + std::to_string(bytes.size()) + " bytes)");
  if (read_u32(bytes.data()) != kGlbMagic) return glb_error("no 'glTF' magic");
  const uint32_t version = read_u32(bytes.data() + 4);
  // Version 1 is binary glTF 1.0 (another layout): refused by name, as a .gltf of 1.0 is.
  if (version == 1)
    return Status(ErrorCode::kUnsupportedFormat, "glb: version 1 (glTF 1.0) is not supported (pm reads glTF 2.0)");
  if (version != 2) return glb_error("version " + std::to_string(version) + ", not 2");
  const uint64_t length = read_u32(bytes.data() + 8);
  if (length > bytes.size())
    return glb_error("header says " + std::to_string(length) + " bytes, the file has " +
                     std::to_string(bytes.size()));
  if (length < kHeaderBytes) return glb_error("header length " + std::to_string(length) + " is too small");
  chunks.whole = bytes.substr(0, length);
  chunks.trailing = bytes.size() - length;
  uint64_t at = kHeaderBytes;
  for (int index = 0; at < length; ++index) {
    if (at + kChunkHeaderBytes > length) return glb_error("chunk " + std::to_string(index) + " header cut short");
    const uint64_t chunk_length = read_u32(bytes.data() + at);
    const uint32_t type = read_u32(bytes.data() + at + 4);
    const uint64_t data = at + kChunkHeaderBytes;
    if (data + chunk_length > length)
      return glb_error("chunk " + std::to_string(index) + " of " + std::to_string(chunk_length) +
                       " bytes ends past the file (" + std::to_string(length) + " bytes)");
    const std::string_view content = bytes.substr(data, chunk_length);
    if (index == 0) {
      if (type != kChunkJson) return glb_error("the first chunk is not JSON");
      chunks.json = content;
    } else if (type == kChunkBinary) {
      if (index != 1) return glb_error("a BIN chunk after the second");
      chunks.binary = content;
      chunks.has_binary = true;
    }  // other chunk types: ignored, as §4.4.3 allows
    at = data + chunk_length;
    at += (4 - at % 4) % 4;  // chunks start on 4-byte boundaries
  }
  if (chunks.json.empty()) return glb_error("no JSON chunk");
  return Status::ok();
}

std::string make_glb(std::string_view json, std::string_view binary) {
  const std::size_t json_padded = (json.size() + 3) / 4 * 4;
  const std::size_t binary_padded = (binary.size() + 3) / 4 * 4;
  const std::size_t length = kHeaderBytes + kChunkHeaderBytes + json_padded +
                             (binary.empty() ? 0 : kChunkHeaderBytes + binary_padded);
  std::string out;
  out.reserve(length);
  append_u32(out, kGlbMagic);
  append_u32(out, 2);
  append_u32(out, static_cast<uint32_t>(length));
  append_u32(out, static_cast<uint32_t>(json_padded));
  append_u32(out, kChunkJson);
  out.append(json);
  out.append(json_padded - json.size(), ' ');
  if (!binary.empty()) {
    append_u32(out, static_cast<uint32_t>(binary_padded));
    append_u32(out, kChunkBinary);
    out.append(binary);
    out.append(binary_padded - binary.size(), '\0');
  }
  return out;
}

}  // namespace pm::detail
