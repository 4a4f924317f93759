// How far a texture seam has drifted from the input's seam curve, tracked through the
// collapses. A seam collapse slides v along the seam onto u (Hoppe 1999, "New quadric
// metric for simplifying meshes with appearance attributes", §5; Garland and Heckbert 1998,
// §4: collapse along a discontinuity, never across it), so the seam polyline u-v-w
// becomes the chord u-w. The constraint planes of the quadric hold that chord in place on
// average; this measures the worst case, as kept_points.h does for the surface (Klein,
// Liebich and Straßer 1996): every input vertex of a seam that has been removed is
// attached to the current seam edge that replaced it, and a collapse is charged the largest
// distance from the points it would attach to the new edge.
//
// Why it matters. The surface distance does not see a seam that moves within the surface
// (a chord across a flat region lies on the surface), but the texture does: the faces on one
// side of the chord then show their chart where the input showed the other one. On spot at
// 10% of the faces, such chords made most of the texture-coordinate error measured at the
// closest surface point (tests/bench/uv.md).
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include "simplify/corner_attributes.h"

namespace pm {

class SeamDrift {
 public:
  // A texture seam's drift within the surface counts this many times a distance off the
  // surface in a collapse loop's measured key. Tuned on tests/bench/uv.md (spot, and the
  // vase sample with three charts at 10%, 2% and 1%): at 2.8 (x^2 = 8) spot's seams still
  // slid at 10%; at 4 (x^2 = 16) the vase's interior at 2% paid for the seams it kept. 3.5
  // holds both (tuned on the former default loop, commit 3cb92db). The quadric metric's key
  // weighs the measure twice and scales this by 1/sqrt(2) (collapse_loop.h, kDriftScale);
  // Schroeder's takes it as it is.
  static constexpr double kDriftScale = 3.5;

  // The seams are the texture-coordinate seams of `attributes` (in its face and vertex
  // ids) as they are now; points holds three floats per vertex (n_vertices), which never
  // move (a half-edge collapse keeps u where it is) and stay the caller's.
  SeamDrift(const float* points, std::size_t n_vertices, const CornerAttributes& attributes);

  // If the collapse c (v -> u) were made: when v lies on a seam (two seam edges, v-u and
  // v-w), the largest distance from v and the removed seam points of v-u and v-w to the
  // segment u-w; 0 when v is on no seam.
  double collapse_drift(const CollapseStar& c) const;

  // Attaches v and those points to u-w. Call just before the loop makes the collapse.
  // Collapses whose stars share no vertex may call this and collapse_drift() on several
  // threads at once (the collapse loop's regions): each touches only its own vertices' lists.
  void collapse(const CollapseStar& c);

 private:
  static constexpr uint32_t kNone = 0xffffffffu;
  static constexpr std::size_t kMeasuredPoints = 256;  // per seam edge and query
  // The seam neighbour of v other than u, kNone when v is not on exactly two seam edges
  // with one of them v-u (then the collapse moves no seam: the legality rules allow no
  // other seam collapse).
  uint32_t other_seam_end(const CollapseStar& c) const;
  // The removed input seam vertices that seam edge a-b replaced, in the order they joined
  // it: the list is the smaller end's, an entry per edge to a larger vertex.
  struct Attached {
    uint32_t other;  // the larger end
    std::vector<uint32_t> points;
  };
  std::vector<Attached>& lists_of(uint32_t a, uint32_t b) {
    std::unique_ptr<std::vector<Attached>>& lists = points_[std::min(a, b)];
    if (!lists) lists = std::make_unique<std::vector<Attached>>();
    return *lists;
  }
  const std::vector<uint32_t>* find(uint32_t a, uint32_t b) const;
  Vec3 point(uint32_t x) const {
    const float* p = points_xyz_ + 3 * std::size_t{x};
    return Vec3(p[0], p[1], p[2]);
  }

  const float* points_xyz_;
  const CornerAttributes& attributes_;
  // Per vertex, its current seam edges to larger vertices that carry removed points. A
  // collapse reads and writes only the lists of v, u and w, so regions of the collapse loop on
  // other threads, whose collapses share no vertex with it, need no lock. Made when first
  // needed: only seam vertices have any, and an empty vector per vertex took 11 of the
  // 950K-face textured mesh's 393 MB.
  std::vector<std::unique_ptr<std::vector<Attached>>> points_;
};

}  // namespace pm
