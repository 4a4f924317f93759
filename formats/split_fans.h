// The connectivity a 2.0 .pm stream is coded against: the faces of the current level and,
// per vertex, the corners that use it, kept up to date split by split. It gives the fan of
// faces around a vertex in counter-clockwise order, which is what lets a split name vl and
// vr by their place in u's one-ring, and leave its moved faces implicit (Hoppe 1996, §3:
// vsplit(s, l, r) takes the faces between l and r around s; Hoppe 1998, "Efficient
// implementation of progressive meshes", §4 codes l and r the same way, as positions in
// s's ring). Internal to the codec.
//
// The fan of u: the faces (u, r[k], r[k+1]), k = 0 .. n-1, for the ring r[0 .. n] around
// u. A vertex in the interior of the surface has a closed fan (r[n] == r[0]; r[0] is then
// the ring's smallest vertex id, so that the coding does not depend on the order in which
// faces were stored); a vertex on a boundary has an open one (r[0] and r[n] are its
// boundary neighbours). A vertex whose faces are not one fan (pinched, or faces with
// inconsistent orientation) has none: such splits are stored explicitly.
//
// Each vertex's corners are a linked list, kept in fan order (each face's next counter-
// clockwise, the swing order of a corner table) by the splits that name their arc: fan() is
// then a walk of the list. A list out of order (the base mesh's, or after an explicit split)
// is searched once, and left in order.
//
// The split of the half-edge collapse v -> u moves the faces between vl and vr, counter-
// clockwise around u: with i the place of vl in the ring (0 when vl is none: the open fan's
// start) and j that of vr (n when vr is none), the faces k = i .. j-1 (modulo n when
// closed). v's ring in the refined mesh is then u, r[i], ..., r[j].
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pm::detail {

class SplitFans {
 public:
  static constexpr uint32_t kNone = 0xFFFFFFFFu;

  // Room for this many vertices and faces; keeps nothing. Faces are then added in order.
  void reset(std::size_t vertex_count, std::size_t face_count);
  void add_face(uint32_t a, uint32_t b, uint32_t c);
  std::size_t face_count() const { return faces_.size(); }
  const uint32_t* face(uint32_t f) const { return faces_[f].vertex; }

  struct Fan {
    std::vector<uint32_t> ring;   // n + 1 vertices (ring[n] == ring[0] when closed)
    std::vector<uint32_t> faces;  // n faces: faces[k] = (u, ring[k], ring[k + 1])
    bool closed = false;
  };
  // u's fan, or false when u's faces do not form one (or u has none).
  bool fan(uint32_t u, Fan& out);

  // The arc of faces from place i to place j of `fan` (see the top of this file); false
  // when the places do not define one: i or j out of range, or j <= i on an open fan, or
  // i == j on a closed one.
  static bool arc(const Fan& fan, std::size_t i, std::size_t j, std::vector<uint32_t>& faces);

  // Applies a split: creates vertex v (the next id), turns corner u of each moved face into
  // v, then appends fl = (v, u, vl) when vl exists and fr = (u, v, vr) when vr exists. The
  // caller has checked that each moved face holds u (holds_once).
  //
  // `fan`, when given, is u's fan as fan() returned it, and the moved faces are its arc from
  // place `first` (arc()): the corner lists of u, v, vl and vr are then left in fan order
  // (see fan()), so that the next fan() of each is a walk, not a search.
  void split(uint32_t u, uint32_t v, uint32_t vl, uint32_t vr, const uint32_t* moved,
             std::size_t moved_count, const Fan* fan = nullptr, std::size_t first = 0);
  // Whether face f exists and holds u exactly once.
  bool holds_once(uint32_t f, uint32_t u) const;
  // The corner (0, 1, 2) of face f that is u (u must be one of its vertices; 2 otherwise).
  // Branch-free: which corner holds a vertex is as good as random.
  int slot_of(uint32_t f, uint32_t u) const {
    const uint32_t* v = face(f);
    return static_cast<int>(v[0] != u) * (2 - static_cast<int>(v[1] == u));
  }

  // How many fan() calls found a vertex's corners out of fan order and searched them (the
  // base mesh's, once each; after a split without `fan`): a measure of split()'s upkeep.
  std::size_t searches() const { return searches_; }

  // Walks the fans of the vertices to be split next a step at a time, a few splits ahead,
  // fetching each face record (and the ring vertices' values, 3 per vertex in `values`,
  // when not null) into the cache: a fan is a chain of face records scattered over the
  // mesh, each found in the one before, and walked when asked for it waits for memory at
  // every face (the coder's largest cost). Ahead, the walks of kAhead vertices overlap.
  // Only a hint: splits made meanwhile may change a fan; whatever the walk finds then is
  // fetched for nothing, and fan() is the same either way.
  class Prefetch {
   public:
    static constexpr std::size_t kAhead = 8;
    // `values`: 3 per vertex, as many as there are so far (null: none). Its storage must not
    // move while this lives (a reserved vector).
    Prefetch(const SplitFans& fans, const std::vector<uint32_t>* values);
    Prefetch(const Prefetch&) = delete;
    Prefetch& operator=(const Prefetch&) = delete;
    // Once per split, before its fan(): u of the split kAhead further on (kNone: none).
    void step(uint32_t u_ahead);
    // Also asks, for each vertex of the walk, for its `per_vertex` entries of `values` (the
    // colours), and for each face of the walk, for its 3 entries of `rows` (a wedge coder's
    // corner ids, as many as there are faces so far): what predicting the split reads next
    // (the colours' and texture coordinates' loads were a third of the writer's coding time,
    // most of it waiting for memory). Each storage must not move while this lives. Two
    // lists of values in all (the positions and the colours) and two of rows (the two wedge
    // kinds', as the writer and reader ask) are fetched; one beyond them is not, which costs
    // time only: this is a hint.
    void also_values(const std::vector<uint32_t>* values, std::size_t per_vertex) {
      if (values && n_values_ < kMost) values_[n_values_++] = {values, per_vertex};
    }
    // `units`, when not null: `per_id` entries per id the rows hold (the coder's values),
    // asked for a step after the row that names them.
    void also_rows(const std::vector<uint32_t>* rows, const std::vector<uint32_t>* units = nullptr,
                   std::size_t per_id = 0) {
      if (rows && n_rows_ < kMost) rows_[n_rows_++] = {rows, units, per_id};
    }

   private:
    static constexpr uint32_t kFirst = 0xFFFFFFFEu;  // a walk waiting for its first corner
    static constexpr int kMost = 2;
    struct PerVertex {
      const std::vector<uint32_t>* values;
      std::size_t per_vertex;
    };
    struct Rows {
      const std::vector<uint32_t>* ids;
      const std::vector<uint32_t>* units;
      std::size_t per_id;
    };
    // x's entries of each, when it has them so far. Both inlined always, as every function
    // that only prefetches (wedge_codes.h, UnknownIds::prefetch, says why).
    [[gnu::always_inline]] inline void fetch_values(uint32_t x) const;
    // The units of the ids in face f's rows (fetched a step ago).
    [[gnu::always_inline]] inline void fetch_units(uint32_t f) const;
    const SplitFans& fans_;
    PerVertex values_[kMost] = {};  // the positions (the constructor's), then also_values()'
    int n_values_ = 0;
    Rows rows_[kMost] = {};
    int n_rows_ = 0;
    uint32_t vertex_[kAhead];  // each walk's vertex
    uint32_t corner_[kAhead];  // the corner it reached (fetched a step ago), kFirst or kNone
    uint32_t row_face_[kAhead];  // the face whose rows it asked for a step ago, or kNone
    std::size_t next_slot_ = 0;
  };

 private:
  static constexpr std::size_t kSmallFan = 16;
  bool chained_fan(Fan& out);
  bool small_fan(uint32_t u, Fan& out);
  void split_arc(uint32_t u, uint32_t v, uint32_t vl, uint32_t vr, const Fan& fan,
                 std::size_t first, std::size_t count);
  void insert_after(uint32_t corner, uint32_t added) {
    next_corner(added) = next_corner(corner);
    next_corner(corner) = added;
  }
  void link(uint32_t corner, uint32_t vertex);
  // Makes `corners` (count > 0), in this order, the whole list of `vertex`.
  void relink(uint32_t vertex, const uint32_t* corners, std::size_t count);
  uint32_t& next_corner(uint32_t corner) { return faces_[corner / 3].next[corner % 3]; }

  // A face's corners: the current vertex of each, and the next corner (3f + k) of the same
  // vertex, together: a walk around a vertex reads one place per face, not two arrays.
  struct Face {
    uint32_t vertex[3];
    uint32_t next[3];
  };
  std::vector<Face> faces_;
  std::vector<uint32_t> first_corner_;   // per vertex: its first corner, or kNone
  struct Wedge {                         // one face of a fan being assembled
    uint32_t a, b, face, corner;
  };
  std::vector<Wedge> wedges_;            // scratch for fan()
  std::vector<uint32_t> seconds_;        // scratch for fan()
  std::vector<uint32_t> corners_;        // scratch for split_arc()
  std::size_t searches_ = 0;
};

}  // namespace pm::detail
