// Selective and view-dependent refinement of a progressive mesh (Hoppe 1997, "View-dependent
// refinement of progressive meshes"): each vertex split may be applied or not, independently
// of the splits' order, as long as its dependencies are applied, so that the mesh can be
// fine where it is seen close up and coarse elsewhere; as the viewpoint moves, the active
// mesh is updated by splitting and collapsing only where the criteria changed.
//
// Vertex hierarchy (Hoppe 1997, §2-3; our vertex ids persist through splits): split j acts on
// vertex u and creates v = base_vertex_count + j. Its parent is the split that last changed u
// before it (the previous split of u, or the split that created u); its children are the
// next split of u and the first split of v. Roots are the first splits of base vertices.
//
// Dependencies (Hoppe 1997, §4.2: a vertex split is legal when its vertex is active and the
// faces fn0..fn3 that will neighbour its new faces are active): split j depends on its parent
// and on the splits that created the faces holding the edges (u, vl) and (u, vr) just before
// j. The mesh of a set of splits is a function of the set (each face corner is the deepest
// active ancestor of its full-detail vertex, Hoppe 1997 §4), and every set closed under the
// dependencies is a manifold with the input's topology: selective_refinement.cpp has the
// argument. Applying or collapsing a split only switches its two faces and its flags.
//
// The object holds one selectively refined mesh. Welds, carried faces and loose vertices (the
// repairs of progressive_mesh.h) are output as extract_level() outputs its levels: carried
// faces always, copies merged into their canonical vertex, loose vertices at full detail only.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "pm/mesh.h"
#include "pm/progressive_mesh.h"
#include "pm/status.h"

namespace pm {

inline constexpr uint32_t kNoSplit = 0xFFFFFFFFu;

using Point3 = std::array<double, 3>;

// A perspective camera (Hoppe 1997, §3: the view frustum and the screen-space projection).
struct ViewCamera {
  Point3 eye{0, 0, 1};
  Point3 target{0, 0, 0};
  Point3 up{0, 1, 0};             // need not be orthogonal to the view direction
  double fov_degrees = 60;        // vertical field of view, in (0, 180)
  double viewport_height = 1080;  // pixels
  double viewport_width = 0;      // pixels; 0: the same as the height (a square viewport)
};
// kInvalidArgument with a one-line message when the camera has no view direction (eye ==
// target, or up parallel to it), a field of view outside (0, 180), a viewport of no pixels,
// or a value that is not finite.
[[nodiscard]] Status check_camera(const ViewCamera& camera);

// The criteria of view-dependent refinement (Hoppe 1997, §3.1-3.3). A split is wanted when its
// box (SplitBounds) meets the view frustum, its region is not entirely back-facing (normal cone)
// and its deviation projected on the screen exceeds pixel_error:
//   deviation * K / (distance(eye, centre) - radius) > pixel_error,  K = viewport_height /
//   (2 tan(fov / 2)), infinite when the eye is inside the sphere.
// Wanted splits are applied with their dependencies; all others are collapsed.
struct ViewOptions {
  double pixel_error = 1;      // the screen-space tolerance, pixels, > 0
  bool frustum_culling = true;   // coarsen outside the view frustum
  bool backface_culling = true;  // coarsen where the region is entirely back-facing
};

// Per-split bounds for the criteria, computed from the .pm positions (Hoppe 1997, §3): the
// bounding sphere (centre: u's position) holds the faces around u and v just before and after
// the split, and every descendant's sphere; the normal cone holds those faces' normals and the
// descendants' cones; the deviation bounds how far collapsing the split and its descendants
// moves the surface: the collapse's length |v - u| plus the largest child's deviation. Each
// bound is at least its children's (parents are coarser), so the tests are conservative.
struct SplitBounds {
  float center[3];
  float radius;
  float deviation;
  float cone_axis[3];  // unit
  float cone_angle;    // half-angle, radians; >= pi/2: never back-facing
  // The box of u and of every vertex the split and its descendants create (exact: float
  // minima and maxima): what the frustum test looks at, since a vertex inside the frustum
  // is in the box of its next split.
  float box_lo[3], box_hi[3];
};

// A limit on the work of one incremental update. 0 means no limit.
struct UpdateBudget {
  std::size_t max_operations = 0;  // vertex splits + edge collapses (forced ones included)
  double max_microseconds = 0;
};

struct UpdateStats {
  std::size_t splits = 0;        // applied this update, forced ones included
  std::size_t collapses = 0;
  std::size_t evaluations = 0;   // criteria evaluated
  std::size_t pending = 0;       // splits or collapses left for the next update (a budget)
};

// Which splits a split depends on (see the top of this file and selective_refinement.cpp).
enum class DependencyRule {
  // Hoppe 1997, §4.2: the parent and the creators of fn0..fn3. Every mesh keeps the input's
  // topology; its faces may combine corners that never met in the full sequence, so where
  // the input has exactly collinear vertices (a CAD grid) a face may have zero area.
  kHoppe1997,
  // The last modifier of every face around u, and the parent (Xia and Varshney 1996,
  // El-Sana and Varshney 1999): every face is one of some level of the sequence, so no
  // zero-area face appears that the levels do not have, at the price of much forced
  // refinement (on the shared meshes about 2.6 times as many splits for the same regions).
  kExactRing,
};

// Ownership: borrows its ProgressiveMesh for its whole life (the reference constructor: the
// caller keeps it alive, unmoved and unchanged) or shares it (the shared_ptr constructor, for
// bindings); movable, not copyable.
class SelectiveRefinement {
 public:
  // pm must be valid (see validate()) and outlive this object, unmoved and unchanged: this
  // object reads its positions and attributes. Builds the hierarchy, the dependencies and the
  // bounds in one replay of the splits; starts at the base mesh.
  explicit SelectiveRefinement(const ProgressiveMesh& pm,
                               DependencyRule rule = DependencyRule::kHoppe1997);
  // The same, keeping pm alive for as long as this object lives (pm must not be null).
  explicit SelectiveRefinement(std::shared_ptr<const ProgressiveMesh> pm,
                               DependencyRule rule = DependencyRule::kHoppe1997);
  DependencyRule dependency_rule() const { return rule_; }

