// Fans of faces around a vertex, kept up to date split by split (see split_fans.h;
// Hoppe 1996, §3, and Hoppe 1998, §4).
#include "split_fans.h"

#include <algorithm>

#include "core/memory_pages.h"

namespace pm::detail {

void SplitFans::reset(std::size_t vertex_count, std::size_t face_count) {
  faces_.clear();
  first_corner_.clear();
  faces_.reserve(face_count);
  first_corner_.reserve(vertex_count);
  // Fans are walked at random over the whole mesh: huge pages spare most TLB misses.
  prefer_huge_pages(faces_);
  prefer_huge_pages(first_corner_);
}

void SplitFans::link(uint32_t corner, uint32_t vertex) {
  if (vertex >= first_corner_.size()) first_corner_.resize(std::size_t{vertex} + 1, kNone);
  next_corner(corner) = first_corner_[vertex];
  first_corner_[vertex] = corner;
}

void SplitFans::relink(uint32_t vertex, const uint32_t* corners, std::size_t count) {
  first_corner_[vertex] = corners[0];
  for (std::size_t k = 0; k + 1 < count; ++k) next_corner(corners[k]) = corners[k + 1];
  next_corner(corners[count - 1]) = kNone;
}

void SplitFans::add_face(uint32_t a, uint32_t b, uint32_t c) {
  const auto corner = static_cast<uint32_t>(3 * faces_.size());
  faces_.push_back({{a, b, c}, {kNone, kNone, kNone}});
  link(corner, a);
  link(corner + 1, b);
  link(corner + 2, c);
}

bool SplitFans::holds_once(uint32_t f, uint32_t u) const {
  if (f >= face_count()) return false;
  const uint32_t* v = face(f);
  return (v[0] == u) + (v[1] == u) + (v[2] == u) == 1;
}

bool SplitFans::fan(uint32_t u, Fan& out) {
  out.ring.clear();
  out.faces.clear();
  out.closed = false;
  if (u >= first_corner_.size()) return false;
  // Over the last fan's wedges in place, then appended (cheaper than a push_back each).
  const std::size_t room = wedges_.size();
  std::size_t n = 0;
  for (uint32_t c = first_corner_[u]; c != kNone; ++n) {
    const uint32_t f = c / 3, k = c % 3;
    const Face& face = faces_[f];
    const Wedge wedge{face.vertex[(k + 1) % 3], face.vertex[(k + 2) % 3], f, c};
    if (n < room) {
      wedges_[n] = wedge;
    } else {
      wedges_.push_back(wedge);
    }
    c = face.next[k];
  }
  wedges_.resize(n);
  if (n == 0) return false;
  if (chained_fan(out)) return true;
  ++searches_;
  if (n <= kSmallFan) return small_fan(u, out);
  // Sorted by a, each a and each b at most once: then every wedge has at most one
  // successor (the wedge whose a is its b), and the wedges form paths and cycles.
  std::sort(wedges_.begin(), wedges_.end(),
            [](const Wedge& x, const Wedge& y) { return x.a < y.a; });
  seconds_.clear();
  for (const Wedge& w : wedges_) seconds_.push_back(w.b);
  std::sort(seconds_.begin(), seconds_.end());
  for (std::size_t k = 1; k < n; ++k) {
    if (wedges_[k].a == wedges_[k - 1].a || seconds_[k] == seconds_[k - 1]) return false;
  }
  const auto find = [&](uint32_t a) -> const Wedge* {
    const auto it = std::lower_bound(wedges_.begin(), wedges_.end(), a,
                                     [](const Wedge& w, uint32_t value) { return w.a < value; });
    return it != wedges_.end() && it->a == a ? &*it : nullptr;
  };
  // An open fan starts at the one wedge whose a is no wedge's b.
  const Wedge* start = nullptr;
  for (const Wedge& w : wedges_) {
    if (!std::binary_search(seconds_.begin(), seconds_.end(), w.a)) {
      if (start != nullptr) return false;  // two open fans: u is pinched
      start = &w;
    }
  }
  out.closed = start == nullptr;
  if (out.closed) start = &wedges_[0];  // the smallest neighbour first
  const Wedge* w = start;
  seconds_.clear();  // now the corners in fan order
  out.ring.push_back(w->a);
  for (std::size_t k = 0; k < n; ++k) {
    out.faces.push_back(w->face);
    out.ring.push_back(w->b);
    seconds_.push_back(w->corner);
    if (k + 1 == n) break;
    w = find(w->b);
    if (w == nullptr || w == start) return false;  // several fans
  }
  // All n wedges walked: a closed fan must come back to its start, an open one must not.
  if (out.closed != (out.ring.back() == out.ring.front())) return false;
  relink(u, seconds_.data(), n);
  return true;
}

// A vertex's corners already in fan order, as split() and small_fan() leave them: each
// wedge's b is the next one's a. The fan is then the list itself (rotated, when closed, to
// start at the smallest neighbour), once the checks small_fan() makes hold: each a once, and
// the last b none of the a's after the first (so each b is once too, and no wedge is (a, a)
// but a lone one, which small_fan() takes too). Then small_fan() finds this same path or
// cycle; anything else is left to it.
bool SplitFans::chained_fan(Fan& out) {
  const std::size_t n = wedges_.size();
  const Wedge* w = wedges_.data();
  for (std::size_t k = 0; k + 1 < n; ++k) {
    if (w[k].b != w[k + 1].a) return false;
  }
  const uint32_t last_b = w[n - 1].b;
  std::size_t smallest = 0;
  if (n <= kSmallFan) {
    // Each a once: a 128-bit set of hashed a's (Fibonacci hashing, Knuth 1998, TAOCP vol. 3,
    // §6.4) finds no two alike in most fans (on nefertiti's splits, 7.5 faces on average,
    // one in six has two in one place), and only a fan where it does is compared pair by
    // pair (the pairs cost more than the rest of the walk).
    uint64_t seen[2] = {0, 0};
    bool alike = false;
    for (std::size_t i = 0; i < n; ++i) {
      if (i > 0 && w[i].a == last_b) return false;
      const auto place = static_cast<unsigned>((w[i].a * 0x9E3779B97F4A7C15ull) >> 57);
      const uint64_t bit = uint64_t{1} << (place & 63);
      alike |= (seen[place >> 6] & bit) != 0;
      seen[place >> 6] |= bit;
      if (w[i].a < w[smallest].a) smallest = i;
    }
    for (std::size_t i = 0; alike && i < n; ++i) {
      for (std::size_t j = i + 1; j < n; ++j) {
        if (w[j].a == w[i].a) return false;
      }
    }
  } else {  // the same checks, sorted
    seconds_.clear();
    for (std::size_t i = 0; i < n; ++i) {
      seconds_.push_back(w[i].a);
      if (w[i].a < w[smallest].a) smallest = i;
    }
    std::sort(seconds_.begin(), seconds_.end());
    if (std::adjacent_find(seconds_.begin(), seconds_.end()) != seconds_.end()) return false;
    if (last_b != w[0].a && std::binary_search(seconds_.begin(), seconds_.end(), last_b)) return false;
  }
  out.closed = last_b == w[0].a;
  const std::size_t start = out.closed ? smallest : 0;
  out.ring.resize(n + 1);
  out.faces.resize(n);
  uint32_t* ring = out.ring.data();
  uint32_t* faces = out.faces.data();
  ring[0] = w[start].a;
  for (std::size_t k = 0, at = start; k < n; ++k, at = at + 1 == n ? 0 : at + 1) {
    faces[k] = w[at].face;
    ring[k + 1] = w[at].b;
  }
  return true;
}

// The same fan as below for a few wedges (nearly every vertex: valence 6 on average), by
// linear scans instead of sorts and binary searches: the same ring, start and faces. One
// pass over the pairs checks that each a and each b is unique and links each wedge to its
// successor (the wedge whose a is its b), so the walk needs no second scan. A fan found
// relinks u's corners in its order, for chained_fan() next time.
bool SplitFans::small_fan(uint32_t u, Fan& out) {
  const std::size_t n = wedges_.size();
  uint8_t next[kSmallFan];
  bool is_second[kSmallFan] = {};
  std::fill(next, next + n, static_cast<uint8_t>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const Wedge& wi = wedges_[i];
    for (std::size_t j = i + 1; j < n; ++j) {
      const Wedge& wj = wedges_[j];
      if (wj.a == wi.a || wj.b == wi.b) return false;
      if (wj.b == wi.a) {
        next[j] = static_cast<uint8_t>(i);
        is_second[i] = true;
      }
      if (wi.b == wj.a) {
        next[i] = static_cast<uint8_t>(j);
        is_second[j] = true;
      }
    }
    // A wedge whose b is its own a: (u, a, a) is not a face of a fan.
    if (wi.b == wi.a) {
      next[i] = static_cast<uint8_t>(i);
      is_second[i] = true;
    }
  }
  std::size_t start = n, smallest = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!is_second[i]) {
      if (start != n) return false;  // two open fans: u is pinched
      start = i;
    }
    if (wedges_[i].a < wedges_[smallest].a) smallest = i;
  }
  out.closed = start == n;
  if (out.closed) start = smallest;  // the smallest neighbour first
  std::size_t w = start;
  uint32_t corners[kSmallFan];  // u's corners in fan order
  out.ring.push_back(wedges_[w].a);
  for (std::size_t k = 0; k < n; ++k) {
    corners[k] = wedges_[w].corner;
    out.faces.push_back(wedges_[w].face);
    out.ring.push_back(wedges_[w].b);
    if (k + 1 == n) break;
    const std::size_t following = next[w];
    if (following == n || following == start) return false;  // several fans
    w = following;
  }
  if (out.closed != (out.ring.back() == out.ring.front())) return false;
  relink(u, corners, n);
  return true;
}

