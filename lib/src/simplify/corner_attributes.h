// Texture coordinates, normals and materials on the half-edge mesh while it is simplified
// (Hoppe 1996, "Progressive meshes", §3: each face corner refers to a "wedge" of attribute
// values, so that a vertex on a UV seam or a crease carries several).
//
// A half-edge collapse v -> u keeps u and its wedges; each corner of v that survives (in
// the faces that move from v to u) takes the wedge of u on its side of the collapsed edge.
// Seams and material borders are discontinuities to keep (Garland and Heckbert 1998, §4;
// Hoppe 1999, §5): a collapse is allowed only along them, never across, so no seam opens
// and none closes. The cost of a collapse adds an attribute error, scaled to model units:
// Hoppe 1999's (§4: over each face, the attribute as a linear function of position; a
// corner moved to u is off by what the face's function gives at u against the value the
// corner takes), but over v's faces as they are now, not summed over every input face v
// has come to stand for (memoryless, as Lindstrom and Turk 1998, §3, price geometry). It
// keeps no state per wedge: the quadrics it replaced (a float quadric per wedge, about its
// vertex) were a quarter of pmenc's peak memory on a textured mesh, and in float they lost
// the small deviations of a large mesh's small faces to the rounding of the values' squares
// (tests/bench/README.md, "The textured whole process", has the measurements).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "simplify/face_renumbering.h"
#include "simplify/geometry.h"
#include "simplify/record_list.h"
#include "pm/mesh.h"

namespace pm {

// What a collapse did to the attributes, for the vertex split that undoes it.
// Places (record_list.h): a collapse's moved ids start at its Collapse::moved_begin, as its
// moved faces do; its removed faces' ids at 3 * Collapse::new_faces_begin.
struct CollapseAttributes {
  // Per moved face, in the order the simplifier lists them: the corner's ids before the
  // collapse (empty lists for a kind the input lacks).
  RecordList moved_uvs{kMovedEntriesPerBlock}, moved_normals{kMovedEntriesPerBlock};
  // The removed faces' corners before the collapse: fl as (v, u, vl), then fr as (u, v, vr).
  RecordList new_face_uvs{kNewFaceEntriesPerBlock}, new_face_normals{kNewFaceEntriesPerBlock};

