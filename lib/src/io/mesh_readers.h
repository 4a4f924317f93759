// Internal to the mesh readers: their entry points (mesh_io.cpp dispatches to them) and the
// number scanning shared by the OBJ, OFF and PLY (ASCII) parsers.
#pragma once

#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <system_error>

#include "pm/mesh.h"
#include "pm/mesh_io.h"
#include "pm/status.h"

namespace pm::detail {

// Our own OBJ parser (obj_reader.cpp). On success fills `mesh` and `report` (both are
// overwritten, not appended to); on failure leaves them in an unspecified state, so callers
// parse into a scratch mesh.
Status read_obj(std::string_view bytes, Mesh& mesh, ReadReport& report);

// The OFF, PLY and STL readers (off_reader.cpp, ply_reader.cpp, stl_reader.cpp), with the
// same contract.
Status read_off(std::string_view bytes, Mesh& mesh, ReadReport& report);
Status read_ply(std::string_view bytes, Mesh& mesh, ReadReport& report);
Status read_with_openmesh(std::string_view bytes, MeshFormat format, Mesh& mesh,
                          ReadReport& report);

// ---------------------------------------------------------------------------------------
// Scanning a line of text: [p, end) never includes the line's '\n'.

inline bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

// A token ends at a blank, at the end of the line, or where a trailing comment starts.
inline bool is_token_end(const char* p, const char* end) {
  return p == end || is_blank(*p) || *p == '#';
}

inline const char* skip_blanks(const char* p, const char* end) {
  while (p != end && is_blank(*p)) ++p;
  return p;
}

enum class NumberResult { kOk, kMalformed, kOutOfRange };

// The fast path of parse_float, for the plain decimals nearly every mesh file holds
// ("-12.345678": an optional '-', digits, optionally '.' and digits, at most 19 digits, no
// exponent). Returns false, having read nothing, for anything else, and for the rare value
// it cannot round correctly; parse_float then gives it to std::from_chars.
//
// Why the result is from_chars' (the float nearest to the decimal, ties to even): the
// decimal is m / 10^f with m < 2^53 and f <= 22, both exact in double, so one division
// gives the double nearest to it. Rounding that double to float again gives the float
// nearest to the decimal unless the double is exactly halfway between two floats (Figueroa,
// "When is double rounding innocuous?", 1995: no float midpoint can lie strictly between the
// decimal and its nearest double, since a midpoint is itself a double). That case is
// recognised by the 29 bits a float drops from a double's significand being exactly
// 1000...0, and left to from_chars. No value here is near float's subnormals or its
// overflow. Needs double arithmetic without excess precision (FLT_EVAL_METHOD 0, which
// x86-64 and AArch64 have); elsewhere every number goes to from_chars.
inline bool parse_plain_decimal(const char*& p, const char* end, float& value) {
#if defined(FLT_EVAL_METHOD) && FLT_EVAL_METHOD == 0
  static constexpr double kPowersOfTen[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                            1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                            1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  auto is_digit = [](char c) { return static_cast<unsigned char>(c - '0') < 10; };
  const char* q = p;
  const bool negative = q != end && *q == '-';
  q += negative;
  uint64_t mantissa = 0;  // wraps past 19 digits, but is then not used
  const char* const digits_begin = q;
  while (q != end && is_digit(*q)) mantissa = mantissa * 10 + static_cast<unsigned>(*q++ - '0');
  const std::ptrdiff_t integer_digits = q - digits_begin;
  if (integer_digits == 0) return false;
  std::ptrdiff_t fraction_digits = 0;
  if (q != end && *q == '.') {
    const char* const fraction_begin = ++q;
    while (q != end && is_digit(*q)) mantissa = mantissa * 10 + static_cast<unsigned>(*q++ - '0');
    fraction_digits = q - fraction_begin;
    if (fraction_digits == 0) return false;
  }
  if (integer_digits + fraction_digits > 19 || mantissa > (uint64_t{1} << 53) ||
      fraction_digits > 22 || !is_token_end(q, end)) {
    return false;
  }
  const double nearest = static_cast<double>(mantissa) / kPowersOfTen[fraction_digits];
  uint64_t bits;
  std::memcpy(&bits, &nearest, sizeof bits);
  constexpr uint64_t kDroppedBits = (uint64_t{1} << 29) - 1;
  if ((bits & kDroppedBits) == uint64_t{1} << 28) return false;  // halfway between floats
  const float single = static_cast<float>(nearest);
  value = negative ? -single : single;
  p = q;
  return true;
#else
  (void)p, (void)end, (void)value;
  return false;
#endif
}

// parse_float for what its fast path declines: std::from_chars. Kept out of line so that
// parse_float, nearly always its fast path, inlines into the readers' loops.
[[gnu::noinline]] inline NumberResult parse_float_with_from_chars(const char*& p, const char* end,
                                                                  float& value) {
  const char* start = p;
  if (p != end && *p == '+' && p + 1 != end && *(p + 1) != '-' && *(p + 1) != '+') ++start;
  auto [ptr, ec] = std::from_chars(start, end, value);
  if (ec == std::errc::invalid_argument) return NumberResult::kMalformed;
  if (!is_token_end(ptr, end)) return NumberResult::kMalformed;
  if (ec == std::errc::result_out_of_range) {
    // Tell underflow (harmless: round to zero or a subnormal) from overflow.
    double wide = 0;
    if (std::from_chars(start, end, wide).ec == std::errc()) {
      if (std::fabs(wide) >= 1.0) return NumberResult::kOutOfRange;
    } else {
      const std::string_view text(start, static_cast<std::size_t>(ptr - start));
      if (text.find("e-") == std::string_view::npos && text.find("E-") == std::string_view::npos) {
        return NumberResult::kOutOfRange;
      }
      wide = *start == '-' ? -0.0 : 0.0;
    }
    value = static_cast<float>(wide);
  }
  p = ptr;
  return NumberResult::kOk;
}

// Parses one float token at `p` (advanced past it) as std::from_chars does: locale-independent
// and correctly rounded to float32. Accepts a leading '+', which from_chars does not. Values
// too small for float32 become (signed) zero or a subnormal, like a C library would; values
// too large are kOutOfRange. "nan" and "inf" are parsed: callers check std::isfinite.
inline NumberResult parse_float(const char*& p, const char* end, float& value) {
  if (parse_plain_decimal(p, end, value)) return NumberResult::kOk;
  return parse_float_with_from_chars(p, end, value);
}

// The message a text reader gives for a coordinate that did not parse, or nullptr.
inline const char* coordinate_problem(NumberResult result) {
  switch (result) {
    case NumberResult::kOk:
      return nullptr;
    case NumberResult::kMalformed:
      return "malformed vertex";
    case NumberResult::kOutOfRange:
      return "coordinate out of float range";
  }
  return "malformed vertex";
}

// Parses one integer at `p` (advanced past it); accepts a leading '+'. Does not require the
// token to end there (OBJ face corners continue with '/').
inline NumberResult parse_int(const char*& p, const char* end, int64_t& value) {
  const char* start = p;
  if (p != end && *p == '+' && p + 1 != end && *(p + 1) != '-' && *(p + 1) != '+') ++start;
  auto [ptr, ec] = std::from_chars(start, end, value);
  if (ec == std::errc::invalid_argument) return NumberResult::kMalformed;
  p = ptr;
  if (ec == std::errc::result_out_of_range) return NumberResult::kOutOfRange;
  return NumberResult::kOk;
}

}  // namespace pm::detail
