// Selective refinement of a progressive mesh: the vertex hierarchy and the dependencies that
// let any set of splits closed under them be applied, in any order (Hoppe 1997, "View-
// dependent refinement of progressive meshes", §2 and §4).
//
// The mesh of a set S of applied splits. A vertex is active when it is a base vertex or its
// split is in S. Its faces are the base faces and the new faces (fl, fr) of the splits in S;
// each corner of a face is the deepest active vertex on the path, in the vertex hierarchy, from
// a base vertex to the vertex that corner has at full detail (Hoppe 1997, §4: the active vertex
// front; a corner's vertex is the active ancestor of its full-detail vertex). That is a
// function of S alone: the order in which splits were applied or collapsed does not matter.
//
// The rule (Hoppe 1997, §4.2: a vsplit is legal when vs is active and the faces fn0..fn3 are
// active; here as static dependencies): split m, on u, depends on its hierarchy parent (the
// previous split of u, or the split that created u) and on the splits that created fn0..fn3,
// the faces that held the edge (u, vl) or (u, vr) just before m in the full sequence (the
// faces that become fl's and fr's neighbours). A split may be collapsed when no applied split
// depends on it. Compared with requiring the whole one-ring m was recorded in (Xia and
// Varshney 1996, El-Sana and Varshney 1999), the faces around u may have other corners than
// they had then, and far less is forced.
//
// Why the mesh of every set S closed under the rule keeps the input's topology. We assume, as
// the encoder guarantees, that every mesh M_k of the full sequence is a manifold (with
// boundary) on which split k + 1 acts at a manifold vertex, undoing a collapse that met the
// link condition. "Degenerate" below means two equal corners (combinatorics; zero area by
// geometry is another matter, see the end). Induction on |S|; S empty is the base mesh.
// Otherwise let m be S's largest split: S' = S - {m} is closed too (dependencies point to
// earlier splits), and its mesh is a manifold with the input's topology whose faces are not
// degenerate. Let phi map each vertex of M_{m-1} to its deepest active ancestor for S'.
// Lemma: mesh(S') is phi(M_{m-1}) without the faces phi makes degenerate (an inactive face,
// made by an unapplied split k, has two corners that descend from k's u and v after k; none
// of those descendants is active, so phi maps both to the same vertex).
//  1. phi maps only u to u: m's parent chain is in S', so u and every earlier split of u are
//     applied, and every other vertex of M_{m-1} that descends from u descends from the v of
//     one of those splits, which is active. So u's faces in mesh(S') are the images of u's
//     fan in M_{m-1}: its link is the image of u's link cycle (or path) w_1..w_d with
//     consecutive repeats removed, and, mesh(S') being a manifold, without any repeat.
//  2. phi(vl) != phi(vr). Otherwise, that vertex appearing once in the reduced link, the whole
//     arc of the link between vl and vr on one side (at a boundary, the side without the gap)
//     maps to it, so every face of u's fan on that side is degenerate, among them the fn face
//     on that side of (u, vl): but it is active (its creator is a dependency of m), hence not
//     degenerate. (With only one of vl, vr there is nothing to show.)
//  3. mesh(S) is mesh(S') after splitting u along phi(vl) and phi(vr): the faces whose corner
//     at u descends from v (m's other side) take v, fl = (v, u, phi(vl)) and fr = (u, v,
//     phi(vr)) appear, and no other corner changes, since m's descendants are not in S. A
//     split of a manifold vertex along two distinct vertices of its link (or, at a boundary,
//     along one) with a new vertex v is the inverse of collapsing (u, v) under the link
//     condition (Dey, Edelsbrunner, Guha and Nekhayev 1999, "Topology preserving edge
//     contraction"): link(u) and link(v) meet exactly in phi(vl), phi(vr). So mesh(S) is a
//     manifold with the topology of mesh(S'), and no face of it is degenerate.
// Collapsing a split no applied split depends on leaves a closed set, so its mesh is valid too.
// Geometry is not covered: a face may join corners that never met in the full sequence, and
// where the input has exactly collinear vertices (a CAD grid) such a face can have zero area,
// as Hoppe 1997's meshes can fold over. DependencyRule::kExactRing (the last modifier of every
// face around u; Xia and Varshney 1996, §4; El-Sana and Varshney 1999, §3) makes every face
// one of some M_k, at the price of about 2.6 times as many splits for the same wanted set.
#include "pm/selective_refinement.h"
#include "core/no_throw.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "levels/level_output.h"
#include "view/view_criteria.h"

