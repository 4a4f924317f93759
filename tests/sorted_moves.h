// A 2.0 .pm reader stores each split's moved faces in the order of u's fan (Hoppe 1998, §4),
// which need not be the encoder's order: for comparing progressive meshes, sort each
// split's moved faces together with their corner ids. Shared by the tests and the fuzzers.
#pragma once

#include <algorithm>
#include <cstdint>
#include <tuple>
#include <vector>

#include "pm/progressive_mesh.h"

namespace pm::test {

inline ProgressiveMesh with_sorted_moves(ProgressiveMesh pm) {
  std::vector<std::tuple<uint32_t, uint32_t, uint32_t>> moved;
  for (const VertexSplit& split : pm.splits) {
    moved.clear();
    for (uint32_t k = split.moved_begin; k < split.moved_begin + split.moved_count; ++k) {
      moved.emplace_back(pm.moved_faces[k], pm.has_uvs() ? pm.moved_uvs[k] : 0,
                         pm.has_normals() ? pm.moved_normals[k] : 0);
    }
    std::sort(moved.begin(), moved.end());
    for (uint32_t k = 0; k < split.moved_count; ++k) {
      pm.moved_faces[split.moved_begin + k] = std::get<0>(moved[k]);
      if (pm.has_uvs()) pm.moved_uvs[split.moved_begin + k] = std::get<1>(moved[k]);
      if (pm.has_normals()) pm.moved_normals[split.moved_begin + k] = std::get<2>(moved[k]);
    }
  }
  return pm;
}

}  // namespace pm::test
