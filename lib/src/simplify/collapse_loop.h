// The collapse loop's state (simplifier.h says what it is for; simplifier.cpp runs it,
// collapse_loop_build.cpp builds its connectivity, collapse_apply.cpp takes its step). Garland
// and Heckbert 1997's quadrics on Campagna, Kobbelt and Seidel 1998's directed edges:
// half-edge h = 3f + k of triangle f leaves the triangle's k-th corner, next and previous
// are implicit, and one array holds each half-edge's twin. Internal to simplify/.
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <deque>
#include <functional>
#include <limits>
#include <set>
#include <thread>

#include "core/in_turn.h"
#include "simplify/collapse_legality.h"
#include "simplify/corner_attributes.h"
#include "simplify/geometry.h"
#include "simplify/indexed_heap.h"
#include "simplify/kept_points.h"
#include "simplify/local_quadric.h"
#include "simplify/seam_drift.h"
#include "simplify/simplifier.h"
#include "simplify/tracked_points.h"
#include "simplify/tracking_thread.h"
#include "simplify/vertex_classification.h"

namespace pm::collapse_loop {

constexpr uint32_t kNone = 0xffffffffu;
constexpr int kMaxValence = 64;  // as the former default loop: a vertex of larger valence stays
static_assert(kMaxValence <= CornerAttributes::StarFields::kMostFaces,
              "a star's faces all have their attribute function");
static_assert(kMaxValence <= KeptPoints::kMaxMoved, "KeptPoints' scratch holds a whole fan");

inline uint32_t next_of(uint32_t h) {
  return h % 3 == 2 ? h - 2 : h + 1;
}
inline uint32_t prev_of(uint32_t h) {
  return h % 3 == 0 ? h + 2 : h - 1;
}

// A neighbour w of v and a half-edge of a face on the edge v-w: v -> w, or w -> v for the
// last neighbour of a boundary vertex (that edge's only face holds it that way round).
struct Neighbour {
  uint32_t vertex;
  uint32_t edge;
};

class CollapseLoop {
  // A heap and the collapses it made since the last merge(): one per region in a round
  // (run_rounds()), one for the whole mesh otherwise.
  struct Worker {
    // Its region: the vertices whose rank is in [lo, hi). The rank is the local id itself,
    // or, when `rank` is set, rank[v] (and `at` its inverse): run_rounds()'s second order.
    uint32_t lo = 0, hi = 0;
    const uint32_t* rank = nullptr;
    const uint32_t* at = nullptr;
    IndexedHeap heap{0};              // of ranks - lo
    uint32_t queued_count = 0;        // queue()'s ties; wraps after 2^32: still deterministic
    // Until merge(), which takes them from the front: deques, whose blocks go as they are
    // taken, where a vector held all of a round's (and, as it doubled, an old copy beside).
    std::deque<Collapse> collapses;  // bound: the collapse's own cost, until merge()
    std::deque<float> recorded;      // per collapse: its own bound (apply()), until merge()
    // Its collapses' moved faces and, with attributes, what they did to them: places in
    // these lists (Collapse::moved_begin, new_faces_begin) until merge() hands the blocks on.
    RecordList moved_faces{kMovedEntriesPerBlock};
    CollapseAttributes record;
    TrackedPoints::Scratch tracked_scratch;  // TrackedPoints::collapse()'s
    // A record that merge() gives every later collapse of this worker at least: the running
    // maximum when it was made, then its own records' (apply()'s tracked points settle within
    // it).
    float record_floor = 0;
    TrackingThread* tracking = nullptr;  // tracks its collapses' points when set (run())
    uint32_t rank_of(uint32_t v) const { return rank ? rank[v] : v; }
    uint32_t vertex_at(uint32_t r) const { return at ? at[r] : r; }
    bool holds(uint32_t v) const { return rank_of(v) - lo < hi - lo; }
    uint32_t cheapest() const { return vertex_at(heap.top() + lo); }
    uint32_t next_cheapest() const { return vertex_at(heap.runner_up() + lo); }
    bool queued(uint32_t v) const { return holds(v) && heap.contains(rank_of(v) - lo); }
    float key(uint32_t v) const { return heap.key(rank_of(v) - lo); }
    // Equal keys go oldest first: each queue() gives v a later tie than every vertex queued
    // before. Flat regions, where the quadric costs are all zero, are made of ties; in id
    // order the collapses sweep across them, each vertex's next one onto the vertex just
    // made, and the vertex hierarchy deepens (fandisk: depth 34 against 24, a split forces
    // 194 others on average against 130), which costs view-dependent refinement its
    // locality. Oldest first, a vertex re-evaluated after a collapse next to it waits for
    // the other ties, as in the former default loop (its push counter).
    void queue(uint32_t v, float key) { heap.set(rank_of(v) - lo, key, ++queued_count); }
    void drop(uint32_t v) {
      if (holds(v)) heap.erase(rank_of(v) - lo);
    }
    std::size_t removed_faces = 0, removed_vertices = 0;
    std::size_t face_budget = 0, vertex_budget = 0;  // set_budgets()
    bool full = false;                               // a collapse would have gone past a budget
  };

 public:
  // `repaired`: its welds and carried faces, or null for an input without either.
  CollapseLoop(const ManifoldMesh* repaired, const EncodeOptions& options,
               const LoopSwitches& switches, Simplification& out)
      : options_(options),
        out_(out),
        welds_(repaired ? weld_groups(*repaired) : WeldGroups{}),
        carried_edges_(repaired ? carried_edges(*repaired)
                                : std::set<std::pair<uint32_t, uint32_t>>{}),
        cos_feature_angle_(std::cos(effective_feature_angle(options) * M_PI / 180.0)),
        cos_max_flip_(std::cos(options.max_normal_flip_deg * M_PI / 180.0)),
        features_(cos_feature_angle_ > -1.0),
        angle_features_(features_),
        schroeder_(options.metric == Metric::kSchroeder),
        measure_(!options.fast),
        plane_term_(!measure_ && !schroeder_ && switches.plane_term),
        reuse_fan_part_(switches.reuse_fan_part),
        keep_apex_candidates_(switches.keep_apex_candidates),
        compact_faces_(switches.compact_faces),
        price_at_top_(switches.price_at_top),
        threads_(thread_count(options.threads)) {}

