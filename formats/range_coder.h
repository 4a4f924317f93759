// A binary adaptive range coder for the 2.1 chunk streams (pm-format.md §5.10). Internal to
// the codec.
//
// Range coding (Martin 1979, "Range encoding: an algorithm for removing redundancy from a
// digitised message"; arithmetic coding as in Witten, Neal and Cleary 1987, "Arithmetic
// coding for data compression") of binary decisions, each with an adaptive probability that
// moves 1/32 of the way towards each bit it codes, as the context-adaptive binary coder of
// H.264 adapts its states (Marpe, Schwarz and Wiegand 2003, "Context-based adaptive binary
// arithmetic coding in the H.264/AVC video compression standard", §III: binarization, then
// context modelling, then adaptive binary arithmetic coding). The arithmetic is LZMA's: a
// 32-bit range, 11-bit probabilities, a carry propagated through a pending byte and a run of
// 0xFF bytes. Integers are binarized as exp-Golomb codes (a unary bit length, then the bits
// below the top one), or as fixed-width binary trees when their range is small.
//
// The decoder trusts nothing: reading past the end of its bytes sets a flag (the caller
// reports kCorruptStream) and yields zeros, so a hostile stream ends in a bounded number of
// steps, and every integer it returns has a capped bit length.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace pm::detail {

// An adaptive bit model: the probability of a 0, in 1/2048.
struct BitModel {
  uint16_t p = 1024;
};

constexpr int kProbabilityBits = 11;
constexpr int kAdaptShift = 5;
constexpr uint32_t kTopValue = 1u << 24;

class RangeEncoder {
 public:
  explicit RangeEncoder(std::string& out) : out_(out) {}

  void bit(BitModel& m, unsigned bit) {
    const uint32_t bound = (range_ >> kProbabilityBits) * m.p;
    if (bit == 0) {
      range_ = bound;
      m.p = static_cast<uint16_t>(m.p + (((1u << kProbabilityBits) - m.p) >> kAdaptShift));
    } else {
      low_ += bound;
      range_ -= bound;
      m.p = static_cast<uint16_t>(m.p - (m.p >> kAdaptShift));
    }
    while (range_ < kTopValue) {
      range_ <<= 8;
      shift_low();
    }
  }

  // `count` (1..16) equiprobable bits of `value` at once, without a model (LZMA's direct
  // bits, several per step): the range is divided into 2^count equal parts.
  void raw_bits(uint32_t value, int count) {
    range_ >>= count;
    low_ += uint64_t{value} * range_;
    while (range_ < kTopValue) {
      range_ <<= 8;
      shift_low();
    }
  }

  // Ends the code: afterwards the decoder has read exactly the bytes written.
  void finish() {
    for (int i = 0; i < 5; ++i) shift_low();
  }

 private:
  void shift_low() {
    if (static_cast<uint32_t>(low_) < 0xFF000000u || (low_ >> 32) != 0) {
      const auto carry = static_cast<uint8_t>(low_ >> 32);
      uint8_t byte = cache_;
      do {
        out_.push_back(static_cast<char>(static_cast<uint8_t>(byte + carry)));
        byte = 0xFF;
      } while (--pending_ != 0);
      cache_ = static_cast<uint8_t>(low_ >> 24);
    }
    ++pending_;
    low_ = (low_ & 0x00FFFFFFu) << 8;
  }

  std::string& out_;
  uint64_t low_ = 0;
  uint32_t range_ = 0xFFFFFFFFu;
  uint8_t cache_ = 0;
  uint64_t pending_ = 1;
};

class RangeDecoder {
 public:
  // The first byte of a range code is always 0 (the encoder's initial pending byte); the
  // next four start the code value.
  explicit RangeDecoder(std::string_view bytes) : bytes_(bytes) {
    if (next_byte() != 0) bad_ = true;
    for (int i = 0; i < 4; ++i) code_ = (code_ << 8) | next_byte();
    if (code_ == range_) bad_ = true;
  }

  // Without a branch on the bit: a decision near even odds is a branch mispredicted half
  // the time, the decoder's largest cost; conditional moves and a mask cost a few cycles.
  unsigned bit(BitModel& m) {
    const uint32_t bound = (range_ >> kProbabilityBits) * m.p;
    const unsigned bit = code_ >= bound ? 1u : 0u;
    const uint32_t mask = 0u - bit;  // all ones for a 1
    code_ -= bound & mask;
    range_ = bit != 0 ? range_ - bound : bound;
    const uint32_t p = m.p;
    const uint32_t towards_one = p - (p >> kAdaptShift);
    const uint32_t towards_zero = p + (((1u << kProbabilityBits) - p) >> kAdaptShift);
    m.p = static_cast<uint16_t>(bit != 0 ? towards_one : towards_zero);
    while (range_ < kTopValue) {
      range_ <<= 8;
      code_ = (code_ << 8) | next_byte();
    }
    return bit;
  }

