// The measured loop's tracked points: see tracked_points.h (after Klein, Liebich and Straßer
// 1996).
#include "simplify/tracked_points.h"

#include <algorithm>
#include <cmath>

#include "core/memory_pages.h"

namespace pm::collapse_loop {

void TrackedPoints::reset(std::size_t n_faces, std::size_t n_vertices, const float* xyz) {
  if (n_faces == 0) {  // the loop is over: the memory goes back
    std::vector<uint32_t>().swap(head_);
    std::vector<uint32_t>().swap(next_);
    xyz_ = nullptr;
    return;
  }
  xyz_ = xyz;
  detail::assign_preferring_huge_pages(head_, n_faces, kNone);
  detail::assign_preferring_huge_pages(next_, n_vertices, kNone);
}

// A fan face's plane and its barycentric frame, made once a collapse by collapse() (when it
// moves at least as many points as the fan has faces) and read by each of its parts (every
// 256 points, on either thread): a point whose foot on the plane falls strictly inside
// the triangle is at its height from it, which a few dot products give and no division
// (Ericson 2005, "Real-Time Collision Detection", §3.4: the foot's barycentric coordinates
// by Cramer's rule on the edges' Gram matrix), where point_triangle_squared_distance() walks
// the Voronoi regions and divides twice. It only says "surely within": any other point
// takes the exact distance, as before. Nefertiti after two Loop steps without the measure,
// one thread, medians of 9 alternating runs: 2.91 -> 2.68 s; the same .pm files from the
// shared meshes, the 950,272-face textured mesh and the Loop mesh, with the measure and
// without (block_features.obj without the measure: 100 records of a flat block 2.2e-16
// where they were 4.4e-16, both the rounding of a distance 0).
struct TrackedPoints::PlaneScreen {
  Vec3 a, e1, e2, normal;
  double g11, g12, g22, det, inverse_normal2;
  static PlaneScreen make(const KeptPoints::FanFace& face) {
    PlaneScreen s;
    s.a = face.a;
    s.e1 = face.b - face.a;
    s.e2 = face.c - face.a;
    s.normal = s.e1 % s.e2;
    s.g11 = s.e1 | s.e1;
    s.g12 = s.e1 | s.e2;
    s.g22 = s.e2 | s.e2;
    s.det = s.g11 * s.g22 - s.g12 * s.g12;
    const double normal2 = s.normal.sqrnorm();
    // A sliver's frame rounds badly: it screens nothing (det 0 fails every test below).
    if (!(s.det > 1e-12 * s.g11 * s.g22) || !(normal2 > 0)) s.det = 0;
    s.inverse_normal2 = normal2 > 0 ? 1.0 / normal2 : 0;
    return s;
  }
  // Whether x is surely within the distance whose surely-within square is stop2: its foot
  // strictly inside, and its squared height below stop2 with a margin (2^-30 of it) far
  // above the rounding of either formula.
  bool surely_within(const Vec3& x, double stop2) const {
    const Vec3 w = x - a;
    const double s1 = e1 | w, s2 = e2 | w;
    const double beta = g22 * s1 - g12 * s2, gamma = g11 * s2 - g12 * s1;
    if (!(beta > 0 && gamma > 0 && beta + gamma < det)) return false;
    const double h = normal | w;
    return h * h * inverse_normal2 <= stop2 * (1 - 0x1p-30);
  }
};

template <typename Push>
double TrackedPoints::move(const uint32_t* pairs, std::size_t count, const KeptPoints::FanFace* fan,
                           int n_fan, const PlaneScreen* screens, double settled, uint8_t* lost,
                           Push push) {
  // Their positions, asked for all at once: the points of a face are far apart in memory.
  for (std::size_t i = 0; i < count; ++i) __builtin_prefetch(xyz_ + 3 * std::size_t{pairs[2 * i]});
  // The first face within `settled`, or within the largest distance so far of this part's
  // points (the one it was on tried first), keeps it: a bound of its distance that the
  // record holds anyway. With the second, nefertiti after two Loop steps without the
  // measure, one thread, medians of 5 alternating runs: 2.38 -> 2.30 s.
  double farthest = 0, stop = settled, stop2 = square_surely_within(settled);
  for (std::size_t i = 0; i < count; ++i) {
    const uint32_t x = pairs[2 * i];
    const float* p = xyz_ + 3 * std::size_t{x};
    const Vec3 position(p[0], p[1], p[2]);
    const int hint = pairs[2 * i + 1] == kNone ? -1 : static_cast<int>(pairs[2 * i + 1]);
    int at = hint;
    double d2 = HUGE_VAL;
    if (screens && hint >= 0 && screens[hint].surely_within(position, stop2)) {
      push(at, x);
      continue;
    }
    if (hint >= 0) {
      const KeptPoints::FanFace& face = fan[hint];
      d2 = point_triangle_squared_distance(position, face.a, face.b, face.c);
    }
    // Most points (86% on nefertiti after two Loop steps) stay, well within `stop`: their
    // square says so without their root, and their distance changes no record (it is at
    // most the part's largest so far, or at most `settled`, which the record holds anyway:
    // collapse()'s result may leave it out).
    if (!(d2 <= stop2)) {  // without a face to try first, d2 is infinite: nearest()'s search
      const double d = KeptPoints::nearest_from(position, fan, n_fan, stop, hint, d2, &at);
      if (at < 0) {  // no distance compares (non-finite input): no finite record bounds it
        *lost = 1;
        continue;
      }
      if (d > farthest) {
        farthest = d;
        if (farthest > stop) {
          stop = farthest;
          stop2 = square_surely_within(stop);
        }
      }
    }
    push(at, x);
  }
  return farthest;
}

double TrackedPoints::collapse(uint32_t v, const uint32_t* old_faces, int n_old,
                               const KeptPoints::FanFace* fan, int n_fan, double settled,
                               Scratch& scratch, PartRunner* runner) {
  // v and the points of v's faces, each with the fan index of the face it was on (a moved
  // face keeps its id; the fan lists v's faces first, in the order of old_faces, but the two
  // at v-u), which it tries first: most stay where they were. Pairs (point, fan index or
  // kNone) in scratch.points.
  std::vector<uint32_t>& points = scratch.points;
  points.clear();
  points.push_back(v);
  points.push_back(kNone);
  // A removed face (at v-u) has no fan index: its points try first the face after it
  // around v, or before it (the faces that shared its edges at v, moved onto u), instead of
  // searching the fan. Nefertiti after two Loop steps without the measure, one thread,
  // medians of 5 alternating runs: 2.50 -> 2.36 s (6.6M of the 22.9M points moved had no
  // face to try first, v among them); the records at bound.md's points the same.
  uint32_t hints[kMaxOldFaces];
  for (int i = 0, j = 0; i < n_old; ++i)
    hints[i] = j < n_fan && fan[j].face == old_faces[i] ? static_cast<uint32_t>(j++) : kNone;
  for (int i = 0; i < n_old; ++i) {
    const uint32_t f = old_faces[i];
    uint32_t hint = hints[i];
    if (hint == kNone) {
      hint = hints[i + 1 < n_old ? i + 1 : 0];
      if (hint == kNone) hint = hints[i > 0 ? i - 1 : n_old - 1];
    }
    for (uint32_t x = head_[f]; x != kNone; x = next_[x]) {
      points.push_back(x);
      points.push_back(hint);
    }
    head_[f] = kNone;
  }
  if (n_fan == 0) return HUGE_VAL;  // nowhere to go: no finite record bounds them
  const std::size_t n = points.size() / 2;
  // The fan's screens, made once for every part: only where the points are at least as many
  // as the fan's faces (else the frames cost more than the distances they save) and `settled`
  // lets a point stay (screens test against its square).
  constexpr int kMaxScreens = 2 * kMaxOldFaces;  // the loop's fans are at most this
  PlaneScreen screen_storage[kMaxScreens];
  const PlaneScreen* screens = nullptr;
  if (square_surely_within(settled) > 0 && n_fan <= kMaxScreens &&
      n >= static_cast<std::size_t>(n_fan)) {
    for (int i = 0; i < n_fan; ++i) screen_storage[i] = PlaneScreen::make(fan[i]);
    screens = screen_storage;
  }
  const std::size_t parts = n < 2 * kPartPoints ? 1 : (n + kPartPoints - 1) / kPartPoints;
  if (parts == 1) {
    // One part, in turn: each point straight onto the front of its face's list, as the
    // joining below would put it (nefertiti after two Loop steps: 0.8M collapses of about 28
    // points each, where the part's lists and their joining were a tenth of the tracking).
    uint8_t lost = 0;
    const double farthest =
        move(points.data(), n, fan, n_fan, screens, settled, &lost, [&](int at, uint32_t x) {
          uint32_t& head = head_[fan[at].face];
          next_[x] = head;
          head = x;
        });
    return lost ? HUGE_VAL : farthest;
  }
  const std::size_t fan_size = static_cast<std::size_t>(n_fan);
  scratch.lists.assign(2 * parts * fan_size, kNone);
  scratch.farthest.assign(parts, 0.0);
  scratch.lost.assign(parts, 0);
  // noexcept: a part another thread runs must end, and count itself done (nothing in it
  // allocates).
  const std::size_t part_size = parts == 1 ? n : kPartPoints;
  const auto part = [&](uint32_t j) noexcept {
    const std::size_t begin = j * part_size, end = std::min(n, begin + part_size);
    uint32_t* heads = &scratch.lists[2 * j * fan_size];
    uint32_t* tails = heads + fan_size;
    scratch.farthest[j] = move(&points[2 * begin], end - begin, fan, n_fan, screens, settled,
                               &scratch.lost[j], [&](int at, uint32_t x) {
                                 if (heads[at] == kNone) tails[at] = x;
                                 next_[x] = heads[at];
                                 heads[at] = x;
                               });
  };
  if (parts > 1 && runner) {
    runner->run_parts(static_cast<uint32_t>(parts), part);
  } else {
    for (uint32_t j = 0; j < parts; ++j) part(j);
  }
  // Each part's lists onto the front of its faces', in the parts' order: as if every point
  // had gone onto the front of its face's list in turn.
  double farthest = 0;
  bool lost = false;
  for (std::size_t j = 0; j < parts; ++j) {
    const uint32_t* heads = &scratch.lists[2 * j * fan_size];
    const uint32_t* tails = heads + fan_size;
    for (std::size_t i = 0; i < fan_size; ++i) {
      if (heads[i] == kNone) continue;
      const uint32_t f = fan[i].face;
      next_[tails[i]] = head_[f];
      head_[f] = heads[i];
    }
    farthest = std::max(farthest, scratch.farthest[j]);
    lost |= scratch.lost[j] != 0;
  }
  return lost ? HUGE_VAL : farthest;
}

}  // namespace pm::collapse_loop