  void run();

  // Keeps the input's texture coordinates, normals and materials through the loop (unless
  // options.drop_attributes): call after build(). input_face[f] is the input triangle of
  // given face f, input_vertex[x] the input vertex of given vertex x (null: the identity).
  // `input_read` (when set) is called once, as soon as the loop holds all it reads of the
  // input but its uvs and normals tables (simplifier.h, loop_built): with attributes, once
  // the faces' corner records are made, before the wedges are numbered (the 950K-face
  // textured mesh: 34 MiB of its triangles and corner indices go then).
  void attach_attributes(const Mesh& input, const uint32_t* input_face,
                         const uint32_t* input_vertex, const std::function<void()>& input_read);

  // Rounds of collapses in regions of the mesh at once, two threads taking the regions in
  // turn (fast_partition_vertices in encoder.h). A collapse v -> u rewrites only faces
  // around v and u, and reads only their rings: while both and all their neighbours lie in
  // one region, regions share nothing that changes, so each runs its own greedy loop, and
  // their sequences interleave in any order into a valid one (the vertex splits of Hoppe
  // 1996, §3, on disjoint neighbourhoods commute: Pajarola and Rossignac 2000, "Compressed
  // progressive meshes", refine in batches of such independent splits). Merged by cost, the
  // sequence stays close to the one-heap greedy order. The regions are runs of a Morton
  // order (kRegions, or without the measure on a large mesh one per kRegionVertices): the
  // local ids' in even rounds, in odd ones that of the positions shifted by an odd
  // fraction of the box (order_b_), whose cuts lie elsewhere, so that a vertex
  // next to a region's edge (band_), which waits, is inside one the next round (in the
  // first order alone, vertices along its big cells' walls, whose neighbours are far in
  // it, waited every round: 70% of those left by the end on a 200K-vertex mesh, and the
  // coarse levels lost a factor 5 in RMS distance). Each round ends at the median queued
  // cost; the last thirty-second of the vertices collapse in one heap. The result depends
  // on the mesh alone, never on the cores or their timing.
  void run_rounds();

  void report_progress(std::size_t collapses) const {
    options_.progress(std::min(1.0, double(collapses) / double(vertex_.size())));
  }

  // The collapses w may make before the mesh would go below the caller's limits
  // (EncodeOptions::min_faces, min_vertices), shared among `workers`.
  void set_budgets(Worker& w, std::size_t workers) const {
    const std::size_t min_vertices = std::max<std::size_t>(options_.min_vertices, 1);
    w.face_budget =
        faces_alive_ > options_.min_faces ? (faces_alive_ - options_.min_faces) / workers : 0;
    w.vertex_budget =
        vertices_alive_ > min_vertices ? (vertices_alive_ - min_vertices) / workers : 0;
    w.full = false;
  }

  // f on each worker, by this thread and others (in_turn.h).
  template <typename F>
  void in_turn(std::vector<Worker>& workers, F&& f) {
    run_in_turn(workers.size(), threads_, [&](std::size_t i, bool) { f(workers[i]); });
  }

  // Whether worker w may collapse v, or collapse onto it: always with one heap; in a round,
  // when v and its neighbours are in w's region.
  bool owns(const Worker& w, uint32_t v) const { return !in_rounds_ || (w.holds(v) && !band_[v]); }

  // Appends the workers' collapses to the sequence: by cost (each record's own key, kept in
  // its bound until here), ties to the earlier worker, each worker's in its order.
  void merge(std::vector<Worker>& workers);

  // The vertices (three coordinates each in `points`) along a Morton (Z-order) curve of
  // their positions in the box [low, high] on a 1024^3 grid (Morton 1966): order[rank] is a
  // vertex, rank[vertex] its place. `shift` (a fraction of the box) moves the positions
  // first, wrapping round, so that the curve's cells fall elsewhere; ties go to the smaller
  // vertex. With `id`, vertex v of `points` is called id[v] (in the order, the ranks and the
  // ties). `keys`, `order` and `rank` hold n each: nothing is allocated here, so that this
  // may run on a thread of its own.
  static void morton_order(const float* points, std::size_t n, const float* low, const float* high,
                           double shift, const uint32_t* id, std::vector<uint32_t>& keys,
                           std::vector<uint32_t>& order, std::vector<uint32_t>& rank);

  // The flat connectivity of triangles `tri` (n_faces, ids below n_vertices) on `points`
  // (three per vertex), pinned vertices never removed (null: none). False, with nothing
  // built, unless they make a manifold without repair: no face with a repeated vertex, no
  // vertex without faces unless `faceless_allowed`, every edge in one face or in two of
  // opposite orientation, and every vertex's faces one fan (build_manifold_mesh makes any
  // mesh so; its vertices used by carried faces alone have no faces, and stay as they are).
  //
  // The copy is renumbered for locality: vertices along a Morton (Z-order) curve of their
  // positions (Morton 1966), faces by their first vertex in that order. A collapse touches
  // one small neighbourhood, but consecutive collapses are anywhere on the mesh; with
  // neighbours close in memory, each collapse misses the cache a few times instead of at
  // every step around its vertices (in the input's order the loop took 1.3 times as long
  // on a Loop-subdivided mesh, whose new vertices are numbered far from their neighbours).
  // Records and the base mesh are written in the given ids.
 public:
  bool build(const uint32_t* tri, std::size_t n_faces, const float* points, std::size_t n_vertices,
             const std::vector<uint8_t>* pinned, bool faceless_allowed);

