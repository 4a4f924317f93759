// Corner attribute ids as codes (pm-format.md §5.10 in 1.1, the same codes in 2.0): 0 none;
// 1 the id this vertex's previous corner had; n >= 2 the previous corner's id (in corner
// order) plus unzigzag(n - 2). Most corners of a vertex share its wedge (Hoppe 1996, §3),
// so after a vertex's first corner its others are mostly code 1. Internal to the codec.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "byte_io.h"
#include "pm/mesh.h"  // kNoAttribute

namespace pm::detail {

struct CornerPredictor {
  std::vector<uint32_t> last;  // per vertex with corners: its latest id, or kNoAttribute
  int64_t previous = 0;        // the latest id of any corner

  explicit CornerPredictor(std::size_t vertices) : last(vertices, kNoAttribute) {}

  uint32_t encode(uint32_t vertex, uint32_t id) {
    if (id == kNoAttribute) return 0;
    uint32_t code = 1;
    if (last[vertex] != id) code = static_cast<uint32_t>(zigzag(int64_t{id} - previous) + 2);
    last[vertex] = id;
    previous = id;
    return code;
  }

  // The id of `code` at a corner of `vertex`, below `count`; false with `problem` set when
  // the code names no id, an id out of range, or is not the code encode() would write.
  bool decode(uint32_t code, uint32_t vertex, uint32_t count, uint32_t& id,
              std::string& problem) {
    id = kNoAttribute;
    if (code == 1) {
      id = last[vertex];
      if (id == kNoAttribute) {
        problem = "repeats the id of vertex " + std::to_string(vertex) + ", which has none yet";
        return false;
      }
    } else if (code >= 2) {
      const int64_t value = previous + unzigzag(code - 2);
      if (value < 0 || value >= count) {
        problem = "has id " + std::to_string(value) + " of " + std::to_string(count);
        return false;
      }
      id = static_cast<uint32_t>(value);
      // One encoding per value: an id the vertex repeats must be written as code 1.
      if (id == last[vertex]) {
        problem = "spells out id " + std::to_string(id) + ", which its vertex repeats (code 1)";
        return false;
      }
    }
    if (id != kNoAttribute) {
      last[vertex] = id;
      previous = id;
    }
    return true;
  }
};

}  // namespace pm::detail
