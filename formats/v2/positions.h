// Values per vertex in the integers their residuals are taken in, and their predictions
// (pm-format.md §5.3, §5.6, §5.10), for the writer and the reader of every section that holds
// positions or table values: quantization grids (Deering 1995, "Geometry compression", §4:
// uniform quantization over a bounding box) and 2.3's decimals, the mean of the neighbours as
// a new vertex's prediction (the "Laplacian" prediction of Taubin, Guéziec, Horn and Lazarus
// 1998, "Progressive forest split compression", §5), and 2.1's frame along u's normal and
// lopsided place. Inline: every split of a chunk uses them. Internal to formats/.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "significant_decimals.h"
#include "split_fans.h"
#include "v2/format.h"

namespace pm::detail::v2 {

// ---------------------------------------------------------------------------------------
// Quantization grids (§5.3): origin + q * step, q in [0, 2^bits); or, lossless (2.3), the
// decimals with `decimals` places after the point from first / 10^decimals on.

constexpr int64_t kMaxDecimalFirst = int64_t{1} << 52;  // |first|: first + q exact in a double

struct Grid {
  int bits = 0;                 // 0: no quantization
  std::vector<float> origin;    // per component
  float step = 1.0f;
  int decimals = -1;            // a decimal grid when >= 0 (2.3)
  std::vector<int64_t> first;   // per component, of a decimal grid

  // The value of index q: as a float, (float)value(q, c) (§5.3). A decimal's division by an
  // exact power of 10 is correctly rounded, so every reader gets the same float.
  double value(uint32_t q, std::size_t component) const {
    if (decimals >= 0) return static_cast<double>(first[component] + q) / kPowersOf10[decimals];
    return double{origin[component]} + static_cast<double>(q) * double{step};
  }
};

// The writer's grids and decimals, and their records in BASE and TABL (positions.cpp).
bool make_decimal_grid(const float* values, std::size_t count, std::size_t components, Grid& grid,
                       double& gain);
bool make_significant_decimals(const float* values, std::size_t count, SignificantDecimals& out,
                               std::vector<uint32_t>& units, double& gain);
bool make_grid(const float* values, std::size_t count, std::size_t components, int bits,
               Grid& grid);
void put_grid(ByteWriter& out, const Grid& grid);
bool read_grid(ByteReader& in, int bits, std::size_t components, Grid& grid, bool decimal = false);
void put_significant(ByteWriter& out, const SignificantDecimals& significant);
bool read_significant(ByteReader& in, SignificantDecimals& out);

// The float a value's integer `unit` stands for (§5.6): a grid index (grid set), a number of
// significant decimals (2.3, significant set), else ordered float bits; false when it stands
// for none (significant decimals only).
inline bool float_of_unit(const Grid* grid, const SignificantDecimals* significant, uint32_t unit,
                   std::size_t c, float& out) {
  if (significant != nullptr) return significant->to_float(unit, out);
  out = grid != nullptr ? static_cast<float>(grid->value(unit, c)) : float_from_ordered(unit);
  return true;
}

inline uint32_t quantize(const Grid& grid, float x, std::size_t component) {
  const double top = double((uint32_t{1} << grid.bits) - 1);
  if (grid.decimals >= 0) {  // exact: make_decimal_grid checked every value
    const double k = std::nearbyint(double{x} * kPowersOf10[grid.decimals]);
    return static_cast<uint32_t>(std::clamp(k - double(grid.first[component]), 0.0, top));
  }
  const double q = std::nearbyint((double{x} - double{grid.origin[component]}) / double{grid.step});
  return static_cast<uint32_t>(std::clamp(q, 0.0, top));
}

// ---------------------------------------------------------------------------------------
// Values per vertex (positions, colours) in the integers their residuals are taken in
// (§5.6): the ordered float bits when lossless, the grid index when quantized.

struct VertexValues {
  std::size_t components = 3;
  const Grid* grid = nullptr;       // quantized when set
  const SignificantDecimals* significant = nullptr;  // 2.3: lossless decimals' numbers when set
  bool mean_of_values = false;  // 2.4: significant decimals predicted by their values' mean

  // Whether the normal frame applies (§5.10): on a grid (2.1), of significant decimals (2.4).
  bool has_frames() const { return grid != nullptr || (significant != nullptr && mean_of_values); }
  std::vector<uint32_t> units;      // components per vertex, as decoded or encoded so far

