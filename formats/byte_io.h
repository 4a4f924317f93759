// Little-endian byte reading and writing for the .pm codec, and the CRC-32 of its header.
// Internal to the library (not installed).
//
// ByteReader is bounds-checked: every read either succeeds or leaves the reader in an
// error state with a one-line Status, and never touches a byte past the end. Reads return
// bool so that tight decode loops stay short: `if (!in.read_u32(x)) return in.status();`.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <utility>

#include "pm/status.h"

namespace pm::detail {

// CRC-32/ISO-HDLC (the zlib / PNG CRC): reflected polynomial 0xEDB88320, initial value
// and final xor 0xFFFFFFFF. crc32("123456789") == 0xCBF43926.
inline constexpr std::array<uint32_t, 256> kCrc32Table = [] {
  std::array<uint32_t, 256> table{};
  for (uint32_t n = 0; n < 256; ++n) {
    uint32_t c = n;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    table[n] = c;
  }
  return table;
}();

inline uint32_t crc32(std::string_view bytes) {
  uint32_t c = 0xFFFFFFFFu;
  for (unsigned char byte : bytes) c = kCrc32Table[(c ^ byte) & 0xFF] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

// ZigZag (the mapping of Protocol Buffers' sint64): 0, -1, 1, -2, 2, ... -> 0, 1, 2, 3, 4, ...
// so that small differences of either sign become small unsigned values.
inline uint64_t zigzag(int64_t value) {
  return (static_cast<uint64_t>(value) << 1) ^ static_cast<uint64_t>(value >> 63);
}
inline int64_t unzigzag(uint64_t code) {
  return static_cast<int64_t>(code >> 1) ^ -static_cast<int64_t>(code & 1);
}

// LEB128 (unsigned): 7 bits per byte, least significant group first, high bit set on
// every byte but the last. A uint32 takes 1 to 5 bytes.
inline constexpr std::size_t kMaxVarintBytes = 5;

class ByteWriter {
 public:
  explicit ByteWriter(std::string& out) : out_(out) {}

  void put_u8(uint8_t value) { out_.push_back(static_cast<char>(value)); }
  void put_u16(uint16_t value) { put_le(value, 2); }
  void put_u32(uint32_t value) { put_le(value, 4); }
  void put_u64(uint64_t value) { put_le(value, 8); }
  // The IEEE-754 bit pattern, unchanged (NaN payloads and -0 survive a round trip).
  void put_f32(float value) {
    uint32_t bits;
    std::memcpy(&bits, &value, 4);
    put_u32(bits);
  }
  void put_varint(uint32_t value) {
    while (value >= 0x80) {
      put_u8(static_cast<uint8_t>(value | 0x80));
      value >>= 7;
    }
    put_u8(static_cast<uint8_t>(value));
  }
  void put_bytes(std::string_view bytes) { out_.append(bytes.data(), bytes.size()); }
  void put_zeros(std::size_t count) { out_.append(count, '\0'); }

 private:
  void put_le(uint64_t value, int size) {
    for (int i = 0; i < size; ++i) put_u8(static_cast<uint8_t>(value >> (8 * i)));
  }
  std::string& out_;
};

class ByteReader {
 public:
  // `where` names the data in messages ("header", "section BASE"). Running out of data is
  // `end_code`: kTruncatedStream for the file itself ("truncated in section BASE (need
  // 1200 bytes, 412 left)"), kCorruptStream inside a payload whose size was declared
  // ("section SPLT: data ends early (need 4 bytes, 2 left)").
  ByteReader(std::string_view bytes, std::string where, ErrorCode end_code)
      : bytes_(bytes), where_(std::move(where)), end_code_(end_code) {}

  std::size_t position() const { return position_; }
  std::size_t remaining() const { return bytes_.size() - position_; }
  bool at_end() const { return position_ == bytes_.size(); }
  const Status& status() const { return status_; }
  const std::string& where() const { return where_; }
  void set_where(std::string where) { where_ = std::move(where); }

  bool read_u8(uint8_t& value) {
    if (!need(1)) return false;
    value = static_cast<uint8_t>(bytes_[position_++]);
    return true;
  }
  bool read_u16(uint16_t& value) { return read_le(value); }
  bool read_u32(uint32_t& value) { return read_le(value); }
  bool read_u64(uint64_t& value) { return read_le(value); }
  bool read_f32(float& value) {
    uint32_t bits;
    if (!read_u32(bits)) return false;
    std::memcpy(&value, &bits, 4);
    return true;
  }
  // Rejects encodings longer than 5 bytes, values above 2^32 - 1 and overlong encodings
  // (a last byte of 0 after the first), so every value has exactly one encoding.
  bool read_varint(uint32_t& value) {
    uint32_t result = 0;
    for (std::size_t i = 0; i < kMaxVarintBytes; ++i) {
      uint8_t byte;
      if (!read_u8(byte)) return false;
      if (i == kMaxVarintBytes - 1 && byte > 0x0F) {
        return fail(
            ErrorCode::kCorruptStream,
            where_ + ": varint at offset " + std::to_string(position_ - 5) + " exceeds 32 bits");
      }
      result |= uint32_t{byte & 0x7Fu} << (7 * i);
      if ((byte & 0x80) == 0) {
        if (byte == 0 && i > 0) {
          return fail(ErrorCode::kCorruptStream,
                      where_ + ": overlong varint at offset " + std::to_string(position_ - i - 1));
        }
        value = result;
        return true;
      }
    }
    return false;  // unreachable: the fifth byte is at most 0x0F, so it ends the loop
  }
  // A view of the next `count` bytes (no copy).
  bool read_bytes(uint64_t count, std::string_view& out) {
    if (!need(count)) return false;
    out = bytes_.substr(position_, static_cast<std::size_t>(count));
    position_ += static_cast<std::size_t>(count);
    return true;
  }
  bool skip(uint64_t count) {
    std::string_view ignored;
    return read_bytes(count, ignored);
  }

  // Records an error found by the caller in what it read (keeps the first one).
  bool fail(ErrorCode code, std::string message) {
    if (status_.is_ok()) status_ = Status(code, std::move(message));
    return false;
  }

 private:
  bool need(uint64_t count) {
    if (!status_.is_ok()) return false;  // sticky: no reads after an error
    if (count <= remaining()) return true;
    const std::string sizes =
        "(need " + std::to_string(count) + " bytes, " + std::to_string(remaining()) + " left)";
    return fail(end_code_, end_code_ == ErrorCode::kTruncatedStream
                               ? "truncated in " + where_ + " " + sizes
                               : where_ + ": data ends early " + sizes);
  }
  template <typename T>
  bool read_le(T& value) {
    if (!need(sizeof(T))) return false;
    T result = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) {
      result |= static_cast<T>(static_cast<uint8_t>(bytes_[position_ + i])) << (8 * i);
    }
    position_ += sizeof(T);
    value = result;
    return true;
  }

  std::string_view bytes_;
  std::size_t position_ = 0;
  std::string where_;
  ErrorCode end_code_;
  Status status_;
};

}  // namespace pm::detail
