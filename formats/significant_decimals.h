// Numbers of significant decimals (pm-format.md §5.3, 2.3) and, from 2.4, their values as
// integers on one decimal scale, so that predictions can take means and affine maps of the
// values themselves. A number n stands for the decimal m · 10^k with P significant digits;
// numbered in order of value, one decade after the other, they are not linear in the value:
// a step in the decade 0.01–0.1 is a tenth of one in 0.1–1, and between −0.01 and +0.01 lie
// all the decades down to the first. The mean of the numbers of 0.05 and 0.15 is far from the
// number of 0.1, and near zero, the mean of ±0.05 is some tiny decimal, millions of numbers
// from where the vertex is. The stream predicts a new vertex by the mean of its neighbours
// (Taubin, Guéziec, Horn and Lazarus 1998, "Progressive forest split compression", §5), which
// presumes coordinates linear in the value; integers of one scale give that back exactly,
// without floating point, so that every reader gets the same predictions.
// Internal to the codec.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "integer_scaling.h"

namespace pm::detail {

// Significant decimals (2.3, §5.3): at most 9 digits; powers of 10 up to 10^22 are exact
// doubles; exponents from -60 to 40 (a float's decimals of 9 digits have -53 to 30).
constexpr int kMaxSignificantDigits = 9, kMaxPowerOf10 = 22;
constexpr int kMinExponent = -60, kMaxExponent = 40;

constexpr double kPowersOf10[kMaxPowerOf10 + 1] = {
    1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
    1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};  // all exact

// m · 10^k as a double: m times, or divided by, 10^22 as often as it takes, then the rest
// (each step IEEE's, so every reader gets the same; one step for |k| <= 22, then exact).
inline double scaled_decimal(double m, int k) {
  for (; k > kMaxPowerOf10; k -= kMaxPowerOf10) m *= kPowersOf10[kMaxPowerOf10];
  for (; k < -kMaxPowerOf10; k += kMaxPowerOf10) m /= kPowersOf10[kMaxPowerOf10];
  return k >= 0 ? m * kPowersOf10[k] : m / kPowersOf10[-k];
}

// 2.4 (§5.3): values at most this many decades below the largest of a prediction's are
// kept; smaller ones count as truncated (towards 0) at that scale. 10^(9 + 9) < 2^63.
constexpr int kLinearDecades = 9;

// One number's decade q (0 for the first exponent's) and mantissa m, or q = -1 for +0;
// `negative` for the numbers below 2^31.
struct DecimalParts {
  int64_t q = -1;
  int64_t m = 0;
  bool negative = false;
};

// 2.3, lossless (§5.3): positions as decimals of `digits` significant digits, m · 10^k with
// 10^(digits-1) <= m < 10^digits and k >= first_exponent, numbered in order of value: the
// unit of +-x is 2^31 +- n, n = 0 for +0, else (k - first_exponent) · 9 · 10^(digits-1) +
// (m - 10^(digits-1)) + 1. Text formats write such values ("0.0832331", "-52.9283": %g's six
// digits); their float bits hold about 24 bits where the text held 20, which their residuals
// pay for at every vertex.
struct SignificantDecimals {
  int digits = 0;          // 0: not used
  int first_exponent = 0;  // k of the smallest decade

  uint64_t low() const { return static_cast<uint64_t>(kPowersOf10[digits - 1]); }
  uint64_t decade() const { return 9 * low(); }

  DecimalParts parts(uint32_t unit) const {
    const int64_t signed_n = int64_t{unit} - (int64_t{1} << 31);
    const uint64_t n = static_cast<uint64_t>(signed_n < 0 ? -signed_n : signed_n);
    DecimalParts p;
    p.negative = signed_n < 0;
    if (n == 0) return p;
    p.q = static_cast<int64_t>((n - 1) / decade());
    p.m = static_cast<int64_t>(low() + (n - 1) % decade());
    return p;
  }

  // The float of `unit`, or false when no decimal of these has that number.
  bool to_float(uint32_t unit, float& out) const {
    const DecimalParts p = parts(unit);
    if (p.q < 0) {
      out = 0.0f;
      return true;
    }
    const int64_t k = first_exponent + p.q;
    if (k > kMaxExponent) return false;
    const double value = scaled_decimal(static_cast<double>(p.m), static_cast<int>(k));
    out = static_cast<float>(p.negative ? -value : value);
    return std::isfinite(out);
  }

  // 2.4 (§5.3): the scale of a prediction from `count` numbers: the decade of the smallest
  // non-zero one, but at most kLinearDecades below the largest's; 0 when all are +0.
  template <typename UnitAt>
  int64_t scale_of(std::size_t count, UnitAt unit_at) const {
    int64_t largest = -1, smallest = INT64_MAX;
    for (std::size_t k = 0; k < count; ++k) {
      const DecimalParts p = parts(unit_at(k));
      if (p.q < 0) continue;
      largest = std::max(largest, p.q);
      smallest = std::min(smallest, p.q);
    }
    if (largest < 0) return 0;
    return std::max(smallest, largest - kLinearDecades);
  }

  // The value of `unit` in units of 10^(first_exponent + scale): m · 10^(q - scale),
  // truncated towards 0 when q < scale. |result| < 10^18 for q <= scale + kLinearDecades.
  int64_t linear(uint32_t unit, int64_t scale) const {
    const DecimalParts p = parts(unit);
    if (p.q < 0) return 0;
    int64_t m = p.m;
    if (p.q >= scale) {
      for (int64_t t = scale; t < p.q; ++t) m *= 10;
    } else {
      for (int64_t t = p.q; t < scale && m != 0; ++t) m /= 10;
    }
    return p.negative ? -m : m;
  }

  // The number nearest to value · 10^(first_exponent + scale) (halves away from 0): value
  // rounded to `digits` digits; below the first decade, the smallest number (n = 1); beyond
  // the largest number (n = 2^31 - 1, or 2^31 below 0), that.
  uint32_t nearest(__int128 value, int64_t scale) const {
    constexpr uint64_t kZero = uint64_t{1} << 31;
    if (value == 0) return static_cast<uint32_t>(kZero);
    const bool negative = value < 0;
    unsigned __int128 a = static_cast<unsigned __int128>(negative ? -value : value);
    const unsigned __int128 high = 10 * static_cast<unsigned __int128>(low());
    int64_t q = scale;
    unsigned __int128 divisor = 1;
    while (a / divisor >= high) divisor *= 10, ++q;
    a = divisor == 1 ? a : (a + divisor / 2) / divisor;  // rounded once, at the last digit
    if (a >= high) a /= 10, ++q;                            // 9.99…5 rounded up to 10.0…
    while (a < low() && q > 0) a *= 10, --q;
    uint64_t n = 1;
    if (a >= low()) {
      const unsigned __int128 wide = static_cast<unsigned __int128>(q) * decade() +
                                     static_cast<uint64_t>(a - low()) + 1;
      n = wide > kZero ? kZero : static_cast<uint64_t>(wide);
    }
    if (!negative) n = std::min(n, kZero - 1);
    return static_cast<uint32_t>(negative ? kZero - n : kZero + n);
  }
};

// `numbers` when they are used (digits > 0), else null.
inline const SignificantDecimals* in_use(const SignificantDecimals& numbers) {
  return numbers.digits != 0 ? &numbers : nullptr;
}

}  // namespace pm::detail