 private:
  bool fail() {
    for (auto* table : {&vertex_of_, &local_vertex_, &face_of_})
      std::vector<uint32_t>().swap(*table);
    std::vector<HalfEdge>().swap(half_);
    std::vector<VertexRecord>().swap(vertex_);
    return false;
  }

  Vec3 point(uint32_t v) const {
    const float* p = &xyz_[3 * std::size_t{v}];
    return Vec3(p[0], p[1], p[2]);
  }

  // Unit normal of face f, or zero when degenerate (as FaceGeometry's).
  Vec3 face_normal(uint32_t f) const {
    const Vec3 n = area_vector(point(half_[3 * f].vertex), point(half_[3 * f + 1].vertex),
                               point(half_[3 * f + 2].vertex));
    const double length = n.norm();
    return length > 0 ? n / length : Vec3(0, 0, 0);
  }

  // Schroeder, Zarge and Lorensen 1992, §3.1: an edge is a feature when its faces' normals
  // differ by more than the feature angle (a degenerate face's edges are features).
  // Attribute seams and material borders are features too (Garland and Heckbert 1998, §4:
  // discontinuities are kept like boundaries).
  bool is_feature(uint32_t h) const {
    if (!features_ || half_[h].twin == kNone) return false;
    if (attributes_ && seam_[h]) return true;
    return angle_features_ &&
           (face_normal(h / 3) | face_normal(half_[h].twin / 3)) < cos_feature_angle_;
  }
  // Whether the interior half-edge h lies on a seam or a material border now (seam_).
  bool seam_now(uint32_t h) const {
    return attributes_->is_seam(h / 3, half_[h].twin / 3, half_[h].vertex,
                                half_[next_of(h)].vertex);
  }
  // seam_ of the edges at u, the only ones a collapse onto u changes: its moved corners
  // are at u, and the edges whose twins it joins (the removed faces' outer edges) end there.
  // Every edge at u, whatever its valence (ring() stops at kMaxValence).
  void update_seams_at(uint32_t u) {
    for_each_leaving(u, [&](uint32_t h) {
      const uint32_t t = half_[h].twin;
      if (t != kNone) seam_[h] = seam_[t] = seam_now(h);
      return true;
    });
  }
  // Whether no edge at u lies on a seam or a material border (seam_ is current).
  bool seamless_at(uint32_t u) const {
    return for_each_leaving(u, [&](uint32_t h) { return !seam_[h]; });
  }
  // Calls f(h) for each half-edge h leaving u, around it from its outgoing one (u's other
  // boundary edge, which no face shares, leaves no half-edge), while f returns true; whether
  // it always did.
  template <class F>
  bool for_each_leaving(uint32_t u, F&& f) const {
    const uint32_t first = vertex_[u].outgoing;
    if (first == kNone) return true;
    uint32_t h = first;
    do {
      if (!f(h)) return false;
      const uint32_t back = half_[prev_of(h)].twin;
      if (back == kNone) break;
      h = back;
    } while (h != first);
    return true;
  }

  // The collapse v -> u as CornerAttributes and SeamDrift read it (corner_attributes.h):
  // v's faces in ring order (the order apply() lists the moved faces), its edges, then
  // aim() at one target. On the stack: regions on other threads have their own.
  struct Star {
    uint32_t faces[kMaxValence];
    CollapseStar::Edge edges[kMaxValence];
    CollapseStar c{};
  };
  void make_star(uint32_t v, const Neighbour* ring_v, int n_v, Star& star) const {
    int n_faces = 0;
    bool seamless = true;  // seam_ is current at every edge (update_seams_at())
    for (int i = 0; i < n_v; ++i) {
      const uint32_t e = ring_v[i].edge, t = half_[e].twin;
      if (half_[e].vertex == v) {
        star.faces[n_faces++] = e / 3;
        attributes_->prefetch(e / 3);
      }
      star.edges[i] = {ring_v[i].vertex, e / 3, t == kNone ? CollapseStar::kNoFace : t / 3};
      seamless &= t == kNone || !seam_[e];
    }
    star.c.seamless = seamless;
    star.c.v = v;
    star.c.faces = star.faces;
    star.c.n_faces = n_faces;
    star.c.edges = star.edges;
    star.c.n_edges = n_v;
  }
  void aim(Star& star, uint32_t u, uint32_t edge) const {
    const Sides s = sides(star.c.v, edge);
    star.c.u = u;
    star.c.fl = s.h == kNone ? CollapseStar::kNoFace : s.h / 3;
    star.c.fr = s.t == kNone ? CollapseStar::kNoFace : s.t / 3;
    star.c.vl = s.h == kNone ? 0 : half_[prev_of(s.h)].vertex;
    star.c.vr = s.t == kNone ? 0 : half_[prev_of(s.t)].vertex;
    star.c.pu = point(u);
    star.c.pv = point(star.c.v);
  }
  bool is_special(uint32_t h) const { return half_[h].twin == kNone || is_feature(h); }

  // v's neighbours in order, at most `cap`: the count, or -1 when there are more.
  // *boundary tells whether v is on a boundary.
  int ring(uint32_t v, Neighbour* out, int cap, bool* boundary) const {
    *boundary = false;
    const uint32_t first = vertex_[v].outgoing;
    if (first == kNone) return 0;
    int n = 0;
    uint32_t h = first;
    do {
      if (n == cap) return -1;
      out[n++] = {half_[next_of(h)].vertex, h};
      const uint32_t incoming = prev_of(h);
      const uint32_t t = half_[incoming].twin;
      if (t == kNone) {  // the boundary edge that ends at v: its far end is the last one
        if (n == cap) return -1;
        out[n++] = {half_[incoming].vertex, incoming};
        *boundary = true;
        break;
      }
      h = t;
    } while (h != first);
    return n;
  }

  bool is_boundary_vertex(uint32_t v) const {
    return vertex_[v].outgoing != kNone && half_[vertex_[v].outgoing].twin == kNone;
  }

