// The collapse loop's recorded error as a true bound without the measure (issue 25;
// EncodeOptions::fast: with the measure, tracked_points.h tracks every point, exactly, for a
// few percent more time): a face keeps only its kKept farthest removed input vertices
// (kept_points.h), so the others, dropped, are no longer measured; here each face f carries
// instead a slack r_f, at least the distance to f of every point dropped onto it. The slack
// grows by the gap between the surfaces at every later collapse of its face, so the records
// are loose: 1.0 to 8.7 times the largest distance of an input vertex to the level on the
// shared meshes at 50/10/2% (tests/bench/bound.md at c0f33ce, with the measure then).
// Internal to simplify/.
//
// Why the record then bounds the distance of every input vertex to the level's surface.
// Invariant: every removed input vertex p lies on one alive face f, either kept there (its
// distance to f measured exactly, when it was placed: kept_points.cpp) or dropped, with
// d(p, f) <= r_f. A collapse v -> u changes v's faces only (u stays in place), and:
// - a point dropped now (off the list of a face of the new fan, or never let on it) was
//   just measured against that face: r_f takes its distance (drop());
// - a point dropped earlier onto an old face g of v (moved or removed) is somewhere within
//   r_g of g; its nearest point q on g has an image F(q) on the new fan with
//   |q - F(q)| <= h, so d(p, F(q)) <= r_g + h, and the new face that holds F(q) takes that
//   slack (collapse()). F is the mapping of Cohen, Manocha and Olano 1997 ("Simplifying
//   polygonal models using successive mappings"): v's faces before and the faces that
//   replace them after, projected on one plane (the normal of v's faces), both triangulate
//   the same polygon, v's ring, and F maps a point of the old surface to the point of the
//   new one over the same place of the plane. Over a cell of the overlay of the two
//   projected triangulations, q lies on one old face and F(q) on one new face T, so
//   d(q, T) <= |q - F(q)|; d(., T) is convex, so its largest over the cell's part of the old
//   face is at the cell's corners: measured there, it is h, for the points of that cell,
//   which go to T (Cohen, Manocha and Olano measure |q - F(q)| at the same corners). The
//   projected triangles must all be positive (else F may fold): otherwise, and where the
//   ring is odd (a boundary vertex collapsing inwards), a coarser bound, valid always:
//   q -> d(q, T) is convex for one triangle T, so its largest over a piece of g is at the
//   piece's corners; g cut into 64 pieces, each takes the fan face T of least largest
//   distance of its corners, and its points go there with r_g plus that distance.
// Each collapse records the largest slack it sets and the largest distance of the points
// it measured (kept_points.cpp), and the sequence records the running maximum: every
// alive face's slack and kept distance was recorded by some collapse so far, so the
// record bounds the distance of every input vertex to the level's surface. Regions on
// several threads (simplifier.cpp) touch disjoint faces, and a merged order keeps
// each region's own order, so the argument holds for their merge too.
//
// Guéziec 1996 ("Surface simplification with variable tolerance") bounds the same
// thing with an error value per vertex, blended linearly over each face into a tolerance
// volume that each collapse must enclose: an accumulated bound as here, but carried by
// every face, where the slack here is carried only by faces that dropped points (the
// others are measured exactly), and the mapping keeps the increments to the surfaces'
// actual gap rather than a vertex's displacement.
//
// Cost per collapse: nothing unless one of v's faces has a slack; then one projection and,
// per such face, a clip against each of the (at most 64) faces that replace v's: bounded,
// whatever the faces absorbed.
#pragma once

#include <cstdint>
#include <vector>

#include "simplify/geometry.h"
#include "simplify/kept_points.h"

namespace pm::collapse_loop {

class DroppedPointsBound {
 public:
  // n_faces faces, none with a dropped point; 0 frees the memory.
  void reset(std::size_t n_faces);
  // Asks for face f's slack ahead of collapse(). Inlined always (CollapseLoop::fetch()).
  [[gnu::always_inline]] void prefetch(uint32_t f) const { __builtin_prefetch(&slack_[f]); }

  // A point dropped onto `face`, at `distance` from it.
  void drop(uint32_t face, double distance) { raise(face, distance); }
  // A point that found no face (only on non-finite input): nothing bounds it.
  void lose() { lost_ = true; }

  // The collapse v -> u as the bound sees it, before the faces change: v's position, its
  // ring of n neighbours in order (ring[i], ring[i + 1] and v make old face i, the ring
  // closed or, for a boundary vertex, open: n - 1 faces), u's place in the ring, the old
  // faces' ids (the moved ones keep theirs, with u in place of v), and the removed faces
  // fl, fr (kNone when absent). `fan`: every face around u after it (the coarse bound's
  // candidates). Moves the slack of v's faces onto the new fan's; returns the largest
  // slack it set (0 if none), or infinity when some slack found no face.
  struct Star {
    Vec3 v;
    const Vec3* ring;
    int n;
    bool closed;
    int u_at;
    const uint32_t* faces;
    uint32_t fl, fr;
  };
  double collapse(const Star& star, const KeptPoints::FanFace* fan, int n_fan);

  // Whether a point was lost since the last call (and forgets it).
  bool take_lost() {
    const bool lost = lost_;
    lost_ = false;
    return lost;
  }

 private:
  static constexpr uint32_t kNone = 0xffffffffu;
  // slack_[f] = max(slack_[f], d), rounded up to a float.
  void raise(uint32_t face, double d);
  // The coarse bound of triangle (a, b, c), slack r, against the fan: cut into
  // kCoarseSplits^2 small triangles, each bounded by its best fan face t (the largest
  // distance of its corners to t), which takes r plus that in to_fan[t]. False when the
  // fan has no face.
  static constexpr int kCoarseSplits = 8;
  static bool coarse(const Vec3& a, const Vec3& b, const Vec3& c, double r,
                     const KeptPoints::FanFace* fan, int n_fan, double* to_fan);

  std::vector<float> slack_;  // per face; negative: no dropped point
  bool lost_ = false;
};

}  // namespace pm::collapse_loop