  // `count` (1..16) equiprobable bits (RangeEncoder::raw_bits). A part beyond the last is
  // damage: it is clamped, and the code marked bad.
  uint32_t raw_bits(int count) {
    range_ >>= count;
    uint32_t value = code_ / range_;
    if (value >= (1u << count)) {
      bad_ = true;
      value = (1u << count) - 1;
    }
    code_ -= value * range_;
    while (range_ < kTopValue) {
      range_ <<= 8;
      code_ = (code_ << 8) | next_byte();
    }
    return value;
  }

  // Whether the code was well formed so far: its first byte 0, no byte read past the end.
  bool ok() const { return !bad_; }
  // Whether every byte was read (a stream with bytes left over is corrupt).
  bool at_end() const { return at_ == bytes_.size(); }

 private:
  uint32_t next_byte() {
    if (at_ >= bytes_.size()) {
      bad_ = true;
      return 0;
    }
    return static_cast<uint8_t>(bytes_[at_++]);
  }

  std::string_view bytes_;
  std::size_t at_ = 0;
  uint32_t range_ = 0xFFFFFFFFu;
  uint32_t code_ = 0;
  bool bad_ = false;
};

// Exp-Golomb binarization of unsigned integers up to 2^kMaxEgBits - 2 with adaptive models
// (Teuhola 1978's exponential Golomb codes; adaptive as CABAC's UEG0 bins, Marpe et al.
// 2003, §III.A): n = bit length of x + 1, minus one, as n ones and a zero (the i-th with
// model prefix[min(i, kEgPrefixModels - 1)]), then the n bits of x + 1 below its top bit,
// most significant first; the first two of them with a model per n and position (they carry
// the shape of the distribution), the rest as equiprobable bits, up to 16 at a time (they
// are close to uniform, and decode several to a division).
constexpr int kMaxEgBits = 40;  // residuals of u32 values need 33 bits
constexpr int kEgPrefixModels = 24;

struct EgModels {
  BitModel prefix[kEgPrefixModels];
  BitModel top[kMaxEgBits][3];  // [n][0]: first suffix bit; [n][1 + first]: second
};

inline void put_eg(RangeEncoder& rc, EgModels& m, uint64_t x) {
  const uint64_t y = x + 1;
  int n = 0;
  while ((y >> (n + 1)) != 0) ++n;
  for (int i = 0; i < n; ++i) rc.bit(m.prefix[i < kEgPrefixModels ? i : kEgPrefixModels - 1], 1);
  rc.bit(m.prefix[n < kEgPrefixModels ? n : kEgPrefixModels - 1], 0);
  if (n == 0) return;
  const unsigned first = static_cast<unsigned>((y >> (n - 1)) & 1);
  rc.bit(m.top[n][0], first);
  if (n == 1) return;
  rc.bit(m.top[n][1 + first], static_cast<unsigned>((y >> (n - 2)) & 1));
  for (int k = n - 2; k > 0;) {  // bits k-1 .. 0, 16 at most at a time
    const int count = k < 16 ? k : 16;
    k -= count;
    rc.raw_bits(static_cast<uint32_t>((y >> k) & ((1u << count) - 1)), count);
  }
}

// False when the prefix is longer than kMaxEgBits - 1 (no writer makes such a code).
inline bool get_eg(RangeDecoder& rc, EgModels& m, uint64_t& x) {
  int n = 0;
  while (rc.bit(m.prefix[n < kEgPrefixModels ? n : kEgPrefixModels - 1]) != 0) {
    if (++n >= kMaxEgBits) return false;
  }
  uint64_t y = 1;
  if (n >= 1) {
    const unsigned first = rc.bit(m.top[n][0]);
    y = (y << 1) | first;
    if (n >= 2) y = (y << 1) | rc.bit(m.top[n][1 + first]);
    for (int k = n - 2; k > 0;) {
      const int count = k < 16 ? k : 16;
      k -= count;
      y = (y << count) | rc.raw_bits(count);
    }
  }
  x = y - 1;
  return true;
}

// A value in [0, 2^bits), bits <= kTreeBits, as a binary tree of adaptive models, most
// significant bit first (each node its own model: the distribution of small alphabets,
// such as the place of vl in a ring of a given size, is learnt exactly).
constexpr int kTreeBits = 6;
struct TreeModels {
  BitModel node[1 << kTreeBits];
};

inline void put_tree(RangeEncoder& rc, TreeModels& m, int bits, uint32_t value) {
  uint32_t node = 1;
  for (int k = bits - 1; k >= 0; --k) {
    const unsigned b = (value >> k) & 1;
    rc.bit(m.node[node], b);
    node = (node << 1) | b;
  }
}

inline uint32_t get_tree(RangeDecoder& rc, TreeModels& m, int bits) {
  uint32_t node = 1;
  for (int k = 0; k < bits; ++k) node = (node << 1) | rc.bit(m.node[node]);
  return node - (1u << bits);
}

}  // namespace pm::detail