  // --- The hierarchy (fixed) ---
  std::size_t split_count() const { return parent_.size(); }
  uint32_t parent(std::size_t split) const { return parent_[split]; }  // kNoSplit: a root
  uint32_t child_u(std::size_t split) const { return child_u_[split]; }  // kNoSplit: none
  uint32_t child_v(std::size_t split) const { return child_v_[split]; }
  // The splits that must be applied before this one (all earlier in the sequence).
  const uint32_t* dependencies(std::size_t split) const { return &deps_[deps_begin_[split]]; }
  std::size_t dependency_count(std::size_t split) const {
    return deps_begin_[split + 1] - deps_begin_[split];
  }
  const SplitBounds& bounds(std::size_t split) const { return bounds_[split]; }
  uint32_t split_vertex(std::size_t split) const { return split_u_[split]; }  // its u

  // --- The current mesh ---
  bool applied(std::size_t split) const { return applied_[split] != 0; }
  std::size_t applied_count() const { return applied_count_; }
  std::vector<uint32_t> applied_splits() const;  // in increasing order
  // Whether the vertex exists in the current mesh (a base vertex, or one whose split is applied).
  bool vertex_active(uint32_t vertex) const;
  // The first split of an active vertex that is not applied (the split that would refine it
  // next), or kNoSplit when it has none left.
  uint32_t pending_split(uint32_t vertex) const;
  // Faces and vertices to_mesh() outputs (carried faces counted; welded copies not counted;
  // loose vertices at full detail only).
  std::size_t face_count() const;
  std::size_t vertex_count() const;

  // --- Direct control ---
  void reset();  // back to the base mesh
  // Applies the split after its unapplied dependencies (forced splits, recursively). Returns
  // how many splits were applied (0 when it already was).
  std::size_t apply(uint32_t split);
  // Collapses an applied split on which no applied split depends. Returns false (and changes
  // nothing) when it is not applied or another applied split depends on it. After apply() or
  // collapse(), the next update_view() evaluates the whole boundary again.
  bool collapse(uint32_t split);
  // Applies exactly the splits of `wanted` (one flag per split) and their dependencies,
  // collapsing every other split.
  void set_applied(const std::vector<bool>& wanted);

  // --- Selective refinement by region: full detail where a split's sphere meets the region,
  // the base mesh elsewhere (with the dependencies those splits need). Every active vertex
  // inside the region is then at full detail.
  void refine_sphere(const Point3& center, double radius);
  void refine_box(const Point3& lo, const Point3& hi);