  bool adjacent(uint32_t a, uint32_t b) const {
    const uint32_t first = vertex_[a].outgoing;
    if (first == kNone) return false;
    uint32_t h = first;
    do {
      if (half_[next_of(h)].vertex == b) return true;
      const uint32_t incoming = prev_of(h);
      if (half_[incoming].twin == kNone) return half_[incoming].vertex == b;
      h = half_[incoming].twin;
    } while (h != first);
    return false;
  }

  // Schroeder, Zarge and Lorensen 1992, §3.1, with Schroeder 1997's corner rule
  // (vertex_classification.h's kinds): a pinned vertex, or one the ring walk refuses, is
  // complex.
  VertexKind kind_of(uint32_t v) const {
    if (vertex_[v].pinned) return VertexKind::kComplex;
    Neighbour ring_of_v[kMaxValence];
    bool boundary;
    const int n = ring(v, ring_of_v, kMaxValence, &boundary);
    if (n <= 0) return VertexKind::kComplex;
    int boundary_edges = 0, feature_edges = 0;
    for (int i = 0; i < n; ++i) {
      if (half_[ring_of_v[i].edge].twin == kNone)
        ++boundary_edges;
      else
        feature_edges += is_feature(ring_of_v[i].edge);
    }
    return kind_from_edges(boundary_edges, feature_edges);
  }

  // The two sides of the collapse v -> u through `edge` (a half-edge of a face on v-u):
  // h = v -> u in fl, t = u -> v in fr, kNone where there is no such face.
  struct Sides {
    uint32_t h, t;
  };
  Sides sides(uint32_t v, uint32_t edge) const {
    return half_[edge].vertex == v ? Sides{edge, half_[edge].twin} : Sides{half_[edge].twin, edge};
  }

  // Topology: the collapse v -> u keeps the mesh a manifold of the same genus and number of
  // boundary loops. That is the link condition (Dey, Edelsbrunner, Guha and Nekhayev 1999,
  // "Topology preserving edge contraction", §2: the common neighbours of v and u are exactly
  // vl and vr) plus the boundary rules of Hoppe et al. 1993 ("Mesh optimization", §3.2: an
  // interior edge between two boundary vertices may not collapse), as OpenMesh's
  // is_collapse_ok checks them; and no closed tetrahedron is flattened.
  bool keeps_topology(uint32_t u, const Sides& s, const Neighbour* ring_v, int n_v,
                      bool boundary_v) const {
    auto apex_ok = [&](uint32_t h) {
      return h == kNone || half_[next_of(h)].twin != kNone || half_[prev_of(h)].twin != kNone;
    };
    if (!apex_ok(s.h) || !apex_ok(s.t)) return false;
    const uint32_t vl = s.h == kNone ? kNone : half_[prev_of(s.h)].vertex;
    const uint32_t vr = s.t == kNone ? kNone : half_[prev_of(s.t)].vertex;
    if (vl == vr) return false;
    // u's neighbours, each looked up among v's: no common neighbour but vl and vr.
    int valence_u = 0;
    bool boundary_u = false;
    const uint32_t first = vertex_[u].outgoing;
    uint32_t h = first;
    auto common = [&](uint32_t w) {
      ++valence_u;
      if (w == vl || w == vr) return false;
      for (int i = 0; i < n_v; ++i)
        if (ring_v[i].vertex == w) return true;
      return false;
    };
    do {
      if (common(half_[next_of(h)].vertex)) return false;
      const uint32_t incoming = prev_of(h);
      if (half_[incoming].twin == kNone) {
        if (common(half_[incoming].vertex)) return false;
        boundary_u = true;
        break;
      }
      h = half_[incoming].twin;
    } while (h != first);
    const bool interior_edge = s.h != kNone && s.t != kNone;
    if (boundary_v && boundary_u && interior_edge) return false;
    // A closed tetrahedron passes the link condition; flattening it would leave two
    // triangles on the same three vertices.
    return !(n_v == 3 && valence_u == 3 && !boundary_v && !boundary_u);
  }

  // By face_keeps_geometry (collapse_legality.h): no surviving face of v's fan turns
  // by more than the flip limit or becomes degenerate.
  bool keeps_geometry(uint32_t v, uint32_t u, const Sides& s, const Neighbour* ring_v,
                      int n_v) const {
    const uint32_t fl = s.h == kNone ? kNone : s.h / 3, fr = s.t == kNone ? kNone : s.t / 3;
    const Vec3 pu = point(u);
    for (int i = 0; i < n_v; ++i) {
      const uint32_t e = ring_v[i].edge;
      if (half_[e].vertex != v) continue;  // the boundary's last entry: its face came already
      const uint32_t f = e / 3;
      if (f == fl || f == fr) continue;
      Vec3 before[3], after[3];
      for (int k = 0; k < 3; ++k) {
        const uint32_t w = half_[3 * f + k].vertex;
        before[k] = point(w);
        after[k] = w == v ? pu : before[k];
      }
      if (!face_keeps_geometry(before, after, cos_max_flip_)) return false;
    }
    return true;
  }

  // Welds (collapse_legality.h: keeps_weld_groups), and a carried face's vertex pair may not
  // become an edge of the surface (collapse_loop_build.cpp: only a repaired mesh has either).
  bool keeps_welds(uint32_t u, const Neighbour* ring_v, int n_v) const {
    return welds_.empty() || keeps_weld_groups(u, ring_v, n_v);
  }
  bool keeps_carried_edges_apart(uint32_t u, const Neighbour* ring_v, int n_v) const {
    return carried_edges_.empty() || keeps_carried_pairs(u, ring_v, n_v);
  }
  bool keeps_weld_groups(uint32_t u, const Neighbour* ring_v, int n_v) const;
  bool keeps_carried_pairs(uint32_t u, const Neighbour* ring_v, int n_v) const;