bool SplitFans::arc(const Fan& fan, std::size_t i, std::size_t j, std::vector<uint32_t>& faces) {
  faces.clear();
  const std::size_t n = fan.faces.size();
  if (fan.closed) {
    if (i >= n || j >= n || i == j) return false;
    for (std::size_t k = i; k != j; k = (k + 1) % n) faces.push_back(fan.faces[k]);
  } else {
    if (j > n || i > j) return false;
    for (std::size_t k = i; k < j; ++k) faces.push_back(fan.faces[k]);
  }
  return true;
}

void SplitFans::split(uint32_t u, uint32_t v, uint32_t vl, uint32_t vr, const uint32_t* moved,
                      std::size_t moved_count, const Fan* fan, std::size_t first) {
  if (fan != nullptr && moved_count > 0) return split_arc(u, v, vl, vr, *fan, first, moved_count);
  // The moved faces' corners leave u's list in one walk (unlinking each alone would walk
  // the list once per moved face), then join v's.
  if (moved_count > 0) {
    uint32_t* link = &first_corner_[u];
    while (*link != kNone) {
      const uint32_t c = *link;
      uint32_t& after = next_corner(c);
      if (std::find(moved, moved + moved_count, c / 3) != moved + moved_count) {
        *link = after;
      } else {
        link = &after;
      }
    }
  }
  for (std::size_t m = 0; m < moved_count; ++m) {
    const uint32_t f = moved[m];
    const auto k = static_cast<uint32_t>(slot_of(f, u));
    faces_[f].vertex[k] = v;
    link(3 * f + k, v);
  }
  if (v >= first_corner_.size()) first_corner_.resize(std::size_t{v} + 1, kNone);
  if (vl != kNone) add_face(v, u, vl);
  if (vr != kNone) add_face(u, v, vr);
}