  // --- Distance-weighted simplification (the source report's ViewDependentModel): from the
  // base mesh, splits in order of deviation / distance from the viewpoint to their sphere, so
  // that vertices near the viewpoint are kept first, while the mesh stays within the budget
  // (faces as face_count(), vertices as vertex_count()). kInvalidArgument when the budget is
  // below the base mesh's count, or the viewpoint is not finite. Give one budget (the other 0).
  [[nodiscard]] Status refine_toward(const Point3& viewpoint, std::size_t max_faces, std::size_t max_vertices);

  // --- View-dependent refinement (Hoppe 1997) ---
  // From scratch: the base mesh, then every wanted split (evaluated top-down through the
  // hierarchy) with its dependencies. kInvalidArgument on a bad camera or tolerance.
  [[nodiscard]] Status set_view(const ViewCamera& camera, const ViewOptions& options);
  // Incremental (Hoppe 1997, §5: temporal coherence): moves the mesh to what set_view() gives
  // for this camera by re-evaluating only the splits on the boundary of the wanted set whose
  // decision may have changed since the previous camera (each carries a margin of camera
  // motion within which its decision cannot change), then splitting and collapsing where it
  // did. Without a budget the result equals set_view()'s, split for split. With a budget the
  // mesh is valid after every update and reaches set_view()'s within the next updates
  // (stats->pending says how much is left). The first update, and any change of options, field
  // of view or viewport, evaluates the whole boundary.
  [[nodiscard]] Status update_view(const ViewCamera& camera, const ViewOptions& options,
                     const UpdateBudget& budget = {}, UpdateStats* stats = nullptr);

  // --- Output ---
  // The current mesh like extract_level(): positions, colours, per-corner texture coordinates
  // and normals, materials. face_levels (when not null) gets, per output face, 1 + the index of
  // the last applied split that created it or moved one of its corners, 0 for a base face no
  // applied split changed. O(faces x the moves of a corner).
  Mesh to_mesh(std::vector<uint32_t>* face_levels = nullptr) const;

  // Bytes held by this object.
  std::size_t memory_bytes() const;

 private:
  // A corner's move to v by a split: the corner's next move is `next` (kNoSplit: none).
  struct MovedCorner {
    uint32_t split;
    uint32_t entry;  // in pm.moved_faces, moved_uvs, moved_normals
    uint32_t next;
  };
  struct ViewState;  // the incremental update's boundary and schedule (view_update.cpp)

  std::size_t apply_with_dependencies(uint32_t split);
  void apply_one(uint32_t split);
  void collapse_one(uint32_t split);
  std::size_t view_memory_bytes() const;  // view_update.cpp
  void activate_face(uint32_t face);
  void deactivate_face(uint32_t face);
  template <class Wanted>
  void refine_top_down(const Wanted& wanted);

  std::shared_ptr<const ProgressiveMesh> owned_;  // null when pm_ is borrowed
  const ProgressiveMesh* pm_;
  DependencyRule rule_;
  uint32_t base_vertex_count_ = 0;
  uint32_t base_face_count_ = 0;
  // Hierarchy and dependencies.
  std::vector<uint32_t> split_u_, parent_, child_u_, child_v_, roots_;
  std::vector<uint32_t> first_split_;  // per base vertex: its first split, or kNoSplit
  std::vector<uint32_t> deps_begin_, deps_;
  std::vector<SplitBounds> bounds_;
  // Per split: its moved corners [moved_begin_[j], moved_begin_[j + 1]) and its first new face.
  std::vector<uint32_t> moved_begin_, new_face_begin_;
  std::vector<MovedCorner> moved_;
  // Per face (base and split faces, creation order): its corners as created, and per corner
  // its first move (kNoSplit: none).
  std::vector<uint32_t> created_corners_, created_uvs_, created_normals_, first_move_;
  // State.
  std::vector<uint8_t> applied_;
  std::vector<uint32_t> refcount_;  // applied splits that depend on each split
  std::size_t applied_count_ = 0;
  std::vector<uint32_t> active_faces_;  // split faces that are active (base faces always are)
  std::vector<uint32_t> active_slot_;   // per split face: its index in active_faces_
  std::vector<std::pair<uint32_t, uint32_t>> apply_stack_, collapse_stack_;  // scratch
  // The model's bounding sphere (holds every split's sphere), and its box (every split's box).
  Point3 model_center_{0, 0, 0};
  double model_radius_ = 0;
  Point3 box_lo_{0, 0, 0}, box_hi_{0, 0, 0};
  struct ViewStateDeleter {
    void operator()(ViewState* state) const;
  };
  std::unique_ptr<ViewState, ViewStateDeleter> view_;
};

}  // namespace pm