  // `star`: v's (make_star()), with attributes; aimed at u here.
  bool legal(uint32_t v, uint32_t u, uint32_t edge, const Neighbour* ring_v, int n_v,
             bool boundary_v, Star* star) const {
    const Sides s = sides(v, edge);
    return keeps_topology(u, s, ring_v, n_v, boundary_v) && keeps_welds(u, ring_v, n_v) &&
           keeps_geometry(v, u, s, ring_v, n_v) && keeps_carried_edges_apart(u, ring_v, n_v) &&
           keeps_attributes(u, edge, star);
  }

  // As the former default loop: seams and material borders slide, never open or close, and no
  // texture triangle turns over (CornerAttributes::collapse_keeps_attributes).
  bool keeps_attributes(uint32_t u, uint32_t edge, Star* star) const {
    if (!attributes_) return true;
    aim(*star, u, edge);
    return attributes_->collapse_keeps_attributes(star->c);
  }

  // The cost of v's collapse onto its neighbour u (through `edge`, a half-edge on v-u) as
  // find_best() ranks it: v's planes at u as a mean over their area (u stays where it is;
  // Garland and Heckbert 1997, §4), plus, with attributes, their error in the same units
  // (Hoppe 1999, §4), as the former default loop: `star` is v's, `fields` its star_fields().
  double cost_of(uint32_t v, uint32_t u, uint32_t edge, Star& star,
                 const CornerAttributes::StarFields& fields) const {
    const double cost = geometric_cost(v, u);
    return attributes_ ? cost + attribute_cost(u, edge, star, fields) : cost;
  }
  // cost_of()'s two terms. The attribute term is never negative, so the geometric one
  // alone is a lower bound of the sum (rounding is monotone): an option whose geometric
  // cost already loses needs no attribute cost.
  double geometric_cost(uint32_t v, uint32_t u) const {
    const LocalQuadric& q = vertex_[v].quadric;
    return q.weight > 0 ? q.error_at(point(u) - point(v)) / q.weight : 0.0;
  }
  // Without the measure, on the geometry alone (plane_term_), find_best()
  // adds to an option's cost kPlaneWeight times the largest squared distance from u to the
  // planes of v's faces (FanPlanes): the quadric is a mean over every plane v stands for, and
  // a collapse that tilts one face far off its plane while the others stay hides in it; the
  // largest is Ronfard and Rossignac 1996's error (the largest distance of the new position
  // to the planes of the faces around it), here over v's faces of the moment, no set
  // carried along. Never negative: geometric_cost() stays a lower bound of an option's cost
  // (keeps_best()). The levels' Hausdorff distance 0.75 times the quadric's alone and RMS
  // 0.97 times (the 8 shared meshes at 50/10/2%, geometric means; nefertiti after two Loop
  // steps at 50/10/2%: Hausdorff 0.81, 0.70 and 0.57 times); about 2% more time on that mesh
  // (one thread, medians of 7 alternating runs), 18% more instructions on nefertiti. With
  // attributes it moved the levels away from the input (the 950K-face textured mesh at 2%:
  // Hausdorff 0.50 -> 0.62 times meshopt's, spot at 50% 1.04 -> 1.16), so there it is off.
  struct FanPlanes {
    // Per face of v: its area vector (not unit) and 1 / its squared length (0 without area).
    double x[kMaxValence], y[kMaxValence], z[kMaxValence], inverse_norm2[kMaxValence];
    int count = 0;
    // The largest squared distance of v + d to the planes (through v).
    double worst(const Vec3& d) const {
      double most = 0;
      for (int i = 0; i < count; ++i) {
        const double s = x[i] * d[0] + y[i] * d[1] + z[i] * d[2];
        most = std::max(most, s * s * inverse_norm2[i]);
      }
      return most;
    }
  };
  // The planes of v's faces, from `to_ring` (each ring neighbour's position less v's, in
  // ring()'s order: face i has v and neighbours i and i + 1, the last face wrapping around
  // unless v is on a boundary).
  static void fan_planes(const Vec3* to_ring, int n, bool boundary, FanPlanes& planes) {
    const int faces = boundary ? n - 1 : n;
    for (int i = 0; i < faces; ++i) {
      const Vec3& a = to_ring[i];
      const Vec3& b = to_ring[i + 1 < n ? i + 1 : 0];
      const double x = a[1] * b[2] - a[2] * b[1], y = a[2] * b[0] - a[0] * b[2],
                   z = a[0] * b[1] - a[1] * b[0];
      const double norm2 = x * x + y * y + z * z;
      planes.x[i] = x, planes.y[i] = y, planes.z[i] = z;
      planes.inverse_norm2[i] = norm2 > 0 ? 1.0 / norm2 : 0.0;
    }
    planes.count = faces > 0 ? faces : 0;
  }
  double attribute_cost(uint32_t u, uint32_t edge, Star& star,
                        const CornerAttributes::StarFields& fields) const {
    aim(star, u, edge);
    return attributes_->collapse_cost(star.c, fields);
  }
  // The key of a candidate of this cost before its measure: the cost alone, a lower bound,
  // so the order stays greedy (a guess of the measure cost Hausdorff: kept_points.h's grids).
  float queued_key(double cost) const { return static_cast<float>(cost); }
  // A candidate's key from its cost and a measured distance: the quadric's plus the
  // distance's square, weighted; Schroeder's the larger of the two, the distance weighted,
  // as the former default loop's combined() (unweighted there).
  float combined(double cost, double worst) const {
    return static_cast<float>(schroeder_ ? std::max(cost, kSchroederWorstWeight * worst)
                                         : cost + kWorstCaseWeight * worst * worst);
  }
  // The distance a key stands for: its square root for the quadric metric.
  double key_distance(float key) const { return schroeder_ ? double(key) : std::sqrt(key); }
  // Whether v's queued candidate is still its best after a collapse onto its neighbour u
  // (apply()'s shortcut, whose conditions hold): when v -> u costs more. Then, with
  // attributes, v is queued again as evaluate() would queue it, its key back to the cost
  // of its candidate; unless v is queued at its geometric cost, unpriced (pricing_at_top()),
  // which is kept as geometry only (its other options' geometric costs did not change).
  bool keeps_best(Worker& worker, uint32_t v, uint32_t u) {
    const double geometric = geometric_cost(v, u);
    if (!attributes_ || vertex_[v].unpriced) return static_cast<float>(geometric) > best_[v].key;
    return keeps_best_with_attributes(worker, v, u, geometric);
  }
  bool keeps_best_with_attributes(Worker& worker, uint32_t v, uint32_t u, double geometric);