// The split of the arc of `count` faces from place `first` of u's fan (Hoppe 1996, §3:
// vsplit(s, l, r)), with the corner lists of u, v, vl and vr left in fan order, as the
// swing order around a vertex of a corner table (Rossignac 2001, "3D compression made
// simple: Edgebreaker with ZipandWrap on a corner-table", §2). With r the ring, i = first
// and j = i + count: u keeps the faces from j on (around a closed fan, back to i - 1), then
// fl = (v, u, vl) and fr = (u, v, vr); v has the arc's faces i .. j-1, fr, then fl (fl
// first when there is no fr: v's fan then starts at u); vl = r[i] has fl just after face
// i; vr = r[j] has fr just after face j, or first when the arc ends an open fan. A list that
// was not in fan order before is not after, and fan() searches it as it would have.
void SplitFans::split_arc(uint32_t u, uint32_t v, uint32_t vl, uint32_t vr, const Fan& fan,
                          std::size_t first, std::size_t count) {
  const std::size_t n = fan.faces.size();
  // Places run to first + n < 2n: one subtraction wraps them (a division per face costs more
  // than the rest of the split).
  const uint32_t* fan_faces = fan.faces.data();
  const auto face_at = [&](std::size_t place) { return fan_faces[place < n ? place : place - n]; };
  const auto slot = [&](uint32_t f, uint32_t vertex) { return static_cast<uint32_t>(slot_of(f, vertex)); };
  const std::size_t end = first + count;  // place j (modulo n around a closed fan)
  if (v >= first_corner_.size()) first_corner_.resize(std::size_t{v} + 1, kNone);
  for (std::size_t k = first; k < end; ++k) {
    const uint32_t f = face_at(k);
    faces_[f].vertex[slot(f, u)] = v;
  }
  const auto new_face = [&](uint32_t a, uint32_t b, uint32_t c) {
    const auto f = static_cast<uint32_t>(faces_.size());
    faces_.push_back({{a, b, c}, {kNone, kNone, kNone}});
    return f;
  };
  const uint32_t fl = vl != kNone ? new_face(v, u, vl) : kNone;
  const uint32_t fr = vr != kNone ? new_face(u, v, vr) : kNone;
  const auto u_corner = [&](std::size_t place) {
    const uint32_t f = face_at(place);
    return 3 * f + slot(f, u);
  };
  // u's and then v's corners, each at most the fan's faces and the two new ones, written
  // through a pointer (push_back's capacity check per corner cost as much as the rest).
  if (corners_.size() < n + 2) corners_.resize(n + 2);
  uint32_t* const corners = corners_.data();
  uint32_t* out = corners;
  if (fan.closed) {
    for (std::size_t k = end; k < first + n; ++k) *out++ = u_corner(k);
  } else {
    for (std::size_t k = 0; k < first; ++k) *out++ = u_corner(k);
  }
  if (fl != kNone) *out++ = 3 * fl + 1;
  if (fr != kNone) *out++ = 3 * fr;
  if (!fan.closed) {
    for (std::size_t k = end; k < n; ++k) *out++ = u_corner(k);
  }
  if (out == corners) {
    first_corner_[u] = kNone;
  } else {
    relink(u, corners, static_cast<std::size_t>(out - corners));
  }
  out = corners;
  if (fl != kNone && fr == kNone) *out++ = 3 * fl;
  for (std::size_t k = first; k < end; ++k) {
    const uint32_t f = face_at(k);
    *out++ = 3 * f + slot(f, v);
  }
  if (fr != kNone) *out++ = 3 * fr + 1;
  if (fl != kNone && fr != kNone) *out++ = 3 * fl;
  relink(v, corners, static_cast<std::size_t>(out - corners));
  if (fl != kNone) {
    const uint32_t f = face_at(first);
    insert_after(3 * f + slot(f, vl), 3 * fl + 2);
  }
  if (fr != kNone) {
    if (fan.closed || end < n) {
      const uint32_t f = face_at(end);
      insert_after(3 * f + slot(f, vr), 3 * fr + 2);
    } else {
      link(3 * fr + 2, vr);
    }
  }
}