  // False when `unit` stands for no value (significant decimals only).
  bool to_float(uint32_t unit, std::size_t c, float& out) const {
    return float_of_unit(grid, significant, unit, c, out);
  }
  uint32_t from_float(float x, std::size_t c) const {
    return grid != nullptr ? quantize(*grid, x, c) : ordered_from_float(x);
  }

  // 2.1 (§5.10): the context of a residual, the bit length of the neighbours' mean absolute
  // deviation from the prediction in that coordinate: where the ring is wide, residuals are
  // large, so each scale of the surface gets its own statistics.
  uint32_t spread_context(const uint32_t* neighbours, std::size_t count, uint32_t predicted,
                          std::size_t c) const {
    uint64_t sum = 0;
    for (std::size_t k = 0; k < count; ++k) {
      const int64_t d = int64_t{units[components * neighbours[k] + c]} - int64_t{predicted};
      sum += static_cast<uint64_t>(d < 0 ? -d : d);
    }
    return std::min<uint32_t>(bit_length(sum / count), kSpreadContexts - 1);
  }

  // The prediction of a new vertex from its neighbours in the refined mesh (Taubin et al.
  // 1998, §5): their mean, in the grid's integers, or in double then rounded to float (when
  // the mean is not finite, the first neighbour's value, which is u's); significant decimals
  // (2.4) as the number nearest to their values' mean (2.3: their numbers' mean).
  void predict(const uint32_t* neighbours, std::size_t count, uint32_t* out) const {
    for (std::size_t c = 0; c < components; ++c) {
      const auto unit_at = [&](std::size_t k) { return units[components * neighbours[k] + c]; };
      if (significant != nullptr && mean_of_values) {
        const int64_t scale = significant->scale_of(count, unit_at);
        __int128 sum = 0;
        for (std::size_t k = 0; k < count; ++k) sum += significant->linear(unit_at(k), scale);
        out[c] = significant->nearest(rounded_quotient(sum, static_cast<__int128>(count)), scale);
      } else if (grid != nullptr || significant != nullptr) {  // 2.3's significant decimals too
        uint64_t sum = 0;
        for (std::size_t k = 0; k < count; ++k) sum += unit_at(k);
        out[c] = static_cast<uint32_t>((2 * sum + count) / (2 * count));
      } else {
        double sum = 0;
        for (std::size_t k = 0; k < count; ++k) {
          sum += double{float_from_ordered(units[components * neighbours[k] + c])};
        }
        const auto mean = static_cast<float>(sum / double(count));
        out[c] = std::isfinite(mean) ? ordered_from_float(mean)
                                     : units[components * neighbours[0] + c];
      }
    }
  }
};

// 2.1, positions on a grid (§5.10): u's normal, from its fan of faces in the grid's integers
// (the sum of the faces' cross products at u, scaled down to 15 bits), and the coordinate
// most along it. A split's new vertex lies close to the tangent plane at u, while the mean of
// its neighbours lies off it where the surface is curved, so the residuals across the
// surface are about three times those along the normal (measured on the bunny: 59 against
// 20 grid steps at 14 bits). The two tangential coordinates are coded first; the normal one
// is then predicted from them, so that the residual vector's normal component is a quarter
// of the prediction's offset from u's plane, with the sign reversed (the least squares fit
// on the shared meshes is -0.6 to -0.75). Integers only, so that every reader gets the same.
struct NormalFrame {
  int64_t n[3] = {0, 0, 0};
  int order[3] = {0, 1, 2};  // tangential, tangential, normal
};

constexpr std::size_t kMaxNormalFan = 1024;  // larger fans (none in practice) go without

// The offsets (ring vertex - u) that lopsided_place and normal_frame read, as offset(k, c)
// for ring[k] (k up to n, so that a closed fan's last face finds its second vertex), in
// integers that are linear in the positions' values: on a grid its indices' differences
// (2.3's decimal grids of more than 24 bits divided by 2^(bits - 24), truncating towards
// zero, so that products stay as small as on 24-bit grids); lossless float bits' differences
// divided by 256 (lopsided_place only); and 2.4's significant decimals (§5.3) as their
// values, u's and the ring's on one scale, then halved together (truncating towards zero)
// until each is below 2^24, computed into `scratch`. `use` gets the offsets as a function
// object, one type per case, so that the common ones read the values directly and divide by
// constants (a division by a variable is slow).
template <typename Use>
auto with_fan_offsets(const VertexValues& positions, uint32_t u, const SplitFans::Fan& fan,
                      std::vector<int64_t>& scratch, Use use) {
  const uint32_t* units = positions.units.data();
  const uint32_t* at_u = units + 3 * std::size_t{u};
  const uint32_t* ring = fan.ring.data();
  if (positions.significant != nullptr && positions.mean_of_values) {
    const std::size_t n = fan.ring.size();
    scratch.resize(3 * n);
    const SignificantDecimals& numbers = *positions.significant;
    const auto unit_at = [&](std::size_t k) {
      return k < 3 ? at_u[k] : units[3 * std::size_t{ring[k / 3 - 1]} + k % 3];
    };
    const int64_t scale = numbers.scale_of(3 * (n + 1), unit_at);
    int64_t origin[3];
    for (int c = 0; c < 3; ++c) origin[c] = numbers.linear(at_u[c], scale);
    for (std::size_t k = 0; k < 3 * n; ++k) scratch[k] = numbers.linear(unit_at(k + 3), scale) - origin[k % 3];
    halve_below(scratch.data(), scratch.size(), kMaxBits);
    const int64_t* table = scratch.data();
    return use([table](std::size_t k, int c) { return table[3 * k + c]; });
  }
  const auto difference = [units, at_u, ring](std::size_t k, int c) {
    return int64_t{units[3 * std::size_t{ring[k]} + c]} - int64_t{at_u[c]};
  };
  if (positions.grid == nullptr) {
    return use([difference](std::size_t k, int c) { return difference(k, c) / 256; });
  }
  const int64_t divisor = int64_t{1} << std::max(0, positions.grid->bits - kMaxBits);
  if (divisor == 1) return use(difference);
  return use([difference, divisor](std::size_t k, int c) { return difference(k, c) / divisor; });
}

// On a grid (2.1) or of significant decimals (2.4): u's normal and its order of coordinates.
template <typename Offset>
inline bool normal_frame_of(const Offset& offset, const SplitFans::Fan& fan, NormalFrame& out) {
  int64_t n[3] = {0, 0, 0};
  int64_t e1[3], e2[3];  // face k's edges from u: to ring[k] and ring[k + 1]
  for (int c = 0; c < 3; ++c) e1[c] = offset(0, c);
  for (std::size_t k = 0; k < fan.faces.size(); ++k) {
    for (int c = 0; c < 3; ++c) e2[c] = offset(k + 1, c);
    // Each product is below 2^48 (each offset below 2^24), each sum of 1024 below 2^60.
    n[0] += e1[1] * e2[2] - e1[2] * e2[1];
    n[1] += e1[2] * e2[0] - e1[0] * e2[2];
    n[2] += e1[0] * e2[1] - e1[1] * e2[0];
    for (int c = 0; c < 3; ++c) e1[c] = e2[c];
  }
  const auto magnitude = [](int64_t x) { return x < 0 ? -x : x; };
  halve_below(n, 3, 15);
  int normal = 0;
  for (int c = 1; c < 3; ++c) {
    if (magnitude(n[c]) > magnitude(n[normal])) normal = c;
  }
  if (n[normal] == 0) return false;
  for (int c = 0; c < 3; ++c) out.n[c] = n[c];
  out.order[0] = normal == 0 ? 1 : 0;
  out.order[1] = normal == 2 ? 1 : 2;
  out.order[2] = normal;
  return true;
}

inline bool normal_frame(const VertexValues& positions, uint32_t u, const SplitFans::Fan& fan,
                  std::vector<int64_t>& scratch, NormalFrame& out) {
  if (fan.faces.empty() || fan.faces.size() > kMaxNormalFan) return false;
  return with_fan_offsets(positions, u, fan, scratch,
                          [&](const auto& offset) { return normal_frame_of(offset, fan, out); });
}

// The normal coordinate's prediction offset, from the tangential residuals r[order[0]],
// r[order[1]] and d = prediction - u: the nearest integer to
// -(3 (d . n) + 4 (n_a r_a + n_b r_b)) / (4 n_c), halves away from minus infinity.
inline int64_t normal_offset(const NormalFrame& f, const int64_t* d, const int64_t* r, int bits) {
  const int a = f.order[0], b = f.order[1], c = f.order[2];
  // |d|, |r| < 2^30 (2^24 but on 2.3's decimal grids) and |n| < 2^15: every term below 2^49.
  int64_t num =
      -(3 * (d[0] * f.n[0] + d[1] * f.n[1] + d[2] * f.n[2]) + 4 * (f.n[a] * r[a] + f.n[b] * r[b]));
  int64_t den = 4 * f.n[c];
  if (den < 0) num = -num, den = -den;
  const int64_t twice = 2 * num + den, q = twice / (2 * den);
  const int64_t offset = (twice % (2 * den) != 0 && twice < 0) ? q - 1 : q;  // floor
  const int64_t limit = int64_t{1} << std::max(bits, kMaxBits);  // beyond any grid: clamped
  return std::clamp(offset, -limit, limit);
}

// 2.4 (§5.10), significant decimals: the normal coordinate c's prediction, the number nearest
// to predicted[c]'s value plus normal_offset's of the values: d = predicted - u and the
// tangential residuals r = v - predicted, all (u's, predicted's and v's two coded coordinates)
// on one scale (§5.3); the offset's terms in 128 bits, it clamped to +-10^18.
inline uint32_t normal_prediction_of_values(const SignificantDecimals& numbers, const NormalFrame& f,
                                     const uint32_t* u, const uint32_t* predicted, const uint32_t* v) {
  const int a = f.order[0], b = f.order[1], c = f.order[2];
  const uint32_t eight[8] = {u[0], u[1], u[2], predicted[0], predicted[1], predicted[2], v[a], v[b]};
  const int64_t scale = numbers.scale_of(8, [&](std::size_t k) { return eight[k]; });
  const auto linear = [&](uint32_t unit) { return static_cast<__int128>(numbers.linear(unit, scale)); };
  __int128 num = 0;
  for (int k = 0; k < 3; ++k) num += 3 * (linear(predicted[k]) - linear(u[k])) * f.n[k];
  num += 4 * (f.n[a] * (linear(v[a]) - linear(predicted[a])) + f.n[b] * (linear(v[b]) - linear(predicted[b])));
  num = -num;
  __int128 den = 4 * static_cast<__int128>(f.n[c]);
  if (den < 0) num = -num, den = -den;
  constexpr __int128 kLimit = 1000000000000000000;  // 10^18
  const __int128 offset = std::clamp(rounded_quotient(num, den), -kLimit, kLimit);
  return numbers.nearest(linear(predicted[c]) + offset, scale);
}

// 2.1 (§5.10): where a closed fan's places start. A collapse v -> u hands v's faces to u, so
// u's ring is lopsided towards where v was: the ring vertex furthest along the mean of
// (ring vertex - u) is near the middle of the arc the split takes back, and vl's place
// counted from it is far from uniform (on the bunny at 14 bits, 2.4 bits instead of 2.9).
// Integers only (differences of values, divided by 256 when lossless, where the values are
// 32-bit), the first of equal scores.
template <typename Offset>
inline std::size_t lopsided_place_of(const Offset& diff, const SplitFans::Fan& fan) {
  const std::size_t n = fan.faces.size();
  // The offsets of a fan of up to kKept faces (nearly all) are kept for the second pass.
  constexpr std::size_t kKept = 16;
  int64_t kept[3 * kKept];
  const bool keep = n <= kKept;
  int64_t direction[3] = {0, 0, 0};  // below 2^34
  for (std::size_t k = 0; k < n; ++k) {
    for (int c = 0; c < 3; ++c) {
      const int64_t d = diff(k, c);
      if (keep) kept[3 * k + c] = d;
      direction[c] += d;
    }
  }
  std::size_t best = 0;
  int64_t best_score = 0;
  for (std::size_t k = 0; k < n; ++k) {
    int64_t score = 0;  // three products below 2^58
    for (int c = 0; c < 3; ++c) score += (keep ? kept[3 * k + c] : diff(k, c)) * direction[c];
    if (k == 0 || score > best_score) best = k, best_score = score;
  }
  return best;
}

inline std::size_t lopsided_place(const VertexValues& positions, uint32_t u, const SplitFans::Fan& fan,
                           std::vector<int64_t>& scratch) {
  if (fan.faces.size() > kMaxNormalFan) return 0;
  return with_fan_offsets(positions, u, fan, scratch,
                          [&](const auto& offset) { return lopsided_place_of(offset, fan); });
}

}  // namespace pm::detail::v2