  // Room for one collapse that moves at most `moved` faces, in the lists of the kinds kept
  // (with the same `moved` as the loop's moved-face list, so that their places agree).
  void make_room(bool uvs, bool normals, uint32_t moved) {
    if (uvs) moved_uvs.make_room(moved), new_face_uvs.make_room(6);
    if (normals) moved_normals.make_room(moved), new_face_normals.make_room(6);
  }
  // The next removed face's place, in faces (0 without texture coordinates and normals).
  uint32_t new_faces_place() const {
    return (!new_face_uvs.empty() ? new_face_uvs.end() : new_face_normals.end()) / 3;
  }
  // Moves from's lists after these (RecordList::take()) and returns how far its new faces'
  // places moved, in faces; its moved ids' places move as the loop's moved-face list's do.
  uint32_t take(CollapseAttributes& from) {
    moved_uvs.take(from.moved_uvs);
    moved_normals.take(from.moved_normals);
    const uint32_t uv_shift = new_face_uvs.take(from.new_face_uvs);
    const uint32_t normal_shift = new_face_normals.take(from.new_face_normals);
    return (!new_face_uvs.empty() ? uv_shift : normal_shift) / 3;
  }
};

// A half-edge collapse v -> u as a collapse loop describes it, in the face and vertex ids
// the CornerAttributes were built with: what the attribute rules read, so that any loop
// (OpenMesh's half-edge mesh, the collapse loop's directed edges) shares them.
struct CollapseStar {
  static constexpr uint32_t kNoFace = 0xFFFFFFFFu;
  // An edge v-w and its faces: f holds the half-edge v -> w or w -> v, g the other (kNoFace
  // on a boundary).
  struct Edge {
    uint32_t w, f, g;
  };
  uint32_t v, u;
  uint32_t fl, fr;  // the faces (v, u, vl) and (u, v, vr), kNoFace where there is none
  uint32_t vl, vr;  // their third vertices (anything where the face is absent)
  Vec3 pu;          // u's position
  Vec3 pv;          // v's position
  // v's faces, fl and fr among them, in the order the loop lists the faces that move.
  const uint32_t* faces;
  int n_faces;
  const Edge* edges;  // v's edges, each once
  int n_edges;
  // The loop knows that none of v's edges is a seam or a material border (it keeps that
  // per edge): then every kind allows the collapse and collapse_keeps_attributes() asks
  // only the texture winding. False: the edges are compared.
  bool seamless = false;
};

// The loop's faces as it holds them: vertex k of face f at first[stride * (3 f + k)] (the
// collapse loop's half-edges: {vertex, twin} per half-edge 3 f + k, stride 2; a plain corner
// array: stride 1). CornerAttributes reads them and never writes: they are the loop's,
// which moves v's corners to u after CornerAttributes::collapse().
struct FaceVertices {
  const uint32_t* first = nullptr;
  std::size_t stride = 1;
  uint32_t operator()(std::size_t f, int k) const { return first[stride * (3 * f + k)]; }
};

class CornerAttributes {
 public:
  // The input's corner ids for each face of the loop's mesh: face f has vertices
  // corners(f, 0..2) (distinct), at points (three floats per vertex); input_face[f] is its
  // input triangle and input_vertex[x] the input vertex of x (null: the identity). corners
  // must stay valid and current until finish() (they are read, not copied: a face's record
  // would hold its vertices again), and points while costs are asked (collapse_cost() reads
  // them). The faces' records are made on `threads`. `inputs_read`, when set, is called once
  // they are made: afterwards neither input_face and input_vertex nor the input's
  // triangles, corner indices and materials are read (only its uvs and normals), so that
  // the caller may let them go before the wedges are numbered.
  CornerAttributes(const Mesh& input, FaceVertices corners, std::size_t n_faces,
                   const float* points, std::size_t n_vertices, const uint32_t* input_face,
                   const uint32_t* input_vertex, unsigned threads = 1,
                   const std::function<void()>& inputs_read = {});

  bool has_uvs() const { return kinds_[kUv].present; }
  bool has_normals() const { return kinds_[kNormal].present; }
  // The input has materials (even if every face was carried aside and none is here).
  bool has_materials() const { return has_materials_; }
  bool any() const { return has_uvs() || has_normals() || has_materials(); }

  // The interior edge a-b between faces f and g: whether they differ in material, or in a
  // corner's texture coordinates or normal at either end (compared by value, bit for bit).
  // False when g is kNoFace (a boundary).
  bool is_seam(uint32_t f, uint32_t g, uint32_t a, uint32_t b) const;
  // Texture-coordinate seams only (SeamDrift follows them).
  bool is_uv_seam(uint32_t f, uint32_t g, uint32_t a, uint32_t b) const {
    return has_uvs() && is_seam_of_kind(kUv, f, g, a, b);
  }

  // For each kind, the collapse v -> u is legal when v is on no seam of that kind, or on
  // exactly two of its seam edges, one of them v-u (v slides along the seam), and when u's
  // two sides of v-u differ only if v's do. And no face that moves turns its texture-space
  // winding over or flat (Hoppe 1996, §3 keeps attributes; this keeps the texture from
  // folding).
  bool collapse_keeps_attributes(const CollapseStar& c) const;

  // The attribute error of the collapse in squared model units: for each kind, over v's
  // faces, the squared difference between the face's linear attribute at u's position and
  // the value its corner at v takes (u's, on that corner's side of the collapsed edge), as
  // a mean weighted by the faces' areas, times the kind's scale squared and its weight
  // (weigh_costs()). Only while the loop runs: it reads the loop's positions.
  double collapse_cost(const CollapseStar& c) const;
  // How much each kind's error counts in collapse_cost(): 1 and 1 unless set (the former default
  // loop's); the collapse loop weighs the texture error less (collapse_loop.h, kUvCostWeight).
  void weigh_costs(double uv, double normal) {
    kinds_[kUv].cost_weight = uv;
    kinds_[kNormal].cost_weight = normal;
  }