  // One of v's collapses as find_best() ranks them (ranks_before()): by `rank` (the quadric
  // metric: its cost), queued with its `cost`.
  struct Option {
    bool special;
    double cost, rank, length;
    int index;        // in v's ring
    uint32_t vertex;  // the neighbour: the last tie-break
  };
  static bool ranks_before(const Option& a, const Option& b);
  // Schroeder's metric (schroeder_costs.cpp): each of the `count` options' cost and rank
  // for v of this kind (ring_v its n neighbours; star and fields v's, with attributes).
  void schroeder_costs(uint32_t v, VertexKind kind, const Neighbour* ring_v, int n, Option* options,
                       int count, Star& star, const CornerAttributes::StarFields& fields) const;
  // Marks the input corners with an edge sharper than kSharpCornerDeg (schroeder_costs.cpp).
  void mark_sharp_corners();

  // Queues v's cheapest collapse in best_[v] and heap_, or takes v out of the heap when it
  // has none. Legality, the dearer test, waits until v comes to the top (apply()) unless
  // `check_legal`: a cheapest option that is legal then is the cheapest legal one, so the
  // order stays exactly greedy; one that is not sends v back through here with check_legal,
  // which asks legality in order of cost until an option passes.
  void evaluate(Worker& worker, uint32_t v, bool check_legal = false) {
    if (find_best(worker, v, check_legal)) return;
    worker.drop(v);
    if (worker.holds(v)) best_[v].target = kNone;
  }
  // evaluate()'s choice (collapse_options.cpp). In a round, v waits (false) when the cut is
  // next to it or to its cheapest target.
  bool find_best(Worker& worker, uint32_t v, bool check_legal);

  // The vertex likely to be collapsed next (the heap's runner-up) is anywhere in the
  // region: its records, asked for one collapse ahead, are there when its turn comes.
  // Inlined always, as every function that only prefetches (formats/wedge_codes.h,
  // UnknownIds::prefetch, says why).
  [[gnu::always_inline]] void fetch(uint32_t v) const {
    __builtin_prefetch(&vertex_[v]);
    __builtin_prefetch(&best_[v]);
    __builtin_prefetch(&xyz_[3 * std::size_t{v}]);
  }

  // apply()'s measure of the collapse v -> u at the top (collapse_measure.cpp): whether v
  // is still at the top with it. `fan` (n_fan faces, the first `moved` v's moved ones) and
  // old_faces (n_old) as make_fan() makes them; `star` v's, aimed at u, with attributes.
  bool measured_at_top(Worker& worker, uint32_t v, uint32_t u, const Star& star,
                       const Neighbour* ring_v, int n, const KeptPoints::FanFace* fan, int n_fan,
                       int moved, const uint32_t* old_faces, int n_old);

  // Applies v's queued collapse if it is still legal, or finds v's best again
  // (collapse_apply.cpp).
  void apply(Worker& worker, uint32_t v);

  // How far the collapse in `star` moves a texture seam within the surface, scaled as the
  // measured distance it joins (as the former default loop's remeasure()); 0 without
  // texture coordinates.
  double seam_drift(const Star& star) const {
    if (!seam_drift_) return 0;
    return (schroeder_ ? SeamDrift::kDriftScale : kDriftScale) * seam_drift_->collapse_drift(star.c);
  }

  // Whether a queued key may hold more than the cost: the measured distance, or with
  // EncodeOptions::fast a texture seam's drift. Otherwise measured_ is empty (nothing to
  // track: the key is the cost).
  bool keyed_by_measure() const { return measure_ || seam_drift_; }
  // v's queued key holds no measure (yet): apply() measures it when v comes to the top.
  void unmeasure(uint32_t v) {
    if (keyed_by_measure()) measured_[v] = kNotMeasured;
  }

  // A new heap (a round's, or the one heap after the rounds) takes v as it was: its
  // candidate, since every collapse that changed v's options had it evaluated again
  // (apply()) or dropped it (best_ says so), and its measure unless a collapse since reset
  // it (queued_measured_key()); v is evaluated when it has no candidate, or one w may not
  // make. A collapsed vertex stays out (its best_ still names the collapse it made).
  void requeue(Worker& w, uint32_t v) {
    if (dead_vertex_[v]) return;
    const Best& best = best_[v];
    if (best.target == kNone || !owns(w, v) || !owns(w, best.target)) {
      evaluate(w, v);
      return;
    }
    float key;
    if (queued_measured_key(v, &key)) {
      w.queue(v, key);
    } else {
      w.queue(v, best.key);
      if (!fan_part_known(v)) unmeasure(v);  // a known fan's part still holds
    }
  }

  // v's key as apply() last queued it, when it holds a measure still valid (measured_ says so;
  // every change around v since has reset it): a new round's heap takes it as it was, rather
  // than the cost alone, which would have v measured again when it comes to the top.
  // Not when only v's fan's part is known (kPointsMoved*): its key is queued as a key
  // that holds no measure would be.
  bool queued_measured_key(uint32_t v, float* key) const {
    if (!measure_ || measured_[v] == kNotMeasured || fan_part_known(v)) return false;
    *key = combined(best_[v].key, measured_worst_[v]);
    return true;
  }

  // Queues v with its quadric cost plus the squared measure `worst` (as the former default loop's
  // combined() for the quadric metric); whether v is still the cheapest.
  bool top_with_measure(Worker& worker, uint32_t v, double worst) {
    const float key = combined(best_[v].key, worst);
    if (key == worker.key(v)) return true;
    worker.queue(v, key);
    return worker.cheapest() == v;
  }