namespace pm {
namespace {

using detail::output_attribute;

using view::Vec;

constexpr double kPi = 3.14159265358979323846;

// Rounds up to the next float, so that a stored bound is never below the computed one.
float round_up(double x) {
  float f = static_cast<float>(x);
  if (double(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

// Relative slack added at each level of the hierarchy so that a parent's bound holds its
// children's despite rounding (the incremental update relies on want(child) => want(parent)).
constexpr double kNest = 1e-6;

Vec position(const ProgressiveMesh& pm, uint32_t v) { return view::vec(&pm.positions[3 * std::size_t{v}]); }


}  // namespace

SelectiveRefinement::SelectiveRefinement(std::shared_ptr<const ProgressiveMesh> pm,
                                         DependencyRule rule)
    : SelectiveRefinement(*pm, rule) {
  owned_ = std::move(pm);
}

SelectiveRefinement::SelectiveRefinement(const ProgressiveMesh& pm, DependencyRule rule)
    : pm_(&pm), rule_(rule) {
  const uint32_t n = static_cast<uint32_t>(pm.splits.size());
  base_vertex_count_ = pm.base_vertex_count;
  base_face_count_ = static_cast<uint32_t>(pm.base_face_count());
  const uint32_t vertices = base_vertex_count_ + n;  // loose vertices have no faces
  const bool uvs = pm.has_uvs(), normals = pm.has_normals();

  // Faces in creation order: base faces, then each split's fl and fr.
  new_face_begin_.resize(n + 1);
  uint32_t faces = base_face_count_;
  for (uint32_t j = 0; j < n; ++j) {
    new_face_begin_[j] = faces;
    faces += pm.splits[j].new_face_count();
  }
  new_face_begin_[n] = faces;
  created_corners_.assign(3 * std::size_t{faces}, 0);
  std::copy(pm.base_faces.begin(), pm.base_faces.end(), created_corners_.begin());
  if (uvs) created_uvs_.assign(pm.face_uvs.begin(), pm.face_uvs.begin() + 3 * std::size_t{faces});
  if (normals)
    created_normals_.assign(pm.face_normals.begin(), pm.face_normals.begin() + 3 * std::size_t{faces});

  split_u_.resize(n);
  parent_.assign(n, kNoSplit);
  child_u_.assign(n, kNoSplit);
  child_v_.assign(n, kNoSplit);
  first_split_.assign(base_vertex_count_, kNoSplit);
  deps_begin_.resize(n + 1);
  moved_begin_.resize(n + 1);
  moved_.reserve(pm.moved_faces.size());
  bounds_.resize(n);

  // Replay every split once on a face array with vertex-to-face incidence, recording what the
  // selective splits need (Hoppe 1997, §4.1: the vsplit records of the vertex hierarchy).
  std::vector<uint32_t> corners = created_corners_;
  std::vector<uint32_t> creator(faces, kNoSplit);  // the split that created each face
  first_move_.assign(3 * std::size_t{faces}, kNoSplit);
  std::vector<uint32_t> last_move(3 * std::size_t{faces}, kNoSplit);
  std::vector<uint32_t> last(faces, kNoSplit);
  std::vector<std::vector<uint32_t>> incident(vertices);
  for (uint32_t f = 0; f < base_face_count_; ++f)
    for (int c = 0; c < 3; ++c) incident[corners[3 * f + c]].push_back(f);
  std::vector<uint32_t> latest(vertices, kNoSplit);  // the split that last changed each vertex
  std::vector<uint32_t> moved_mark(faces, kNoSplit);
  std::vector<double> own_deviation(n);
  std::vector<Vec> normal_list;
  for (uint32_t j = 0; j < n; ++j) {
    const VertexSplit& s = pm.splits[j];
    const uint32_t u = s.u, v = base_vertex_count_ + j;
    split_u_[j] = u;
    // Hierarchy: the parent is the split that last changed u (it split u, or created it).
    const uint32_t p = latest[u];
    parent_[j] = p;
    if (p == kNoSplit) {
      first_split_[u] = j;
      roots_.push_back(j);
    } else if (u == base_vertex_count_ + p) {
      child_v_[p] = j;
    } else {
      child_u_[p] = j;
    }
    latest[u] = latest[v] = j;

    // Dependencies (Hoppe 1997, §4.2: vsplit is legal iff vs is active and fn0..fn3 are
    // active): the parent, and the creators of the faces that hold the edge (u, vl) or
    // (u, vr) now, just before the split (base faces have none). With kExactRing, the last
    // modifier of every face around u instead (Xia and Varshney 1996, §4; El-Sana and
    // Varshney 1999, §3), which is a superset, since a face's last modifier depends on its
    // creator through the modifiers in between.
    deps_begin_[j] = static_cast<uint32_t>(deps_.size());
    for (uint32_t f : incident[u]) {
      if (rule == DependencyRule::kExactRing) {
        if (last[f] != kNoSplit) deps_.push_back(last[f]);
        continue;
      }
      if (creator[f] == kNoSplit) continue;
      for (int c = 0; c < 3; ++c) {
        const uint32_t w = corners[3 * f + c];
        if ((w == s.vl && s.vl != kNoVertex) || (w == s.vr && s.vr != kNoVertex)) {
          deps_.push_back(creator[f]);
          break;
        }
      }
    }
    if (p != kNoSplit) deps_.push_back(p);
    std::sort(deps_.begin() + deps_begin_[j], deps_.end());
    deps_.erase(std::unique(deps_.begin() + deps_begin_[j], deps_.end()), deps_.end());

    // Bounds of the region before and after the split: the faces around u, then around u and v.
    const Vec cu = position(pm, u), cv = position(pm, v);
    double radius = length(cv - cu);
    normal_list.clear();
    auto add_face = [&](uint32_t a, uint32_t b, uint32_t c) {
      const Vec pa = position(pm, a), pb = position(pm, b), pc = position(pm, c);
      radius = std::max({radius, length(pa - cu), length(pb - cu), length(pc - cu)});
      const Vec normal = cross(pb - pa, pc - pa);
      const double area = length(normal);
      if (area > 0 && std::isfinite(area)) normal_list.push_back((1.0 / area) * normal);
    };
    for (uint32_t f : incident[u]) add_face(corners[3 * f], corners[3 * f + 1], corners[3 * f + 2]);

    // The moved faces: corner u becomes v. Each corner's moves are chained, in order, for
    // to_mesh(), which follows them while their splits are applied.
    moved_begin_[j] = static_cast<uint32_t>(moved_.size());
    for (uint32_t k = 0; k < s.moved_count; ++k) {
      const uint32_t entry = s.moved_begin + k;
      const uint32_t f = pm.moved_faces[entry];
      uint32_t c = 0;
      while (corners[3 * f + c] != u) ++c;  // validate(): u is there once
      const uint32_t index = static_cast<uint32_t>(moved_.size());
      moved_.push_back(MovedCorner{j, entry, kNoSplit});
      uint32_t& tail = last_move[3 * std::size_t{f} + c];
      (tail == kNoSplit ? first_move_[3 * std::size_t{f} + c] : moved_[tail].next) = index;
      tail = index;
      corners[3 * f + c] = v;
      moved_mark[f] = j;
      last[f] = j;
      incident[v].push_back(f);
      add_face(corners[3 * f], corners[3 * f + 1], corners[3 * f + 2]);
    }
    auto& ring = incident[u];
    ring.erase(std::remove_if(ring.begin(), ring.end(), [&](uint32_t f) { return moved_mark[f] == j; }),
               ring.end());
    // The new faces fl = (v, u, vl), fr = (u, v, vr).
    uint32_t f = new_face_begin_[j];
    auto add_new = [&](uint32_t a, uint32_t b, uint32_t c) {
      const uint32_t abc[3] = {a, b, c};
      for (int i = 0; i < 3; ++i) {
        corners[3 * f + i] = created_corners_[3 * f + i] = abc[i];
        incident[abc[i]].push_back(f);
      }
      creator[f] = last[f] = j;
      add_face(a, b, c);
      ++f;
    };
    if (s.vl != kNoVertex) add_new(v, u, s.vl);
    if (s.vr != kNoVertex) add_new(u, v, s.vr);

    // The normal cone: around the mean of the unit normals, wide enough for all of them.
    SplitBounds& b = bounds_[j];
    for (int i = 0; i < 3; ++i) b.center[i] = pm.positions[3 * std::size_t{u} + i];
    Vec axis{0, 0, 0};
    for (const Vec& normal : normal_list) axis = axis + normal;
    const double axis_length = length(axis);
    if (axis_length > 1e-12 && normal_list.size() > 0) {
      axis = (1.0 / axis_length) * axis;
    } else {
      axis = {0, 0, 1};
      normal_list.push_back({0, 0, -1});  // no usable direction: a cone of every direction
    }
    b.cone_axis[0] = float(axis.x), b.cone_axis[1] = float(axis.y), b.cone_axis[2] = float(axis.z);
    const Vec stored_axis = view::vec(b.cone_axis);
    double angle = 0;
    for (const Vec& normal : normal_list)
      angle = std::max(angle, std::acos(std::clamp(dot(stored_axis, normal) / length(stored_axis), -1.0, 1.0)));
    b.cone_angle = round_up(angle * (1 + kNest) + kNest);
    for (int i = 0; i < 3; ++i) {
      const float pu = pm.positions[3 * std::size_t{u} + i], pv = pm.positions[3 * std::size_t{v} + i];
      b.box_lo[i] = std::min(pu, pv);
      b.box_hi[i] = std::max(pu, pv);
    }
    b.radius = round_up(radius * (1 + kNest));
    own_deviation[j] = length(cv - cu);
  }
  deps_begin_[n] = static_cast<uint32_t>(deps_.size());
  moved_begin_[n] = static_cast<uint32_t>(moved_.size());

  // Bounds up the hierarchy, children (later splits) first: a parent's sphere holds its
  // children's spheres, its cone their cones, and its deviation is its own plus the larger of
  // theirs (Hoppe 1997, §3: bounds nested so that the tests are conservative).
  for (uint32_t j = n; j-- > 0;) {
    SplitBounds& b = bounds_[j];
    const Vec center = view::vec(b.center), axis = view::vec(b.cone_axis);
    const double axis_length = length(axis);
    double radius = b.radius, angle = b.cone_angle, deviation = 0;
    for (uint32_t c : {child_u_[j], child_v_[j]}) {
      if (c == kNoSplit) continue;
      const SplitBounds& cb = bounds_[c];
      radius = std::max(radius, (length(view::vec(cb.center) - center) + cb.radius) * (1 + kNest));
      const double between = std::acos(
          std::clamp(dot(axis, view::vec(cb.cone_axis)) / (axis_length * length(view::vec(cb.cone_axis))),
                     -1.0, 1.0));
      angle = std::max(angle, (between + cb.cone_angle) * (1 + kNest) + kNest);
      deviation = std::max(deviation, double(cb.deviation));
      for (int i = 0; i < 3; ++i) {
        b.box_lo[i] = std::min(b.box_lo[i], cb.box_lo[i]);
        b.box_hi[i] = std::max(b.box_hi[i], cb.box_hi[i]);
      }
    }
    b.radius = round_up(radius);
    b.cone_angle = round_up(std::min(angle, kPi));
    b.deviation = round_up((own_deviation[j] + deviation) * (1 + kNest));
  }

  // The model's bounding sphere: around the box of the vertices, holding every root's sphere.
  Vec lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (uint32_t v = 0; v < vertices; ++v) {
    const Vec p = position(pm, v);
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  const Vec center = vertices ? 0.5 * (lo + hi) : Vec{0, 0, 0};
  model_center_ = {center.x, center.y, center.z};
  for (uint32_t v = 0; v < vertices; ++v)
    model_radius_ = std::max(model_radius_, length(position(pm, v) - center));
  for (uint32_t j : roots_)
    model_radius_ =
        std::max(model_radius_, length(view::vec(bounds_[j].center) - center) + bounds_[j].radius);
  box_lo_ = {lo.x, lo.y, lo.z};
  box_hi_ = {hi.x, hi.y, hi.z};

  applied_.assign(n, 0);
  refcount_.assign(n, 0);
  active_slot_.assign(faces - base_face_count_, kNoSplit);
  reset();
}

std::vector<uint32_t> SelectiveRefinement::applied_splits() const {
  std::vector<uint32_t> out;
  out.reserve(applied_count_);
  for (uint32_t j = 0; j < applied_.size(); ++j)
    if (applied_[j]) out.push_back(j);
  return out;
}

bool SelectiveRefinement::vertex_active(uint32_t vertex) const {
  if (vertex < base_vertex_count_) return true;
  const std::size_t j = vertex - base_vertex_count_;
  return j < applied_.size() && applied_[j];
}

uint32_t SelectiveRefinement::pending_split(uint32_t vertex) const {
  if (!vertex_active(vertex)) return kNoSplit;
  uint32_t j = vertex < base_vertex_count_ ? first_split_[vertex]
                                           : child_v_[vertex - base_vertex_count_];
  while (j != kNoSplit && applied_[j]) j = child_u_[j];
  return j;
}

std::size_t SelectiveRefinement::face_count() const {
  return base_face_count_ + active_faces_.size() + pm_->carried_faces.size() / 3;
}

std::size_t SelectiveRefinement::vertex_count() const {
  std::size_t count = base_vertex_count_ + applied_count_ - pm_->welds.size();
  if (applied_count_ == applied_.size()) count += pm_->loose_vertex_count;
  return count;
}

void SelectiveRefinement::reset() {
  std::fill(applied_.begin(), applied_.end(), 0);
  std::fill(refcount_.begin(), refcount_.end(), 0);
  applied_count_ = 0;
  for (uint32_t f : active_faces_) active_slot_[f - base_face_count_] = kNoSplit;
  active_faces_.clear();
  view_.reset();
}

void SelectiveRefinement::activate_face(uint32_t face) {
  active_slot_[face - base_face_count_] = static_cast<uint32_t>(active_faces_.size());
  active_faces_.push_back(face);
}

void SelectiveRefinement::deactivate_face(uint32_t face) {
  const uint32_t slot = active_slot_[face - base_face_count_];
  const uint32_t last = active_faces_.back();
  active_faces_[slot] = last;
  active_slot_[last - base_face_count_] = slot;
  active_faces_.pop_back();
  active_slot_[face - base_face_count_] = kNoSplit;
}

// Hoppe 1997, §4.3 (vsplit): fl and fr appear. The corners that now take v (those whose
// full-detail vertex descends from v) are found by to_mesh(), which derives every corner from
// the applied set (see the top of this file), so a split costs O(1) and its dependencies.
void SelectiveRefinement::apply_one(uint32_t j) {
  for (uint32_t f = new_face_begin_[j]; f < new_face_begin_[j + 1]; ++f) activate_face(f);
  for (uint32_t k = deps_begin_[j]; k < deps_begin_[j + 1]; ++k) ++refcount_[deps_[k]];
  applied_[j] = 1;
  ++applied_count_;
}

// Hoppe 1997, §4.3 (ecol): the reverse.
void SelectiveRefinement::collapse_one(uint32_t j) {
  for (uint32_t f = new_face_begin_[j]; f < new_face_begin_[j + 1]; ++f) deactivate_face(f);
  for (uint32_t k = deps_begin_[j]; k < deps_begin_[j + 1]; ++k) --refcount_[deps_[k]];
  applied_[j] = 0;
  --applied_count_;
}

std::size_t SelectiveRefinement::apply(uint32_t split) {
  view_.reset();  // a change from outside: the next update_view() looks at everything again
  return apply_with_dependencies(split);
}

std::size_t SelectiveRefinement::apply_with_dependencies(uint32_t split) {
  if (applied_[split]) return 0;
  // Depth first through the unapplied dependencies (forced splits, Hoppe 1997 §4.3), each
  // applied once all of its own are.
  std::size_t count = 0;
  // Pairs (split, the next of its dependencies to look at), kept between calls.
  std::vector<std::pair<uint32_t, uint32_t>>& stack = apply_stack_;
  stack.assign(1, {split, deps_begin_[split]});
  while (!stack.empty()) {
    auto& [top, next] = stack.back();
    if (next < deps_begin_[top + 1]) {
      const uint32_t d = deps_[next++];
      if (!applied_[d]) stack.push_back({d, deps_begin_[d]});
      continue;
    }
    if (!applied_[top]) {  // a dependency reached twice is applied once
      apply_one(top);
      ++count;
    }
    stack.pop_back();
  }
  return count;
}

bool SelectiveRefinement::collapse(uint32_t split) {
  if (!applied_[split] || refcount_[split] != 0) return false;
  collapse_one(split);
  view_.reset();
  return true;
}

void SelectiveRefinement::set_applied(const std::vector<bool>& wanted) {
  reset();
  for (uint32_t j = 0; j < wanted.size() && j < applied_.size(); ++j)
    if (wanted[j]) apply_with_dependencies(j);
}

// From the base mesh, every split the predicate wants, looked at top-down through the
// hierarchy (a split is only looked at when its parent is wanted; the predicates are monotone,
// so this is every split they want), applied with its dependencies.
template <class Wanted>
void SelectiveRefinement::refine_top_down(const Wanted& wanted) {
  reset();
  std::vector<uint32_t> stack(roots_.rbegin(), roots_.rend()), chosen;
  while (!stack.empty()) {
    const uint32_t j = stack.back();
    stack.pop_back();
    if (!wanted(j)) continue;
    chosen.push_back(j);
    if (child_v_[j] != kNoSplit) stack.push_back(child_v_[j]);
    if (child_u_[j] != kNoSplit) stack.push_back(child_u_[j]);
  }
  std::sort(chosen.begin(), chosen.end());
  for (uint32_t j : chosen) apply_with_dependencies(j);
}

void SelectiveRefinement::refine_sphere(const Point3& center, double radius) {
  const Vec c = view::vec(center);
  refine_top_down([&](uint32_t j) {
    const SplitBounds& b = bounds_[j];
    return length(view::vec(b.center) - c) <= radius + b.radius;
  });
}

void SelectiveRefinement::refine_box(const Point3& lo, const Point3& hi) {
  refine_top_down([&](uint32_t j) {
    const SplitBounds& b = bounds_[j];
    double d2 = 0;
    for (int i = 0; i < 3; ++i) {
      const double x = b.center[i];
      const double outside = x < lo[i] ? lo[i] - x : x > hi[i] ? x - hi[i] : 0.0;
      d2 += outside * outside;
    }
    return std::sqrt(d2) <= b.radius;
  });
}

Status check_camera(const ViewCamera& camera) {
  for (const Point3* p : {&camera.eye, &camera.target, &camera.up})
    for (double x : *p)
      if (!std::isfinite(x)) return Status(ErrorCode::kInvalidArgument, "camera value is not finite");
  const Vec forward = view::vec(camera.target) - view::vec(camera.eye);
  if (!(length(forward) > 0))
    return Status(ErrorCode::kInvalidArgument, "camera eye and target are the same point");
  const Vec side = cross(forward, view::vec(camera.up));
  if (!(length(side) > 1e-12 * length(forward) * length(view::vec(camera.up))))
    return Status(ErrorCode::kInvalidArgument, "camera up is parallel to the view direction");
  if (!(camera.fov_degrees > 0 && camera.fov_degrees < 180))
    return Status(ErrorCode::kInvalidArgument, "field of view must be in (0, 180) degrees");
  if (!(camera.viewport_height >= 1 && std::isfinite(camera.viewport_height)))
    return Status(ErrorCode::kInvalidArgument, "viewport height must be at least 1 pixel");
  if (!(camera.viewport_width == 0 ||
        (camera.viewport_width >= 1 && std::isfinite(camera.viewport_width))))
    return Status(ErrorCode::kInvalidArgument, "viewport width must be at least 1 pixel");
  return Status::ok();
}

Status SelectiveRefinement::set_view(const ViewCamera& camera, const ViewOptions& options) {
  return detail::no_throw([&]() -> Status {
    if (Status s = check_camera(camera); !s) return s;
    if (!(options.pixel_error > 0 && std::isfinite(options.pixel_error)))
      return Status(ErrorCode::kInvalidArgument, "pixel error must be a positive number");
    const view::Frame frame = view::make_frame(camera, options);
    refine_top_down([&](uint32_t j) { return view::evaluate(bounds_[j], frame, false).want; });
    return Status::ok();
  });
}

Mesh SelectiveRefinement::to_mesh(std::vector<uint32_t>* face_levels) const {
  const ProgressiveMesh& pm = *pm_;
  const bool uvs = pm.has_uvs(), normals = pm.has_normals(), materials = pm.has_materials();
  // Faces in creation order: base faces, active split faces, then the carried faces.
  std::vector<uint32_t> order(base_face_count_);
  for (uint32_t f = 0; f < base_face_count_; ++f) order[f] = f;
  const std::size_t split_faces = active_faces_.size();
  order.insert(order.end(), active_faces_.begin(), active_faces_.end());
  std::sort(order.end() - split_faces, order.end());
  const std::size_t carried = pm.carried_faces.size() / 3;
  const std::size_t first_carried = pm.total_face_count() - carried;

  std::vector<uint32_t> faces, face_uvs, face_normals, face_materials;
  faces.reserve(3 * (order.size() + carried));
  if (face_levels) face_levels->clear();
  // Each corner: its vertex when its face was created, then its moves while their splits are
  // applied (they form a prefix: each move splits the vertex the previous one made); or, when
  // that first vertex is not active, its deepest active ancestor, with the attributes the
  // corner was created with (the corner never had that vertex in the full sequence).
  for (uint32_t f : order) {
    uint32_t level = f < base_face_count_
                         ? 0
                         : 1 + static_cast<uint32_t>(std::upper_bound(new_face_begin_.begin(),
                                                                      new_face_begin_.end(), f) -
                                                     new_face_begin_.begin() - 1);
    for (int c = 0; c < 3; ++c) {
      const std::size_t corner = 3 * std::size_t{f} + c;
      uint32_t vertex = created_corners_[corner];
      uint32_t uv = uvs ? created_uvs_[corner] : 0, normal = normals ? created_normals_[corner] : 0;
      if (!vertex_active(vertex)) {
        while (!vertex_active(vertex)) vertex = split_u_[vertex - base_vertex_count_];
      } else {
        for (uint32_t k = first_move_[corner]; k != kNoSplit && applied_[moved_[k].split];
             k = moved_[k].next) {
          const MovedCorner& m = moved_[k];
          vertex = base_vertex_count_ + m.split;
          if (uvs) uv = pm.moved_uvs[m.entry];
          if (normals) normal = pm.moved_normals[m.entry];
          level = std::max(level, m.split + 1);
        }
      }
      faces.push_back(vertex);
      if (uvs) face_uvs.push_back(uv);
      if (normals) face_normals.push_back(normal);
    }
    if (materials) face_materials.push_back(pm.face_materials[f]);
    if (face_levels) face_levels->push_back(level);
  }
  faces.insert(faces.end(), pm.carried_faces.begin(), pm.carried_faces.end());
  if (uvs)
    face_uvs.insert(face_uvs.end(), pm.face_uvs.begin() + 3 * first_carried, pm.face_uvs.end());
  if (normals)
    face_normals.insert(face_normals.end(), pm.face_normals.begin() + 3 * first_carried,
                        pm.face_normals.end());
  if (materials)
    face_materials.insert(face_materials.end(), pm.face_materials.begin() + first_carried,
                          pm.face_materials.end());
  if (face_levels) face_levels->insert(face_levels->end(), carried, 0);

  // Vertices: the active ones in id order, welded copies merged into their canonical vertex,
  // loose vertices at full detail only.
  const bool full = applied_count_ == applied_.size();
  const uint32_t total = static_cast<uint32_t>(pm.vertex_count());
  const uint32_t with_splits = base_vertex_count_ + static_cast<uint32_t>(applied_.size());
  std::vector<uint32_t> canonical(base_vertex_count_);
  for (uint32_t v = 0; v < base_vertex_count_; ++v) canonical[v] = v;
  for (const Weld& w : pm.welds) canonical[w.copy] = w.canonical;
  std::vector<uint32_t> output_id(total, kNoVertex);
  Mesh mesh;
  const std::size_t cc = pm.color_components;
  mesh.color_components = pm.color_components;
  mesh.positions.reserve(3 * vertex_count());
  mesh.colors.reserve(cc * vertex_count());
  for (uint32_t v = 0; v < total; ++v) {
    if (v < base_vertex_count_ && canonical[v] != v) continue;
    if (v >= base_vertex_count_ && v < with_splits && !applied_[v - base_vertex_count_]) continue;
    if (v >= with_splits && !full) continue;
    output_id[v] = static_cast<uint32_t>(mesh.positions.size() / 3);
    mesh.positions.insert(mesh.positions.end(), pm.positions.begin() + 3 * std::size_t{v},
                          pm.positions.begin() + 3 * std::size_t{v} + 3);
    mesh.colors.insert(mesh.colors.end(), pm.colors.begin() + cc * v, pm.colors.begin() + cc * (v + 1));
  }
  mesh.triangles.resize(faces.size());
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const uint32_t v = faces[i];
    mesh.triangles[i] = output_id[v < base_vertex_count_ ? canonical[v] : v];
  }
  if (uvs) output_attribute(face_uvs, pm.uvs, 2, full, mesh.uvs, mesh.uv_indices);
  if (normals) output_attribute(face_normals, pm.normals, 3, full, mesh.normals, mesh.normal_indices);
  mesh.face_materials = std::move(face_materials);
  mesh.material_names = pm.material_names;
  mesh.material_libraries = pm.material_libraries;
  return mesh;
}

std::size_t SelectiveRefinement::memory_bytes() const {
  auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  std::size_t total = sizeof(*this);
  for (const std::vector<uint32_t>* v :
       {&split_u_, &parent_, &child_u_, &child_v_, &roots_, &first_split_, &deps_begin_, &deps_,
        &moved_begin_, &new_face_begin_, &created_corners_, &created_uvs_, &created_normals_,
        &first_move_, &refcount_,
        &active_faces_, &active_slot_})
    total += bytes(*v);
  total += bytes(bounds_) + bytes(moved_) + bytes(applied_);
  return total + view_memory_bytes();
}

}  // namespace pm
