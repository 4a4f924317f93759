// The writer's choice of a grid or of decimals for positions and table values, and the
// records that hold them in BASE and TABL, written and read side by side (pm-format.md §5.3,
// §5.4): a grid over the bounding box when quantized (Deering 1995, "Geometry compression",
// §4), and when lossless (2.3) the values' own decimals, on a grid or as numbers of
// significant decimals, when they are coarser than the floats. The predictions that use
// them, split by split, are in positions.h.
#include "v2/positions.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "byte_io.h"
#include "significant_decimals.h"

namespace pm::detail::v2 {
namespace {

// 2.3 (§5.3): how many bits coarser a decimal step of 2^log2_step is than the float step
// above |x| (+0's is the smallest subnormal), within +-16: the writer's estimate of what
// coding x as that decimal saves over its float bits.
double bits_coarser(double log2_step, float x) {
  const float a = std::fabs(x);
  const float ulp = std::nextafter(a, std::numeric_limits<float>::infinity()) - a;  // a power of 2
  return std::clamp(log2_step - std::ilogb(ulp), -16.0, 16.0);
}

}  // namespace

// 2.3, lossless (§5.3): a decimal grid for the `components`-vectors `values`, when each is
// exactly the float of a decimal with a few places after the point (as text formats write
// them: "0.037830"), within kMaxDecimalBits of range, and coarser than the floats' own steps
// where most values lie (then the grid's residuals are smaller than those of the float bits;
// on the bunny, 6 places and 18 bits, about a third of the stream). False otherwise.
bool make_decimal_grid(const float* values, std::size_t count, std::size_t components, Grid& grid,
                       double& gain) {
  if (count == 0) return false;
  int decimals = 0;
  std::vector<int64_t> low(components), high(components);  // of the decimals, per component
  for (;; ++decimals) {
    if (decimals > kMaxDecimals) return false;
    const double scale = kPowersOf10[decimals];
    bool exact = true;
    for (std::size_t i = 0; i < count * components && exact; ++i) {
      const float x = values[i];
      const double k = std::nearbyint(double{x} * scale);
      exact = std::isfinite(x) && std::fabs(k) < double(kMaxDecimalFirst);
      if (!exact) break;
      const auto back = static_cast<float>(static_cast<double>(static_cast<int64_t>(k)) / scale);
      exact = std::memcmp(&back, &x, sizeof x) == 0;  // -0 is not a decimal's float
      const std::size_t c = i % components;
      const auto decimal = static_cast<int64_t>(k);
      if (i < components || decimal < low[c]) low[c] = decimal;
      if (i < components || decimal > high[c]) high[c] = decimal;
    }
    if (exact) break;
  }
  const double scale = kPowersOf10[decimals];
  uint64_t extent = 0;
  for (std::size_t c = 0; c < components; ++c) {
    extent = std::max(extent, static_cast<uint64_t>(high[c] - low[c]));
  }
  int bits = kMinBits;
  while (bits <= kMaxDecimalBits && (extent >> bits) != 0) ++bits;
  if (bits > kMaxDecimalBits) return false;
  // Worth it where the grid's step is coarser than the floats' (log2 of the ratio, each value
  // counted within +-16).
  const double log_step = -std::log2(scale);
  gain = 0;
  for (std::size_t i = 0; i < count * components; ++i) gain += bits_coarser(log_step, values[i]);
  if (!(gain > 0)) return false;
  grid.bits = bits;
  grid.decimals = decimals;
  grid.first = low;
  grid.origin.assign(components, 0.0f);
  grid.step = 1.0f;
  return true;
}

namespace {

// The decimal of `digits` significant digits whose float is x (m, k), or false.
bool significant_decimal(float x, int digits, int64_t& m, int& k) {
  if (!std::isfinite(x) || x == 0) return false;
  const double a = std::fabs(double{x});
  const auto low = static_cast<int64_t>(kPowersOf10[digits - 1]), high = 10 * low;
  k = static_cast<int>(std::floor(std::log10(a))) - digits + 1;
  for (int attempt = 0; attempt < 3; ++attempt) {
    if (k < kMinExponent || k > kMaxExponent) return false;
    m = static_cast<int64_t>(std::nearbyint(a * std::pow(10.0, -k)));  // a guess: checked below
    if (m >= high) {
      ++k;
    } else if (m < low) {
      --k;
    } else {
      const double value = scaled_decimal(double(m), k);
      const auto back = static_cast<float>(x < 0 ? -value : value);
      return std::memcmp(&back, &x, sizeof x) == 0;
    }
  }
  return false;
}

}  // namespace

// 2.3, lossless (§5.3): the fewest significant digits whose decimals give every value back
// bit for bit (+0 has a number, -0 none), and each value's unit, when those decimals are
// coarser than the floats' own steps where most values lie (as make_decimal_grid decides).
// False otherwise.
bool make_significant_decimals(const float* values, std::size_t count, SignificantDecimals& out,
                               std::vector<uint32_t>& units, double& gain) {
  if (count == 0) return false;
  std::vector<int> exponents(count);
  std::vector<int64_t> mantissas(count);
  int digits = 1;
  // 9 digits give back every float, in steps finer than the float's own: they never pay
  // (and trying them would read every value once more, where nothing is a short decimal).
  for (;; ++digits) {
    if (digits >= kMaxSignificantDigits) return false;
    bool exact = true;
    for (std::size_t i = 0; i < count && exact; ++i) {
      const float x = values[i];
      if (x == 0) {
        exact = !std::signbit(x);
        continue;
      }
      exact = significant_decimal(x, digits, mantissas[i], exponents[i]);
    }
    if (exact) break;
  }
  int first = kMaxExponent;
  gain = 0;
  for (std::size_t i = 0; i < count; ++i) {
    if (values[i] == 0) {
      gain += bits_coarser(0, values[i]);  // +0: 16, as on a grid
      continue;
    }
    first = std::min(first, exponents[i]);
    gain += bits_coarser(double(exponents[i]) * std::log2(10.0), values[i]);
  }
  if (!(gain > 0)) return false;
  const auto low = static_cast<int64_t>(kPowersOf10[digits - 1]);
  units.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    int64_t n = 0;
    if (values[i] != 0) n = (exponents[i] - first) * 9 * low + (mantissas[i] - low) + 1;
    if (n >= (int64_t{1} << 31)) return false;  // decades too far apart
    units[i] = static_cast<uint32_t>((int64_t{1} << 31) + (values[i] < 0 ? -n : n));
  }
  out.digits = digits;
  out.first_exponent = first;
  return true;
}