  // The faces of the collapse v -> u (sides s): into `fan`, v's faces but the two at v-u
  // with u in place of v (*moved of them), then u's other faces; into old_faces, all of v's
  // faces (old_fan_face() makes their fan faces when the measure needs them). Returns the
  // fan's size.
  int make_fan(uint32_t v, uint32_t u, const Sides& s, const Neighbour* ring_v, int n_v,
               KeptPoints::FanFace* fan, uint32_t* old_faces, int* n_old, int* moved) const {
    const uint32_t fl = s.h == kNone ? kNone : s.h / 3, fr = s.t == kNone ? kNone : s.t / 3;
    const Vec3 pu = point(u);
    int n_fan = 0;
    auto corner = [&](uint32_t h) {
      const uint32_t w = half_[h].vertex;
      return w == v ? pu : point(w);
    };
    auto add = [&](uint32_t f) {
      fan[n_fan++] =
          KeptPoints::FanFace::make(f, corner(3 * f), corner(3 * f + 1), corner(3 * f + 2));
    };
    for (int i = 0; i < n_v; ++i) {
      const uint32_t e = ring_v[i].edge;
      if (half_[e].vertex != v) continue;  // the boundary's last entry: its face came already
      const uint32_t f = e / 3;
      old_faces[(*n_old)++] = f;
      if (f != fl && f != fr) add(f);
    }
    *moved = n_fan;
    Neighbour ring_u[kMaxValence];
    bool boundary_u;
    const int n_u = ring(u, ring_u, kMaxValence, &boundary_u);
    for (int i = 0; i < n_u; ++i) {
      const uint32_t e = ring_u[i].edge;
      if (half_[e].vertex != u) continue;
      const uint32_t f = e / 3;
      if (f != fl && f != fr) add(f);
    }
    return n_fan;
  }

  // Face f as it is now.
  KeptPoints::FanFace old_fan_face(uint32_t f) const {
    return KeptPoints::FanFace::make(f, point(half_[3 * f].vertex), point(half_[3 * f + 1].vertex),
                                     point(half_[3 * f + 2].vertex));
  }

  // A boundary vertex's walk starts at its outgoing half-edge with no twin.
  void start_at_boundary(uint32_t x) {
    const uint32_t first = vertex_[x].outgoing;
    if (first == kNone) return;
    uint32_t h = first;
    while (half_[h].twin != kNone) {
      h = next_of(half_[h].twin);
      if (h == first) return;  // interior
    }
    vertex_[x].outgoing = h;
  }

  // Per-vertex quadrics of the input, as the former default loop's (commit 3cb92db): each face's
  // plane weighted by its area (§6.1), and along each boundary and feature edge a plane
  // through the edge perpendicular to its face (§6.2).
  void initialize_quadrics();

  // The records in the given ids: in one pass at the end, where each lookup is independent
  // of the next, instead of a dependent cache miss in every collapse. Their faces from
  // where compact_faces() left off (it renames those before).
  void to_given_ids();
  // The faces of the records made since the last call, in the given ids (face_of_ as it is).
  void faces_to_given_ids();
  // Renames the faces without the dead ones and shrinks every per-face and per-half-edge
  // array (face_renumbering.h), between rounds: the sequence stays the same.
  void compact_faces();
  // The records' collapses and moved-face blocks whose faces are in the given ids already.
  std::size_t given_faces_collapses_ = 0, given_faces_blocks_ = 0;

  // What is left, in the given ids, increasing.
  void write_base();

