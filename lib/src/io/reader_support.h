// What the OFF, PLY and STL readers share (off_reader.cpp, ply_header.cpp, ply_reader.cpp,
// stl_reader.cpp): their errors, header tokens, and attributes read per vertex or per corner.
// Internal to io/; inline, as it was when the readers were one file, for the readers' loops.
#pragma once

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <string_view>
#include <system_error>
#include <unordered_map>
#include <utility>
#include <vector>

#include "pm/mesh.h"
#include "pm/mesh_io.h"
#include "pm/status.h"

namespace pm::detail {

inline std::string lower_case(std::string_view text) {
  std::string lower(text);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower;
}

inline Status parse_error(std::string message) {
  return Status(ErrorCode::kParseError, std::move(message));
}

// ---------------------------------------------------------------------------------------------
// Header tokens

inline bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

// Splits a line into blank-separated tokens, up to a '#' comment.
inline std::vector<std::string_view> split_tokens(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    if (i == line.size() || line[i] == '#') break;
    std::size_t start = i;
    while (i < line.size() && !is_space(line[i]) && line[i] != '#') ++i;
    tokens.push_back(line.substr(start, i - start));
  }
  return tokens;
}

inline bool parse_count(std::string_view token, uint64_t& value) {
  auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && ptr == token.data() + token.size();
}

// ---------------------------------------------------------------------------------------------
// Attributes shared by the PLY and OFF readers

// Records a read-but-not-kept property once.
inline void note_ignored(ReadReport& report, std::string what) {
  for (const std::string& known : report.ignored_properties) {
    if (known == what) return;
  }
  report.ignored_properties.push_back(std::move(what));
}

// Whether a tuple of attribute values means "none" (every value NaN: what our writers put at
// a corner without one). Values that are partly NaN, or infinite, are an error.
enum class TupleKind { kValue, kNone, kInvalid };

inline TupleKind classify_tuple(const float* values, int dims) {
  int nans = 0;
  for (int d = 0; d < dims; ++d) {
    if (std::isnan(values[d])) {
      ++nans;
    } else if (!std::isfinite(values[d])) {
      return TupleKind::kInvalid;
    }
  }
  if (nans == 0) return TupleKind::kValue;
  return nans == dims ? TupleKind::kNone : TupleKind::kInvalid;
}

// A per-vertex attribute (one tuple of `dims` per vertex, all-NaN for none) as a table and
// per-corner indices: a corner indexes its vertex's entry. Returns the first vertex with an
// invalid tuple, or -1.
inline int64_t attach_per_vertex(std::vector<float>& values, int dims,
                          const std::vector<uint32_t>& triangles, std::vector<float>& table,
                          std::vector<uint32_t>& indices) {
  const std::size_t vertices = values.size() / dims;
  std::vector<bool> none(vertices, false);
  for (std::size_t v = 0; v < vertices; ++v) {
    float* tuple = &values[v * dims];
    switch (classify_tuple(tuple, dims)) {
      case TupleKind::kValue:
        break;
      case TupleKind::kNone:
        none[v] = true;
        // The table holds finite values only; no corner will index this entry.
        std::fill(tuple, tuple + dims, 0.0f);
        break;
      case TupleKind::kInvalid:
        return static_cast<int64_t>(v);
    }
  }
  indices.resize(triangles.size());
  for (std::size_t c = 0; c < triangles.size(); ++c) {
    indices[c] = none[triangles[c]] ? kNoAttribute : triangles[c];
  }
  table = std::move(values);
  return -1;
}

// Builds a table of distinct values (bit for bit) from per-corner tuples, in order of first
// appearance. Used for per-corner lists (PLY texcoord, corner_normals).
class ValueTable {
 public:
  ValueTable(std::vector<float>& table, int dims) : table_(table), dims_(dims) {}

  uint32_t add(const float* tuple) {
    uint64_t key[2] = {0, 0};
    std::memcpy(key, tuple, sizeof(float) * static_cast<std::size_t>(dims_));
    const auto [it, inserted] =
        ids_.try_emplace(Key{key[0], key[1]}, static_cast<uint32_t>(table_.size() / dims_));
    if (inserted) table_.insert(table_.end(), tuple, tuple + dims_);
    return it->second;
  }
  std::size_t size() const { return table_.size() / dims_; }

 private:
  struct Key {
    uint64_t low, high;
    bool operator==(const Key& other) const { return low == other.low && high == other.high; }
  };
  struct KeyHash {
    std::size_t operator()(const Key& key) const {
      return std::hash<uint64_t>()(key.low * 0x9E3779B97F4A7C15ull ^ key.high);
    }
  };
  std::vector<float>& table_;
  int dims_;
  std::unordered_map<Key, uint32_t, KeyHash> ids_;
};

// Whether a number token is a plain integer ([+-]digits): Geomview's colour specification
// tells 0..255 integers from 0..1 floats by this.
inline bool is_integer_token(std::string_view token) {
  std::size_t i = 0;
  if (i < token.size() && (token[i] == '+' || token[i] == '-')) ++i;
  if (i == token.size()) return false;
  for (; i < token.size(); ++i) {
    if (token[i] < '0' || token[i] > '9') return false;
  }
  return true;
}

}  // namespace pm::detail