// The grid of `components`-vectors `values` (count of them), over their bounding box's
// longest side. False when a value is not finite.
bool make_grid(const float* values, std::size_t count, std::size_t components, int bits,
               Grid& grid) {
  grid.bits = bits;
  grid.origin.assign(components, 0.0f);
  std::vector<float> top(components, 0.0f);
  for (std::size_t i = 0; i < count; ++i) {
    for (std::size_t c = 0; c < components; ++c) {
      const float x = values[components * i + c];
      if (!std::isfinite(x)) return false;
      if (i == 0 || x < grid.origin[c]) grid.origin[c] = x;
      if (i == 0 || x > top[c]) top[c] = x;
    }
  }
  double extent = 0;
  for (std::size_t c = 0; c < components; ++c) {
    extent = std::max(extent, double{top[c]} - double{grid.origin[c]});
  }
  const double steps = double((uint32_t{1} << bits) - 1);
  grid.step = extent > 0 ? static_cast<float>(extent / steps) : 1.0f;
  if (!(grid.step > 0) || !std::isfinite(grid.step)) grid.step = 1.0f;
  return true;
}

void put_grid(ByteWriter& out, const Grid& grid) {
  if (grid.decimals >= 0) {  // 2.3 (§5.3)
    out.put_u8(static_cast<uint8_t>(grid.decimals));
    for (int64_t k : grid.first) out.put_u64(static_cast<uint64_t>(k));
    return;
  }
  for (float x : grid.origin) out.put_f32(x);
  out.put_f32(grid.step);
}
bool read_grid(ByteReader& in, int bits, std::size_t components, Grid& grid, bool decimal) {
  grid.bits = bits;
  if (decimal) {  // 2.3 (§5.3)
    uint8_t decimals = 0;
    if (!in.read_u8(decimals)) return false;
    if (decimals > kMaxDecimals) {
      return in.fail(ErrorCode::kCorruptStream, in.where() + ": a decimal grid of " +
                                                    std::to_string(decimals) + " places (at most 15)");
    }
    grid.decimals = decimals;
    grid.first.assign(components, 0);
    grid.origin.assign(components, 0.0f);
    for (int64_t& k : grid.first) {
      uint64_t bits64 = 0;
      if (!in.read_u64(bits64)) return false;
      k = static_cast<int64_t>(bits64);
      if (k <= -kMaxDecimalFirst || k >= kMaxDecimalFirst) {
        return in.fail(ErrorCode::kCorruptStream, in.where() + ": a decimal grid's first value is beyond 2^52");
      }
    }
    return true;
  }
  grid.origin.assign(components, 0.0f);
  for (float& x : grid.origin) {
    if (!in.read_f32(x)) return false;
  }
  if (!in.read_f32(grid.step)) return false;
  for (float x : grid.origin) {
    if (!std::isfinite(x)) return in.fail(ErrorCode::kCorruptStream, in.where() + ": grid origin is not finite");
  }
  if (!(grid.step > 0) || !std::isfinite(grid.step)) {
    return in.fail(ErrorCode::kCorruptStream, in.where() + ": grid step is not a positive number");
  }
  return true;
}

// 2.3 (§5.3, §5.4): significant decimals' record, u8 digits and i8 first exponent.
void put_significant(ByteWriter& out, const SignificantDecimals& significant) {
  out.put_u8(static_cast<uint8_t>(significant.digits));
  out.put_u8(static_cast<uint8_t>(static_cast<int8_t>(significant.first_exponent)));
}
bool read_significant(ByteReader& in, SignificantDecimals& out) {
  uint8_t digits = 0, exponent = 0;
  if (!in.read_u8(digits) || !in.read_u8(exponent)) return false;
  const int first_exponent = static_cast<int8_t>(exponent);
  if (digits < 1 || digits > kMaxSignificantDigits || first_exponent < kMinExponent ||
      first_exponent > kMaxExponent) {
    return in.fail(ErrorCode::kCorruptStream, in.where() + ": significant decimals of " +
                                                  std::to_string(digits) + " digits from 10^" +
                                                  std::to_string(first_exponent));
  }
  out.digits = digits;
  out.first_exponent = first_exponent;
  return true;
}

}  // namespace pm::detail::v2