  // v's faces' attribute functions (Hoppe 1999, §4), about v's position: the part of the
  // cost that is the same for every target, so that a loop pricing all of v's options
  // makes them once (star_fields(), then collapse_cost(c, fields) per target).
  struct StarFields {
    static constexpr int kMostFaces = 64;  // collapse_loop.h's kMaxValence
    static constexpr int kMostDims = 3;
    struct Field {
      double area;
      double gradient[kMostDims][3];  // per component: a(p) = gradient . (p - pv) + offset
      double offset[kMostDims];
      uint32_t wedge;  // of the face's corner at v
    };
    Field fields[2][kMostFaces];  // per kind (texture coordinates, normals)
    int count[2];
  };
  void star_fields(const CollapseStar& c, StarFields& out) const;
  // collapse_cost(c), given star_fields() of a star with the same v and faces.
  double collapse_cost(const CollapseStar& c, const StarFields& fields) const;

  // Applies the collapse to the corners' ids and wedges (call before the loop changes its
  // mesh, once the collapse is decided; the loop then moves v's corners to u in its faces,
  // which `corners` reads): appends what the split needs to `record`, which has room for it
  // (CollapseAttributes::make_room()); the moved faces are c.faces but fl and fr, in that
  // order.
  void collapse(const CollapseStar& c, CollapseAttributes& record);

  // Asks for face f's corners ahead of reading them (star_wedges(), collapse_cost(),
  // collapse_keeps_attributes(): their loads of a star's faces miss the cache): both ends
  // of its record, which may lie across two cache lines. Inlined always, as every function
  // that only prefetches (formats/wedge_codes.h, UnknownIds::prefetch, says why).
  [[gnu::always_inline]] void prefetch(uint32_t f) const {
    const char* record = reinterpret_cast<const char*>(&faces_[f]);
    __builtin_prefetch(record);
    __builtin_prefetch(record + sizeof(FaceCorners) - 1);
  }

  // The current corner ids of face f at the given vertices (in that order).
  void corner_ids(uint32_t f, const uint32_t (&at)[3], uint32_t (&uvs)[3],
                  uint32_t (&normals)[3]) const;
  uint32_t material(uint32_t f) const { return has_materials_ ? materials_[f] : kNoAttribute; }

  // The loop's faces renamed without the dead ones (face_renumbering.h), between collapses;
  // given_face[f]: face f's id in the caller's ids (finish()'s face_of) before the renaming.
  // The dead faces' materials are kept aside in the caller's ids (their splits restore
  // them), the live faces' records move. `corners` must read the renamed faces afterwards
  // (the loop renames its half-edges in place).
  void compact(const FaceRenumbering& faces, const uint32_t* given_face);

  // After the last collapse, before the loop's positions go: no cost may be asked
  // afterwards (the corners stay, for the assembly).
  void end_collapses() { points_ = nullptr; }

  // After the loop (and end_collapses()), while `corners` still reads its faces: keeps what
  // the assembly reads, in the caller's ids, face f becoming face_of[f] and vertex x
  // vertex_of[x] (a loop that works in its own ids hands the result back in the caller's):
  // every face's material, and the corners of the faces still alive (face_dead[f] false:
  // the base mesh's), with their vertices. The faces' records go, so that the assembly does
  // not build the progressive mesh beside them (then 64 bytes a face: 58 MiB of the
  // 950K-face textured mesh, where pmenc --fast peaked in the assembly). Then corner_ids()
  // answers for those faces only, material() for all; nothing else may be asked, and
  // `corners` is no longer read.
  void finish(const std::vector<uint32_t>& face_of, const std::vector<uint32_t>& vertex_of,
              const std::vector<uint8_t>& face_dead);

