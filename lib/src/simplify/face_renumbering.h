// The collapse loop's faces renumbered without the dead ones, between its rounds: each live
// face keeps its place among the live (new ids in increasing order), so that every walk and
// every order the loop takes stays the same and its sequence does not change; the per-face
// arrays shrink in place and give their ends back (memory_pages.h, shrink_in_place()).
//
// Why. A collapse kills two faces but frees nothing: the per-face arrays (half-edges,
// corner records, tracked points' lists) kept every face to the end, where the sequence's
// record had grown beside them, and the loop's memory peaked there (pmenc --fast on the
// 950K-face textured mesh: 223 MiB at its last round, when a third of its faces were dead
// after the first round and two thirds after the second; 187 MiB, in its second round, once
// renamed). Internal to simplify/.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/memory_pages.h"

namespace pm {

struct FaceRenumbering {
  static constexpr uint32_t kGone = 0xffffffffu;
  std::vector<uint32_t> new_id;  // per face: its id among the live, kGone when dead
  std::size_t live = 0;

  explicit FaceRenumbering(const std::vector<uint8_t>& face_dead) : new_id(face_dead.size(), kGone) {
    for (std::size_t f = 0; f < face_dead.size(); ++f)
      if (!face_dead[f]) new_id[f] = static_cast<uint32_t>(live++);
  }

  // Half-edge h = 3f + k of a live face f, renamed; kGone for a dead face's.
  uint32_t half_edge(uint32_t h) const {
    const uint32_t f = new_id[h / 3];
    return f == kGone ? kGone : 3 * f + h % 3;
  }

  // values holds `per` entries per face: each live face's move to its new place (never
  // after its old one), and the rest go.
  template <class T>
  void compact(std::vector<T>& values, std::size_t per) const {
    if (values.empty()) return;
    for (std::size_t f = 0; f < new_id.size(); ++f) {
      const uint32_t to = new_id[f];
      if (to == kGone || to == f) continue;
      for (std::size_t k = 0; k < per; ++k) values[per * to + k] = values[per * f + k];
    }
    detail::shrink_in_place(values, per * live);
  }
};

}  // namespace pm