SplitFans::Prefetch::Prefetch(const SplitFans& fans, const std::vector<uint32_t>* values)
    : fans_(fans) {
  std::fill(vertex_, vertex_ + kAhead, kNone);
  std::fill(corner_, corner_ + kAhead, kNone);
  std::fill(row_face_, row_face_ + kAhead, kNone);
  also_values(values, 3);
}

inline void SplitFans::Prefetch::fetch_units(uint32_t f) const {
  for (int r = 0; r < n_rows_; ++r) {
    const Rows& rows = rows_[r];
    if (rows.units == nullptr || 3 * (std::size_t{f} + 1) > rows.ids->size()) continue;
    for (int k = 0; k < 3; ++k) {
      const std::size_t at = rows.per_id * std::size_t{(*rows.ids)[3 * std::size_t{f} + k]};
      if (at < rows.units->size()) __builtin_prefetch(rows.units->data() + at);
    }
  }
}

inline void SplitFans::Prefetch::fetch_values(uint32_t x) const {
  for (int i = 0; i < n_values_; ++i) {
    const PerVertex& v = values_[i];
    if (v.per_vertex * (std::size_t{x} + 1) <= v.values->size())
      __builtin_prefetch(v.values->data() + v.per_vertex * std::size_t{x});
  }
}

void SplitFans::Prefetch::step(uint32_t u_ahead) {
  const std::size_t faces = fans_.faces_.size(), vertices = fans_.first_corner_.size();
  for (std::size_t s = 0; s < kAhead; ++s) {
    if (row_face_[s] != kNone) fetch_units(row_face_[s]);
    row_face_[s] = kNone;
    uint32_t corner = corner_[s];
    if (corner == kNone) continue;
    if (corner == kFirst) {  // asked for a step ago
      corner = vertex_[s] < vertices ? fans_.first_corner_[vertex_[s]] : kNone;
    } else {  // this face's record was asked for a step ago: its ring vertices, then on
      const Face& face = fans_.faces_[corner / 3];
      const uint32_t k = corner % 3;
      for (int r = 0; r < n_rows_; ++r)
        if (3 * std::size_t{corner / 3} < rows_[r].ids->size())
          __builtin_prefetch(rows_[r].ids->data() + 3 * std::size_t{corner / 3});
      row_face_[s] = corner / 3;
      for (const uint32_t w : {face.vertex[(k + 1) % 3], face.vertex[(k + 2) % 3]}) {
        fetch_values(w);
        // A split links its new faces into the corner lists of vl and vr, ring vertices.
        if (w < vertices) __builtin_prefetch(&fans_.first_corner_[w], 1);
      }
      corner = face.next[k];
    }
    if (corner != kNone && corner / 3 >= faces) corner = kNone;
    corner_[s] = corner;
    if (corner != kNone) __builtin_prefetch(&fans_.faces_[corner / 3]);
  }
  // The oldest walk's vertex is the one split now: its slot starts u_ahead's walk.
  const std::size_t s = next_slot_;
  next_slot_ = (next_slot_ + 1) % kAhead;
  vertex_[s] = u_ahead;
  corner_[s] = kNone;
  if (u_ahead < vertices) {
    __builtin_prefetch(&fans_.first_corner_[u_ahead]);
    fetch_values(u_ahead);
    corner_[s] = kFirst;
  }
}

}  // namespace pm::detail
