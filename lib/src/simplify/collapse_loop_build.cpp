// The collapse loop's connectivity (collapse_loop.h): the directed edges of Campagna, Kobbelt and
// Seidel 1998 built from flat triangles, renumbered along a Morton curve (Morton 1966); and
// the legality rules only a repaired mesh needs (welds, carried faces).
#include "simplify/collapse_loop.h"

#include "core/memory_pages.h"

namespace pm::collapse_loop {

void CollapseLoop::morton_order(const float* points, std::size_t n, const float* low,
                                const float* high, double shift, const uint32_t* id,
                                std::vector<uint32_t>& keys, std::vector<uint32_t>& order,
                                std::vector<uint32_t>& rank) {
  for (std::size_t v = 0; v < n; ++v) {
    uint32_t code = 0;  // 30 bits
    for (int c = 0; c < 3; ++c) {
      const float extent = high[c] - low[c];
      double t = extent > 0 ? (points[3 * v + c] - low[c]) / double(extent) + shift : 0.0;
      if (shift > 0 && t >= 1.0) t -= 1.0;
      const uint32_t cell = std::min<uint32_t>(1023, static_cast<uint32_t>(t * 1024.0));
      for (int bit = 0; bit < 10; ++bit) code |= ((cell >> bit) & 1) << (3 * bit + c);
    }
    keys[id ? id[v] : v] = code;
  }
  // By code, ties to the smaller id: a least-significant-digit radix sort (Knuth, "The Art
  // of Computer Programming", vol. 3, §5.2.5), three stable passes of 10 bits over the ids
  // in increasing order, back and forth between `order` and `rank` (std::sort of the 64-bit
  // (code, id) pairs took twice as long: 1.7% of the loop on nefertiti after two Loop steps).
  constexpr int kDigitBits = 10, kDigits = 1 << kDigitBits;
  for (std::size_t i = 0; i < n; ++i) rank[i] = static_cast<uint32_t>(i);
  std::vector<uint32_t>* from = &rank;
  std::vector<uint32_t>* to = &order;
  for (int pass = 0; pass < 3; ++pass, std::swap(from, to)) {
    const int shift = kDigitBits * pass;
    std::size_t start[kDigits + 1] = {};
    for (std::size_t i = 0; i < n; ++i) ++start[((keys[i] >> shift) & (kDigits - 1)) + 1];
    for (int d = 0; d < kDigits; ++d) start[d + 1] += start[d];
    for (std::size_t i = 0; i < n; ++i) {
      const uint32_t x = (*from)[i];
      (*to)[start[(keys[x] >> shift) & (kDigits - 1)]++] = x;
    }
  }
  // Three passes: the sorted ids are in `order`.
  for (std::size_t i = 0; i < n; ++i) rank[order[i]] = static_cast<uint32_t>(i);
}

bool CollapseLoop::build(const uint32_t* tri, std::size_t n_faces, const float* points,
                         std::size_t n_vertices, const std::vector<uint8_t>* pinned,
                         bool faceless_allowed) {
  // Morton order of the vertices.
  float low[3] = {HUGE_VALF, HUGE_VALF, HUGE_VALF}, high[3] = {-HUGE_VALF, -HUGE_VALF, -HUGE_VALF};
  for (std::size_t i = 0; i < 3 * n_vertices; ++i) {
    low[i % 3] = std::min(low[i % 3], points[i]);
    high[i % 3] = std::max(high[i % 3], points[i]);
  }
  std::vector<uint32_t> keys(n_vertices);  // the Morton codes, by vertex (morton_order())
  detail::assign_preferring_huge_pages(vertex_of_, n_vertices, 0);
  detail::assign_preferring_huge_pages(local_vertex_, n_vertices, 0);
  morton_order(points, n_vertices, low, high, 0.0, nullptr, keys, vertex_of_, local_vertex_);
  // Regions of the Morton order (run_rounds()) need the weld and carried-edge checks,
  // which look anywhere on the mesh, to be idle.
  const std::size_t partition = options_.fast_partition_vertices;
  partitioned_ =
      welds_.empty() && carried_edges_.empty() && partition != 0 && n_vertices >= partition;
  // run_rounds()'s second order, on another thread while the connectivity is built here:
  // the Morton codes of the positions moved by 0.37 of the box's extent along each axis,
  // wrapping round (a region may then be in two pieces, which does not matter), so that
  // its cells' walls fall between the first order's; in local ids, ties to the smaller.
  std::thread second_order;
  const auto join = [&] {
    if (second_order.joinable()) second_order.join();
  };
  struct JoinOnExit {  // also when an allocation below throws
    std::thread& thread;
    ~JoinOnExit() {
      if (thread.joinable()) thread.join();
    }
  } join_on_exit{second_order};
  const auto give_up = [&] {
    join();
    return fail();
  };
  if (partitioned_) {
    detail::assign_preferring_huge_pages(order_b_, n_vertices, 0);
    detail::assign_preferring_huge_pages(rank_b_, n_vertices, 0);
    const auto order = [this, points, n_vertices, low, high, &keys] {
      morton_order(points, n_vertices, low, high, 0.37, local_vertex_.data(), keys, order_b_,
                   rank_b_);
    };
    // With one thread, or no thread to be had: here.
    if (threads_ < 2 || !try_start_thread(second_order, order)) order();
  }

  // Faces by their first local vertex (a counting sort); a face with a repeated vertex,
  // or a vertex without faces, needs the repair.
  // The lookups by vertex id are scattered: the ones a few faces ahead are fetched first,
  // so that their cache misses overlap.
  constexpr std::size_t kFetchAhead = 16;
  std::vector<uint32_t> begin(n_vertices + 1, 0);  // per local vertex: its faces' slots
  face_of_.resize(n_faces);  // first each face's first local vertex, then the sorted faces
  for (std::size_t f = 0; f < n_faces; ++f) {
    if (f + kFetchAhead < n_faces) {
      for (int k = 0; k < 3; ++k)
        __builtin_prefetch(local_vertex_.data() + tri[3 * (f + kFetchAhead) + k]);
    }
    const uint32_t* t = tri + 3 * f;
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return give_up();
    face_of_[f] = std::min({local_vertex_[t[0]], local_vertex_[t[1]], local_vertex_[t[2]]});
    ++begin[face_of_[f] + 1];
  }
  for (std::size_t v = 0; v < n_vertices; ++v) begin[v + 1] += begin[v];
  {
    std::vector<uint32_t> first_vertex(n_faces);
    first_vertex.swap(face_of_);
    for (std::size_t f = 0; f < n_faces; ++f)
      face_of_[begin[first_vertex[f]]++] = static_cast<uint32_t>(f);
  }
  detail::assign_preferring_huge_pages(half_, 3 * n_faces, HalfEdge{kNone, kNone});
  for (std::size_t i = 0; i < n_faces; ++i) {
    if (i + 2 * kFetchAhead < n_faces)
      __builtin_prefetch(tri + 3 * std::size_t{face_of_[i + 2 * kFetchAhead]});
    if (i + kFetchAhead < n_faces) {
      const uint32_t* ahead = tri + 3 * std::size_t{face_of_[i + kFetchAhead]};
      for (int k = 0; k < 3; ++k) __builtin_prefetch(local_vertex_.data() + ahead[k]);
    }
    for (int k = 0; k < 3; ++k)
      half_[3 * i + k].vertex = local_vertex_[tri[3 * std::size_t{face_of_[i]} + k]];
  }

  // The half-edges leaving each vertex (compressed rows), then each half-edge's twin:
  // the one way back, if any; two the same way, or two back, is an edge the repair cuts.
  std::fill(begin.begin(), begin.end(), 0);
  for (uint32_t h = 0; h < half_.size(); ++h) ++begin[half_[h].vertex + 1];
  for (std::size_t v = 0; v < n_vertices; ++v) {
    if (begin[v + 1] == 0 && !faceless_allowed) return give_up();  // a vertex no face uses
    begin[v + 1] += begin[v];
  }
  // Each row holds the half-edges and, beside them, the vertices they lead to: the search
  // below reads rows, where reading each half-edge's far end was a cache miss (the search
  // took half of build(), on nefertiti after two Loop steps).
  std::vector<uint32_t> leaving(half_.size()), leaving_to(half_.size());
  {
    std::vector<uint32_t> fill(begin.begin(), begin.end() - 1);
    for (uint32_t h = 0; h < half_.size(); ++h) {
      const uint32_t slot = fill[half_[h].vertex]++;
      leaving[slot] = h;
      leaving_to[slot] = half_[next_of(h)].vertex;
    }
  }
  // Two half-edges the same way are two the same way in a's row; two back from b, two the
  // same way in b's: a row holding a target twice is a cut. Otherwise each edge a-b, a < b,
  // is paired once, from a's row, with the one entry of b's row back to a, if any. Vertices
  // in slices at once (in_turn.h): an edge's two half-edges are written by the slice of its
  // smaller vertex alone.
  std::atomic<bool> cut{false};
  run_in_slices(n_vertices, threads_, [&](std::size_t lo, std::size_t hi) {
    for (auto a = static_cast<uint32_t>(lo); a < hi; ++a) {
      for (uint32_t i = begin[a]; i < begin[a + 1]; ++i) {
        const uint32_t b = leaving_to[i];
        for (uint32_t j = i + 1; j < begin[a + 1]; ++j)
          if (leaving_to[j] == b) return cut.store(true);
        if (b < a) continue;
        for (uint32_t j = begin[b]; j < begin[b + 1]; ++j) {
          if (leaving_to[j] != a) continue;
          half_[leaving[i]].twin = leaving[j];
          half_[leaving[j]].twin = leaving[i];
          break;  // b's row holds a once, or the slice holding b finds the cut
        }
      }
    }
  });
  if (cut) return give_up();
  std::vector<uint32_t>().swap(leaving_to);
  // An outgoing half-edge per vertex, from its row (the half-edges leaving it, in
  // increasing order: the first, or on a boundary the one with no twin, where a walk
  // around the vertex, ring(), starts); read row by row, where a pass over the half-edges
  // wrote each vertex's record at random. Two without a twin, or a walk that misses some
  // of the vertex's faces, is a vertex where fans meet.
  detail::assign_preferring_huge_pages(vertex_, n_vertices, {});
  for (std::size_t v = 0; v < n_vertices; ++v) {
    if (begin[v] == begin[v + 1]) continue;  // no faces (faceless_allowed)
    uint32_t outgoing = leaving[begin[v]];
    bool boundary = false;
    for (uint32_t i = begin[v]; i < begin[v + 1]; ++i) {
      if (half_[leaving[i]].twin != kNone) continue;
      if (boundary) return give_up();
      boundary = true;
      outgoing = leaving[i];
    }
    vertex_[v].outgoing = outgoing;
  }
  std::vector<uint32_t>().swap(leaving);
  run_in_slices(n_vertices, threads_, [&](std::size_t lo, std::size_t hi) {
    for (auto v = static_cast<uint32_t>(lo); v < hi; ++v) {
      if (vertex_[v].outgoing == kNone) continue;  // no faces (faceless_allowed)
      uint32_t faces = 0, h = vertex_[v].outgoing;
      do {
        ++faces;
        h = half_[prev_of(h)].twin;
      } while (h != kNone && h != vertex_[v].outgoing && faces <= begin[v + 1] - begin[v]);
      if (faces != begin[v + 1] - begin[v]) return cut.store(true);
    }
  });
  if (cut) return give_up();

  detail::assign_preferring_huge_pages(xyz_, 3 * n_vertices, 0);
  for (std::size_t i = 0; i < n_vertices; ++i) {
    if (i + kFetchAhead < n_vertices)
      __builtin_prefetch(points + 3 * std::size_t{vertex_of_[i + kFetchAhead]});
    for (int c = 0; c < 3; ++c) xyz_[3 * i + c] = points[3 * std::size_t{vertex_of_[i]} + c];
    if (pinned) vertex_[i].pinned = (*pinned)[vertex_of_[i]];
  }
  detail::assign_preferring_huge_pages(face_dead_, n_faces, 0);
  join();
  // Only the weld check looks a vertex up by its given id from here on.
  if (welds_.empty()) std::vector<uint32_t>().swap(local_vertex_);
  return true;
}

// The collapse v -> u is refused if a new edge u-w would join two copies of one vertex,
// or would merge at output with an existing edge between copies of u's and w's vertices
// (WeldGroups, collapse_legality.h). Weld groups hold the given (repaired) ids.
bool CollapseLoop::keeps_weld_groups(uint32_t u, const Neighbour* ring_v, int n_v) const {
  auto members_of = [&](uint32_t x, uint32_t& single) -> std::pair<const uint32_t*, std::size_t> {
    const int g = welds_.group[x];
    if (g < 0) {
      single = x;
      return {&single, 1};
    }
    return {welds_.members[g].data(), welds_.members[g].size()};
  };
  const uint32_t u_id = vertex_of_[u];
  const int group_u = welds_.group[u_id];
  for (int i = 0; i < n_v; ++i) {
    const uint32_t w = ring_v[i].vertex;
    if (w == u) continue;
    const uint32_t w_id = vertex_of_[w];
    const int group_w = welds_.group[w_id];
    if (group_u < 0 && group_w < 0) continue;
    if (group_u >= 0 && group_u == group_w) return false;
    uint32_t single_u, single_w;
    const auto [us, nu] = members_of(u_id, single_u);
    const auto [ws, nw] = members_of(w_id, single_w);
    for (std::size_t a = 0; a < nu; ++a)
      for (std::size_t b = 0; b < nw; ++b) {
        if (us[a] == u_id && ws[b] == w_id) continue;
        if (adjacent(local_vertex_[us[a]], local_vertex_[ws[b]])) return false;
      }
  }
  return true;
}

// A carried face's vertex pair may not
// become an edge of the surface.
bool CollapseLoop::keeps_carried_pairs(uint32_t u, const Neighbour* ring_v, int n_v) const {
  for (int i = 0; i < n_v; ++i) {
    const uint32_t w = ring_v[i].vertex;
    if (w == u) continue;
    const uint32_t a = vertex_of_[u], b = vertex_of_[w];
    if (carried_edges_.count({std::min(a, b), std::max(a, b)}) && !adjacent(u, w)) return false;
  }
  return true;
}

}  // namespace pm::collapse_loop