  const EncodeOptions& options_;
  Simplification& out_;
  const WeldGroups welds_;
  const std::set<std::pair<uint32_t, uint32_t>> carried_edges_;
  const double cos_feature_angle_, cos_max_flip_;
  bool features_;              // some edge can be a feature (by angle, or a seam)
  const bool angle_features_;  // the angle is below 180 degrees
  const bool schroeder_;       // Schroeder's metric (schroeder_costs.cpp), else quadrics
  const bool measure_;         // the measured distance joins the key (EncodeOptions::fast: no)
  // Without the measure, the quadric metric's cost has its plane term (FanPlanes); not with
  // attributes (attach_attributes() turns it off).
  bool plane_term_;
  // LoopSwitches' (simplifier.h), for tests.
  const bool reuse_fan_part_, keep_apex_candidates_, compact_faces_, price_at_top_;
  // Whether evaluations queue the cheapest geometric cost, the attributes priced at the top
  // (LoopSwitches::price_at_top): without the measure, with attributes, the quadric metric.
  bool pricing_at_top() const { return price_at_top_ && attributes_ && !measure_ && !schroeder_; }
  const unsigned threads_;     // run_in_turn's (EncodeOptions::threads)
  std::vector<uint32_t> vertex_of_, local_vertex_;  // local vertex id <-> the given one
  std::vector<uint32_t> face_of_;                   // local face id -> the given one
  // Positions, three per local vertex, apart from the rest: a collapse reads the positions
  // of a few dozen neighbours and nothing else of them, and 12 bytes a vertex stay in the
  // cache where the 64-byte records miss (find_best() spent a third of its time waiting
  // for neighbours' records). They never change: a half-edge collapse keeps u in place.
  std::vector<float> xyz_;
  // What the loop reads of the vertex it evaluates or collapses, in one cache line.
  struct alignas(64) VertexRecord {
    LocalQuadric quadric;       // its origin: the vertex's position
    uint32_t outgoing = kNone;  // a half-edge leaving it; on a boundary, the one with no twin
    uint8_t pinned = 0;        // never removed
    uint8_t input_corner = 0;  // classified a corner on the input
    uint8_t simple = 0;        // of kind kSimple when last evaluated (apply()'s shortcut)
    uint8_t cheapest = 0;      // its queued option was its cheapest then, legal or not
    uint8_t sharp_corner = 0;  // Schroeder's metric: an input corner of a sharp edge
    uint8_t unpriced = 0;      // queued at its geometric cost, a bound (pricing_at_top())
  };
  static_assert(sizeof(VertexRecord) == 64);
  // Half-edge h = 3f + k of face f: the vertex it leaves and its twin (kNone on a boundary).
  struct HalfEdge {
    uint32_t vertex, twin;
  };
  std::vector<VertexRecord> vertex_;
  std::vector<HalfEdge> half_;
  std::vector<uint8_t> face_dead_;
  // Per vertex: collapsed. Apart from vertex_: a new round's requeue() reads it for every
  // vertex, in the second order's scattered one, and a byte per vertex stays in the cache
  // where the 64-byte records miss.
  std::vector<uint8_t> dead_vertex_;
  // Per vertex: its cheapest collapse, queued in a worker's heap while the vertex is there;
  // target kNone when it has none (or has not been evaluated since it last waited).
  struct Best {
    uint32_t target;  // u
    uint32_t edge;    // a half-edge of a face on v-u (Neighbour::edge)
    float key;        // its cost (the heap's key adds its measure once measured: apply())
  };
  std::vector<Best> best_;
  // The measured error: points kept per face, and per vertex whether its queued key holds
  // their distance, or the first part of it (apply()). A measured distance counts as its
  // square, as in the former default loop's combined() for the quadric metric, but twice: the fast
  // loop measures less than the former default loop (kKept points per face, the new surface
  // against the old one rather than the input), and on the shared meshes at 50/10/2% the
  // weight 2 brings its Hausdorff distance from 1.05x the former default loop's to 0.97x
  // (geometric means; RMS 1.01x -> 0.99x), 3 and 4 about as well, 1.5 less
  // (tests/bench/fast.md; the fastquality helper's notes). A candidate is queued at its
  // cost alone (queued_key()). With the measure against the input (kept_points.h's
  // input_distance()), 2 stays best: 1.5, 2.5 and 3 left more points above 1.05x.
  static constexpr double kWorstCaseWeight = 2.0;
  // The plane term's weight (FanPlanes). Against meshopt_simplify on the 8 shared meshes at
  // 50/10/2%, Hausdorff and RMS geometric means (0: the quadric alone, 0.920 and 0.844):
  // 0.03: 0.767, 0.821; 0.1: 0.737, 0.809; 0.25: 0.691, 0.816; 0.5: 0.695, 0.830; 1: 0.758,
  // 0.858; 4: 0.878, 0.901 (each v's ring walked again per option then; this loop's is 0.686
  // and 0.815).
  static constexpr double kPlaneWeight = 0.25;
  // With Schroeder's metric the measured distance joins the key as the larger of the two,
  // as in the former default loop, but weighs three times for the same reason (on 6 shared meshes
  // at 50/10/2%, fast/default Hausdorff geometric mean 1.15 at weight 1, 1.08 at 2, 1.04 at
  // 3; RMS 1.04, 0.97, 0.95: tests/bench/fast_schroeder.md). Measured against the input
  // too (kept_points.h), 3 stays best: 2 left 2 of 72 points above 1.05x, 3 none.
  static constexpr double kSchroederWorstWeight = 3.0;
  // Quadric metric, texture: its error (Hoppe 1999, §4) weighs 0.03 of the former default loop's,
  // a seam's drift as there (3.5 / sqrt kWorstCaseWeight): surface and texture at most
  // meshopt's (tests/bench/attr_quality.md, uv.md; tests/bench/README.md says more).
  static constexpr double kUvCostWeight = 0.03;
  static constexpr double kDriftScale = SeamDrift::kDriftScale * 0.70710678118654752;
  KeptPoints kept_;
  KeptPoints::InputSurface input_;  // kept_.input_distance()'s
  // How much of v's queued key is measured (apply()): nothing; the kept points' part; the
  // whole, the fan's part (the moved faces against the old fan and the input) at most the
  // points' or above it; or the whole, but points have moved onto v's faces since, which
  // changes the points' part alone (kPointsMoved*, as the whole was).
  enum : uint8_t {
    kNotMeasured,
    kMeasuredPoints,
    kMeasuredWhole,
    kMeasuredWholeFanAbove,
    kPointsMovedFanBelow,
    kPointsMovedFanAbove
  };
  static bool whole_measured(uint8_t m) {
    return m == kMeasuredWhole || m == kMeasuredWholeFanAbove;
  }
  bool fan_part_known(uint32_t v) const {
    return measure_ &&
           (measured_[v] == kPointsMovedFanBelow || measured_[v] == kPointsMovedFanAbove);
  }
  std::vector<uint8_t> measured_;  // per vertex, the enum above (empty unless keyed_by_measure())
  // The measured distance v's queued key holds (apply()): the kept points' with
  // kMeasuredPoints, else the whole (unless kNotMeasured). Empty with fast.
  std::vector<double> measured_worst_;
  // Attributes kept (attach_attributes()), in local ids until run() ends; null: geometry
  // only. The drift of texture seams, null without texture coordinates.
  std::unique_ptr<CornerAttributes> attributes_;
  std::unique_ptr<SeamDrift> seam_drift_;
  // With attributes, per half-edge: on a seam or a material border (seam_now()), kept up to
  // date at each collapse (update_seams_at()) so that classifying a vertex, which the loop
  // does at every evaluation, reads one byte per edge instead of comparing corners.
  std::vector<uint8_t> seam_;
  // The record: every removed point, on a face of the level (tracked_points.h).
  TrackedPoints tracked_;
  bool partitioned_ = false;    // rounds first (run_rounds())
  bool in_rounds_ = false;      // regions at once (run_rounds()), else one heap
  std::vector<uint8_t> band_;   // per vertex: next to its region's edge (run_rounds())
  // run_rounds()'s second order: the vertex at each rank, and each vertex's rank.
  std::vector<uint32_t> order_b_, rank_b_;
  std::size_t faces_alive_ = 0, vertices_alive_ = 0;
  float bound_ = 0;
};

}  // namespace pm::collapse_loop
