// Integer roundings the predictions share (pm-format.md §5.3, §5.10, §5.11): exact, so that
// every reader gets the same predictions as the writer. Internal to the codec.
#pragma once

#include <cstddef>
#include <cstdint>

namespace pm::detail {

// The integer nearest to num / den (den > 0), halves up: ⌊(2 num + den) / (2 den)⌋.
inline __int128 rounded_quotient(__int128 num, __int128 den) {
  const __int128 twice = 2 * num + den, twice_den = 2 * den;
  __int128 q = twice / twice_den;
  if (twice % twice_den != 0 && twice < 0) --q;  // C++ truncates towards 0; this floors
  return q;
}

// Halves `count` values together, each truncated towards zero, until every magnitude is
// below 2^bits (k halvings are one division by 2^k: truncation composes), so that products
// of them fit in 64 bits.
inline void halve_below(int64_t* values, std::size_t count, int bits) {
  int64_t largest = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const int64_t magnitude = values[i] < 0 ? -values[i] : values[i];
    if (magnitude > largest) largest = magnitude;
  }
  int halvings = 0;
  while ((largest >> halvings) >= (int64_t{1} << bits)) ++halvings;
  if (halvings == 0) return;
  for (std::size_t i = 0; i < count; ++i) {
    values[i] = values[i] < 0 ? -(-values[i] >> halvings) : values[i] >> halvings;
  }
}

}  // namespace pm::detail