 private:
  static constexpr int kUv = 0, kNormal = 1, kKinds = 2;
  struct Kind {
    bool present = false;
    int dims = 0;
    const std::vector<float>* values = nullptr;  // the input's table
    double scale = 0;  // model units per attribute unit
    double cost_weight = 1;  // weigh_costs()
    const float* value(uint32_t id) const { return values->data() + std::size_t{id} * dims; }
  };
  // Which of three vertices is w (0, 1 or 2; 2 when neither of the first two).
  static int corner_among(uint32_t a, uint32_t b, uint32_t w) { return a == w ? 0 : b == w ? 1 : 2; }
  // Which corner of face f holds vertex w (0, 1 or 2).
  int corner_of(uint32_t f, uint32_t w) const {
    return corner_among(corners_(f, 0), corners_(f, 1), w);
  }
  // The wedge of face f's corner at vertex w. A vertex has one wedge per value class (ids
  // whose values have the same bits; number_wedges()), and a collapse gives each moved
  // corner both the id and the wedge of one of u's corners (collapse()): so two corners of
  // a vertex have the same wedge exactly when their values have the same bits (or both
  // none, kNoWedge), and the rules compare wedges where they compare values, in the face
  // records they read already.
  uint32_t wedge_at(int kind, uint32_t f, uint32_t w) const {
    return faces_[f].wedge[kind][corner_of(f, w)];
  }
  // kind kKinds stands for materials.
  bool is_seam_of_kind(int kind, uint32_t f, uint32_t g, uint32_t a, uint32_t b) const;
  bool kind_allows(int kind, const CollapseStar& c) const;
  bool keeps_uv_winding(const CollapseStar& c) const;
  // The corner of u whose wedge a corner of v with wedge w takes: u's corner in fl when w
  // is v's wedge in fl, else in fr. Returns {face, corner index}.
  std::pair<uint32_t, int> target_corner(int kind, const CollapseStar& c, uint32_t v_wedge) const;
  // value_class: per id, the smallest id with the same value bits (value_classes()); begin and
  // corners: each vertex's corners (3 f + c), corners[begin[x]] to corners[begin[x + 1]], in
  // face order.
  void number_wedges(int kind, const std::vector<uint32_t>& value_class,
                     const std::vector<uint32_t>& begin, const std::vector<uint32_t>& corners);

  // Per face, per kind: its corners' ids and wedges (kNoAttribute and kNoWedge where the
  // kind is absent). One record a face: the rules read a star's faces together, and with an
  // array per kind and field (and a value-class table) each face missed the cache five
  // times or more. The textured 950K-face mesh's loop without its measure, one thread,
  // medians of alternating runs: prefetch() alone 6.53 -> 6.26 s; a record and wedge_at()
  // with it 6.16 -> 5.24 s. Its vertices are the loop's (corners_) and its material apart
  // (materials_): 48 bytes instead of a cache line's 64, 14.5 MiB less on that mesh.
  struct alignas(16) FaceCorners {
    std::array<uint32_t, 3> id[kKinds];
    std::array<uint32_t, 3> wedge[kKinds];
  };
  static_assert(sizeof(FaceCorners) == 48, "no padding");
  FaceVertices corners_;
  std::vector<FaceCorners> faces_;
  Kind kinds_[kKinds];
  bool has_materials_ = false;
  // Per face, its material (has_materials_ alone): in the loop's ids, then the caller's.
  // Once faces were renamed (compact()), the materials of the faces dead by then in
  // given_materials_, in the caller's ids (one per face the loop began with).
  std::vector<uint32_t> materials_, given_materials_;
  std::size_t first_faces_ = 0;  // the faces the loop began with
  const float* points_ = nullptr;  // the loop's positions, three floats per vertex
  // finish(): faces_ holds the live faces' records alone, in the order of their caller's ids
  // (live_ids_), and live_vertices_ their corners' vertices in the caller's ids.
  bool finished_ = false;
  std::vector<uint32_t> live_ids_, live_vertices_;
};

}  // namespace pm
