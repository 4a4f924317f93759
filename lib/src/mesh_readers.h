// Internal to the mesh readers: the OBJ parser's entry point (mesh_io.cpp dispatches to it)
// and the number scanning shared by the OBJ, OFF and PLY (ASCII) parsers.
#pragma once

#include <charconv>
#include <cmath>
#include <cstdint>
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

// Parses one float token at `p` (advanced past it) with std::from_chars: locale-independent
// and correctly rounded to float32. Accepts a leading '+', which from_chars does not. Values
// too small for float32 become (signed) zero or a subnormal, like a C library would; values
// too large are kOutOfRange. "nan" and "inf" are parsed: callers check std::isfinite.
inline NumberResult parse_float(const char*& p, const char* end, float& value) {
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
