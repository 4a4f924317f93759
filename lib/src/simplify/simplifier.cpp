// The encoder: manifold repair, then Schroeder's decimation as a priority-ordered
// sequence of half-edge collapses (Schroeder, Zarge and Lorensen 1992; Schroeder 1997,
// "A topology modifying progressive decimation algorithm", with topology kept), recorded
// as the vertex splits of a progressive mesh (Hoppe 1996, "Progressive meshes", §3).
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <new>
#include <numeric>
#include <set>
#include <stdexcept>
#include <string>

#include "io/openmesh_logs.h"
#include "simplify/collapse_legality.h"
#include "simplify/collapse_sequence.h"
#include "simplify/corner_attributes.h"
#include "simplify/fast_simplifier.h"
#include "simplify/manifold_repair.h"
#include "pm/advanced/stream_order.h"
#include "pm/encoder.h"
#include "pm/pm_codec.h"
#include "simplify/quadric.h"
#include "simplify/removed_points.h"
#include "simplify/schroeder_error.h"
#include "simplify/seam_drift.h"
#include "simplify/vertex_classification.h"

namespace pm {
namespace {

using VertexHandle = HalfEdgeMesh::VertexHandle;
using HalfedgeHandle = HalfEdgeMesh::HalfedgeHandle;
using FaceHandle = HalfEdgeMesh::FaceHandle;

// The smallest error goes first. Corners compete like every other vertex: their error is
// the true distance to the surface that replaces them, and the tracked removed points
// charge what they carried. (An earlier version removed corners only after every other
// kind; once simple vertices ran out, that removed corners at any cost: 4.6% of the
// diagonal on rocker-arm at 10% of the faces, against 0.29% now.)
//
// Equal keys go oldest first, by a push counter. Flat regions, whose quadric errors are
// all zero, are made of ties, and how they are broken shows in the streams' sizes: of
// the orders tried (by vertex id, newest first, oldest first), oldest first kept the 2.0
// stream of samples/block_features.obj under 60% of its 1.1 stream. Every entry has its
// own key, so the order of the collapses does not depend on how the heap stores them
// (compact() rebuilds it freely).
constexpr uint32_t kVersionMask = 0x7fffffffu;

struct Candidate {
  float priority;  // a lower bound of the cost until measured
  float local;     // the local cost alone (quadric or Schroeder's)
  float distance;  // the error in model units, for the record
  uint32_t vertex;
  uint32_t halfedge;
  uint32_t version : 31;  // version_'s low 31 bits (kVersionMask)
  uint32_t measured : 1;  // the priority includes the removed points' distance
  uint32_t sequence = 0;  // when it was pushed (SchroederSimplifier::push)
  bool operator>(const Candidate& o) const {
    return priority != o.priority ? priority > o.priority : sequence > o.sequence;
  }
};

// The collapse h as CornerAttributes and SeamDrift read it (corner_attributes.h), in the
// half-edge mesh's ids: v's faces in vf_range order (the order of the moved faces), its
// edges in voh_range order.
class HalfEdgeStar {
 public:
  HalfEdgeStar(const HalfEdgeMesh& mesh, HalfedgeHandle h) {
    const VertexHandle v = mesh.from_vertex_handle(h), u = mesh.to_vertex_handle(h);
    const FaceHandle fl = mesh.face_handle(h), fr = mesh.opposite_face_handle(h);
    auto id = [](FaceHandle f) {
      return f.is_valid() ? static_cast<uint32_t>(f.idx()) : CollapseStar::kNoFace;
    };
    star_.v = static_cast<uint32_t>(v.idx());
    star_.u = static_cast<uint32_t>(u.idx());
    star_.fl = id(fl);
    star_.fr = id(fr);
    star_.vl = fl.is_valid() ? mesh.to_vertex_handle(mesh.next_halfedge_handle(h)).idx() : 0;
    star_.vr = fr.is_valid()
                   ? mesh.to_vertex_handle(mesh.next_halfedge_handle(mesh.opposite_halfedge_handle(h))).idx()
                   : 0;
    star_.pu = point_of(mesh, u);
    int n_faces = 0, n_edges = 0;
    for (auto f : mesh.vf_range(v)) {
      if (n_faces == kMost) return;  // complete() stays false
      faces_[n_faces++] = static_cast<uint32_t>(f.idx());
    }
    for (auto out : mesh.voh_range(v)) {
      if (n_edges == kMost) return;
      edges_[n_edges++] = {static_cast<uint32_t>(mesh.to_vertex_handle(out).idx()),
                           id(mesh.face_handle(out)), id(mesh.opposite_face_handle(out))};
    }
    star_.faces = faces_;
    star_.n_faces = n_faces;
    star_.edges = edges_;
    star_.n_edges = n_edges;
    complete_ = true;
  }
  // False for a vertex of more than kMost faces, which no attribute rule then allows
  // (the loop never evaluates one of more than 64).
  bool complete() const { return complete_; }
  const CollapseStar& operator*() const { return star_; }

 private:
  static constexpr int kMost = 256;
  uint32_t faces_[kMost];
  CollapseStar::Edge edges_[kMost];
  CollapseStar star_{};
  bool complete_ = false;
};

class SchroederSimplifier {
 public:
  // kSharpCornerDeg and kSharpCornerWeight: schroeder_error.h.
  // The removed points' worst squared distance counts as much as the quadric's mean
  // squared distance: on the benchmark meshes, 0.5 and 2 were each worse on some mesh.
  static constexpr double kWorstCaseWeight = 1.0;
  SchroederSimplifier(const Mesh& original, ManifoldMesh& input, const EncodeOptions& options)
      : mesh_(input.mesh),
        pinned_(input.pinned),
        welds_(weld_groups(input)),
        carried_edges_(carried_edges(input)),
        options_(options),
        cos_feature_angle_(std::cos(effective_feature_angle(options) * M_PI / 180.0)),
        cos_max_flip_(std::cos(options.max_normal_flip_deg * M_PI / 180.0)) {
    if (!options.drop_attributes) {
      std::vector<uint32_t> corners;
      corners.reserve(3 * input.mesh.n_faces());
      for (auto f : input.mesh.faces())
        for (auto w : input.mesh.fv_range(f)) corners.push_back(static_cast<uint32_t>(w.idx()));
      static_assert(sizeof(HalfEdgeMesh::Point) == 3 * sizeof(float));
      attributes_ = std::make_unique<CornerAttributes>(
          original, corners.data(), input.mesh.n_faces(),
          reinterpret_cast<const float*>(input.mesh.points()), input.mesh.n_vertices(),
          input.input_face.data(), input.input_vertex.data());
      if (!attributes_->any()) attributes_.reset();
    }
  }

  void run() {
    const std::size_t n_vertices = mesh_.n_vertices(), n_faces = mesh_.n_faces();
    faces_.normal.resize(n_faces);
    faces_.area.resize(n_faces);
    faces_.attributes = attributes_.get();
    for (auto f : mesh_.faces()) faces_.update(mesh_, f);
    if (options_.metric == Metric::kQuadric) initialize_quadrics();
    removed_ = std::make_unique<RemovedPoints>(mesh_);
    if (attributes_ && attributes_->has_uvs())
      seam_drift_ = std::make_unique<SeamDrift>(reinterpret_cast<const float*>(mesh_.points()),
                                                mesh_.n_vertices(), *attributes_);
    input_corner_.assign(n_vertices, 0);
    sharp_corner_.assign(n_vertices, 0);
    const double cos_sharp = std::cos(kSharpCornerDeg * M_PI / 180.0);
    for (auto v : mesh_.vertices()) {
      if (classify_vertex(mesh_, faces_, v, cos_feature_angle_, pinned_[v.idx()]).kind !=
          VertexKind::kCorner)
        continue;
      input_corner_[v.idx()] = 1;
      for (auto h : mesh_.voh_range(v))
        if (is_feature_edge(mesh_, faces_, mesh_.edge_handle(h), cos_sharp))
          sharp_corner_[v.idx()] = 1;
    }
    version_.assign(n_vertices, 0);
    keyed_by_measure_.assign(n_vertices, 0);
    faces_alive_ = n_faces;
    vertices_alive_ = n_vertices;

    // Collapses change the neighbourhood of the vertices around them only; legality
    // further out is re-checked when a candidate is popped. A final sweep re-evaluates
    // every vertex, so the loop ends only when no legal collapse remains.
    //
    // The heap's array holds at most a quarter more entries than there are vertices:
    // when full, its stale entries (older versions) are dropped (compact()) instead of
    // letting it double. That changes no pop: the keys order every entry, ties included.
    queue_.reserve(n_vertices + n_vertices / 4 + 64);
    collapses.reserve(n_vertices);  // at most one per vertex: no doubling on the way
    moved_faces.reserve(4 * n_vertices);  // about 3.4 per collapse (fast_simplifier.cpp)
    for (;;) {
      for (auto v : mesh_.vertices()) evaluate(v);
      const std::size_t before = collapses.size();
      while (!queue_.empty() && !stopped_) {
        std::pop_heap(queue_.begin(), queue_.end(), std::greater<Candidate>());
        const Candidate top = queue_.back();
        queue_.pop_back();
        if (top.version != (version_[top.vertex] & kVersionMask)) continue;
        if (removed_ && !top.measured && remeasure(top)) continue;
        apply(top);
      }
      if (stopped_ || collapses.size() == before) break;
    }
    // Only the loop needed these: free them before assemble() builds the output, which is
    // where the encoder's memory peaked (issue 9).
    std::vector<Candidate>().swap(queue_);
    std::vector<Quadric>().swap(quadrics_);
    removed_.reset();
    seam_drift_.reset();
    faces_ = FaceGeometry{};
    std::vector<uint32_t>().swap(version_);
    std::vector<uint8_t>().swap(keyed_by_measure_);
    std::vector<uint8_t>().swap(input_corner_);
    std::vector<uint8_t>().swap(sharp_corner_);
  }

  std::vector<Collapse> collapses;
  std::vector<uint32_t> moved_faces;  // half-edge-mesh face ids
  CollapseAttributes attribute_record;  // corner ids the splits restore
  const CornerAttributes* attributes() const { return attributes_.get(); }

 private:
  bool legal(HalfedgeHandle h) {
    return collapse_keeps_topology(mesh_, h) && collapse_keeps_welds(mesh_, h, welds_) &&
           collapse_keeps_geometry(mesh_, h, cos_max_flip_) &&
           (!attributes_ || keeps_attributes(h)) &&
           keeps_carried_edges_apart(h);
  }

  bool keeps_attributes(HalfedgeHandle h) const {
    const HalfEdgeStar star(mesh_, h);
    return star.complete() && attributes_->collapse_keeps_attributes(*star);
  }

  // A carried face (a, a, b) joins a and b by an edge of no surface; were a collapse to make
  // a-b an edge of the surface too, the two would merge and the output lose an edge.
  bool keeps_carried_edges_apart(HalfedgeHandle h) const {
    if (carried_edges_.empty()) return true;
    const VertexHandle v = mesh_.from_vertex_handle(h), u = mesh_.to_vertex_handle(h);
    for (auto w : mesh_.vv_range(v)) {
      if (w == u) continue;
      const uint32_t a = static_cast<uint32_t>(u.idx()), b = static_cast<uint32_t>(w.idx());
      if (carried_edges_.count({std::min(a, b), std::max(a, b)}) &&
          !mesh_.find_halfedge(u, w).is_valid())
        return false;
    }
    return true;
  }

  static constexpr int kMaxValence = 64;  // a vertex of larger valence is never cheap: it stays

  // Finds how v would be removed now and queues it; a stale entry is dropped by version.
  void evaluate(VertexHandle v) {
    ++version_[v.idx()];
    keyed_by_measure_[v.idx()] = 0;
    if (mesh_.status(v).deleted()) return;
    // One walk around v finds each edge's kind once, for v's classification
    // (classify_vertex's rules, the same answers) and for its options.
    struct Option {
      bool special;
      double length;
      HalfedgeHandle h;
    };
    Option options[kMaxValence];
    int count = 0;
    VertexClass vertex_class;  // complex until classified
    if (!pinned_[v.idx()]) {
      int boundary_edges = 0, feature_edges = 0;
      bool manifold = true;  // OpenMesh's is_manifold: no boundary half-edge out but the first
      for (auto h : mesh_.voh_range(v)) {
        if (count == kMaxValence) return;
        if (count > 0 && mesh_.is_boundary(h)) manifold = false;
        const auto e = mesh_.edge_handle(h);
        const bool boundary = mesh_.is_boundary(e);
        const bool feature = !boundary && is_feature_edge(mesh_, faces_, e, cos_feature_angle_);
        if (boundary || feature) {
          const int special = boundary_edges + feature_edges;
          if (special < 2) vertex_class.line_ends[special] = mesh_.to_vertex_handle(h);
          boundary_edges += boundary;
          feature_edges += feature;
        }
        options[count++] = {boundary || feature, 0.0, h};
      }
      if (count > 0 && manifold)  // count == 0: isolated
        vertex_class.kind = kind_from_edges(boundary_edges, feature_edges);
    }
    // A corner of the input stays one: collapses around it can wear its feature edges
    // down to fewer than three, but the shape's extremity it marks is still there.
    if (input_corner_[v.idx()] && vertex_class.kind != VertexKind::kComplex)
      vertex_class.kind = VertexKind::kCorner;
    CollapseEdges edges = kCollapseEdges[static_cast<int>(vertex_class.kind)];
    if (vertex_class.kind == VertexKind::kCorner && options_.keep_corners)
      edges = CollapseEdges::kNone;
    if (edges == CollapseEdges::kNone) return;
    if (edges == CollapseEdges::kSpecialOnly)
      count = static_cast<int>(std::remove_if(options, options + count,
                                              [](const Option& o) { return !o.special; }) -
                               options);
    for (int i = 0; i < count; ++i) options[i].length = mesh_.calc_edge_sqr_length(options[i].h);
    // Shortest legal edge first (Schroeder 1997, §3.2); corners try their special edges
    // first and take the one of least true error.
    std::sort(options, options + count, [](const Option& a, const Option& b) {
      return a.special != b.special ? a.special : a.length < b.length;
    });
    HalfedgeHandle chosen;
    double error = 0;
    if (options_.metric == Metric::kQuadric) {
      // Garland and Heckbert 1997, §4: the cheapest pair; here among v's legal half-edge
      // collapses, with u staying where it is (subset placement, §4 "optimal placement" is
      // not possible for a progressive mesh that keeps input positions).
      //
      // The options of options[0]'s kind (special or not) come first, the cheapest legal
      // one wins; only if none is legal, the first legal one of the other kind. Legality is
      // the dearer test, so it is asked in order of cost, until one passes: the choice is
      // the same as testing every option.
      const Quadric& qv = quadrics_[v.idx()];
      struct Costed {
        double cost, geometric;
        int option;
      };
      auto costed = [&](int i) {
        const VertexHandle u = mesh_.to_vertex_handle(options[i].h);
        // v's planes at u, as a mean over their area (cost_of_moving), plus the
        // attributes' error in the same units (Hoppe 1999, §4).
        const double geometric = cost_of_moving(qv, point_of(mesh_, u));
        return Costed{geometric + attribute_cost(options[i].h), geometric, i};
      };
      Costed first_kind[64];
      int n_first = 0, i = 0;
      for (; i < count && options[i].special == options[0].special; ++i) {
        const Costed c = costed(i);
        if (c.cost < HUGE_VAL) first_kind[n_first++] = c;  // not NaN nor infinite
      }
      std::sort(first_kind, first_kind + n_first, [](const Costed& a, const Costed& b) {
        return a.cost != b.cost ? a.cost < b.cost : a.option < b.option;
      });
      const Costed* best = nullptr;
      for (int k = 0; k < n_first && !best; ++k)
        if (legal(options[first_kind[k].option].h)) best = &first_kind[k];
      Costed other;
      for (; i < count && !best; ++i) {
        if (!legal(options[i].h)) continue;
        other = costed(i);
        if (other.cost < HUGE_VAL) best = &other;
      }
      if (!best) return;
      chosen = options[best->option].h;
      push({static_cast<float>(best->cost), static_cast<float>(best->cost),
                   static_cast<float>(std::sqrt(best->geometric)), static_cast<uint32_t>(v.idx()),
                   static_cast<uint32_t>(chosen.idx()), version_[v.idx()] & kVersionMask, 0});
      return;
    }
    if (vertex_class.kind == VertexKind::kCorner) {
      double best = HUGE_VAL;
      for (int i = 0; i < count; ++i) {
        if (chosen.is_valid() && options[i].special != options[0].special) break;
        if (!legal(options[i].h)) continue;
        const double e = collapse_distance(mesh_, options[i].h);
        const double priority = std::max(e, std::sqrt(attribute_cost(options[i].h)));
        if (priority < best) best = priority, chosen = options[i].h, error = e;
      }
    } else {
      for (int i = 0; i < count && !chosen.is_valid(); ++i)
        if (legal(options[i].h)) chosen = options[i].h;
      if (chosen.is_valid()) error = vertex_removal_error(mesh_, faces_, vertex_class, chosen);
    }
    if (!chosen.is_valid()) return;
    // Schroeder's error is a distance; the attributes' error, in model units, joins it as
    // the larger of the two.
    const double local = std::max(error, std::sqrt(attribute_cost(chosen)));
    const float priority =
        static_cast<float>(sharp_corner_[v.idx()] ? kSharpCornerWeight * local : local);
    push({priority, priority, static_cast<float>(error), static_cast<uint32_t>(v.idx()),
                 static_cast<uint32_t>(chosen.idx()), version_[v.idx()] & kVersionMask, 0});
  }

  // The priority of a candidate whose local cost is `local` and whose removed points and
  // fan lie up to `worst` from the input or the surface they move to (remeasure()).
  float combined(float local, double worst) const {
    return static_cast<float>(options_.metric == Metric::kQuadric
                                  ? local + kWorstCaseWeight * worst * worst
                                  : std::max<double>(local, worst));
  }

  double attribute_cost(HalfedgeHandle h) const {
    return attributes_ ? attributes_->collapse_cost(*HalfEdgeStar(mesh_, h)) : 0.0;
  }

  // The mean squared distance of q's planes to p. Area-weighted quadrics summed over
  // collapses grow with the area they stand for; dividing by that area makes the cost a
  // distance, comparable between a fresh vertex and one that has absorbed many (the
  // normalization meshoptimizer uses too).
  static double cost_of_moving(const Quadric& q, const Vec3& p) {
    return q.weight > 0 ? q.error(p) / q.weight : 0;
  }

  // A candidate's cost is local: the quadric's is a mean, Schroeder's the distance of v
  // alone to a plane or line. Either can hide input vertices, removed earlier, that this
  // collapse would leave far from the surface. Before applying it, charge the removed
  // points' worst distance (RemovedPoints); if that makes it dearer than the next
  // candidate, queue it again. Costs only grow, so the greedy order stays exact (lazy
  // evaluation).
  //
  // For Schroeder's metric this takes the place of his error accumulation (Schroeder 1997,
  // §3.3: a removed vertex's error is added to its neighbours', an estimate of how far
  // the surface has drifted from the input): the drift is measured instead. The
  // priority is the larger of the local error and the measured one; on the benchmark
  // meshes that beats both summing them and carrying the maximum as an accumulation.
  //
  // A texture seam that slides within the surface is charged too (SeamDrift), scaled by
  // SeamDrift::kDriftScale: the surface distance cannot see it, and the texture shows it at once.
  bool remeasure(const Candidate& top) {
    const HalfedgeHandle h = mesh_.halfedge_handle(top.halfedge);
    if (mesh_.status(h).deleted()) return false;  // apply() re-evaluates it
    // First the removed points alone (no input region to gather): their worst distance is
    // a lower bound of the whole measure, and so is the seam's drift. When that bound
    // already puts the candidate behind the next one, it goes back with the bound as its
    // key, which keeps the greedy order exact (a key never exceeds the cost) and skips the
    // dearer half of the measure, often for good: most candidates sent back are
    // re-evaluated before they come up again.
    const double drift =
        seam_drift_ ? SeamDrift::kDriftScale * seam_drift_->collapse_drift(*HalfEdgeStar(mesh_, h)) : 0.0;
    const double lower = removed_->removed_distance(h);
    const double bound = std::max(lower, drift);
    if (bound > 0) {
      Candidate bounded = top;
      bounded.priority = combined(top.local, bound);
      if (!queue_.empty() && bounded > least()) {
        keyed_by_measure_[top.vertex] = 1;
        push(bounded);
        return true;
      }
    }
    const double worst = lower < 0 ? 0 : removed_->collapse_distance_from(h, lower);
    Candidate measured = top;
    measured.measured = 1;
    measured.priority = combined(top.local, std::max(worst, drift));
    // The record's error stays a distance to the surface (pmdec --error): no drift in it.
    measured.distance = static_cast<float>(std::max<double>(top.distance, worst));
    if (queue_.empty() || !(measured > least())) {
      apply(measured);
      return true;
    }
    keyed_by_measure_[top.vertex] = 1;
    push(measured);
    return true;
  }

  void apply(const Candidate& candidate) {
    const HalfedgeHandle h = mesh_.halfedge_handle(candidate.halfedge);
    const VertexHandle v = mesh_.from_vertex_handle(h), u = mesh_.to_vertex_handle(h);
    // Something two rings away may have made the collapse illegal since it was queued.
    if (mesh_.status(h).deleted() || !legal(h)) {
      evaluate(v);
      return;
    }
    const FaceHandle fl = mesh_.face_handle(h), fr = mesh_.opposite_face_handle(h);
    const std::size_t removed_faces = fl.is_valid() + fr.is_valid();
    if (faces_alive_ < options_.min_faces + removed_faces ||
        vertices_alive_ <= std::max<std::size_t>(options_.min_vertices, 1)) {
      stopped_ = true;
      return;
    }

    Collapse c;
    c.v = v.idx();
    c.u = u.idx();
    c.fl = fl.idx();
    c.fr = fr.idx();
    c.vl = fl.is_valid() ? mesh_.to_vertex_handle(mesh_.next_halfedge_handle(h)).idx() : kNoVertex;
    c.vr =
        fr.is_valid()
            ? mesh_.to_vertex_handle(mesh_.next_halfedge_handle(mesh_.opposite_halfedge_handle(h)))
                  .idx()
            : kNoVertex;
    c.moved_begin = static_cast<uint32_t>(moved_faces.size());
    for (auto f : mesh_.vf_range(v))
      if (f != fl && f != fr) moved_faces.push_back(f.idx());
    c.moved_count = static_cast<uint32_t>(moved_faces.size()) - c.moved_begin;
    c.new_faces_begin = new_faces_recorded_;
    new_faces_recorded_ += static_cast<uint32_t>(removed_faces);
    if (attributes_) {
      // The drift first: it finds the seams on the corners as they are before the collapse.
      const HalfEdgeStar star(mesh_, h);
      attributes_->collapse(*star, attribute_record);
      // After the corners moved, as this loop always did (its levels stay as measured in
      // tests/bench): the drift then misreads the seams at v's moved corners and attaches
      // fewer points. The fast loop attaches them first (fast_loop.h, apply()).
      if (seam_drift_) seam_drift_->collapse(*star);
    }
    // The record's error: the largest so far of the candidates' errors and of the removed
    // points' distances to their faces, so non-increasing from base to full detail, and
    // at least the distance of every input vertex to the level's surface.
    bound_ = std::max(bound_, double(candidate.distance));
    bound_ = std::max(bound_, removed_->collapse(h));  // before mesh_ changes
    // Rounded up to a float: rounded to nearest, it fell a rounding below the distance it
    // bounds (homer at 2% of the faces, tests/bench/bound.md).
    c.bound = static_cast<float>(std::min<double>(bound_, std::numeric_limits<float>::max()));
    if (double(c.bound) < bound_) c.bound = std::nextafter(c.bound, HUGE_VALF);
    collapses.push_back(c);

    VertexHandle ring[kMaxValence];  // v's neighbours (evaluate() refuses larger valences)
    int ring_count = 0;
    for (auto w : mesh_.vv_range(v))
      if (ring_count < kMaxValence) ring[ring_count++] = w;
    mesh_.collapse(h);
    faces_alive_ -= removed_faces;
    --vertices_alive_;
    for (uint32_t i = c.moved_begin; i < moved_faces.size(); ++i)
      faces_.update(mesh_, mesh_.face_handle(moved_faces[i]));
    if (options_.metric == Metric::kQuadric)
      quadrics_[u.idx()] += quadrics_[v.idx()];  // Garland and Heckbert 1997, §4: Q = Q1 + Q2
    ++version_[v.idx()];

    // Re-evaluated: u and v's other neighbours, whose one-rings changed. u's other
    // neighbours keep their faces, so their classification, their options' costs and the
    // geometry of their own faces are as they were, and their links can only have grown
    // (u, next to them, is next to more vertices now), so their queued collapse is still
    // their best unless it became illegal, which apply() finds when it is popped. Unless
    // its key holds a measure: points may have moved onto their faces that touch u.
    evaluate(u);
    for (auto w : mesh_.vv_range(u))
      if (keyed_by_measure_[w.idx()] || std::find(ring, ring + ring_count, w) != ring + ring_count)
        evaluate(w);
    report_progress();
  }

  // Per-vertex quadrics of the input: the planes of its faces, weighted by area
  // (Garland and Heckbert 1997, §6.1), plus, along each boundary and feature edge, a plane
  // through the edge perpendicular to its face, which holds the edge in place (§6.2,
  // "preserving boundaries"; Garland and Heckbert 1998 §4 use the same for discontinuities).
  void initialize_quadrics() {
    // Constraint planes weigh like a face a few times the edge's square: strong enough to
    // keep borders and creases, not so strong that they alone decide.
    constexpr double kConstraintWeight = 4.0;
    quadrics_.assign(mesh_.n_vertices(), Quadric{});
    for (auto f : mesh_.faces()) {
      const double area = faces_.area[f.idx()];
      if (area == 0) continue;
      const Vec3& n = faces_.normal[f.idx()];
      const auto any_vertex = *mesh_.cfv_iter(f);
      const Quadric plane = Quadric::from_plane(n, point_of(mesh_, any_vertex), area);
      for (auto w : mesh_.fv_range(f)) quadrics_[w.idx()] += plane;
    }
    for (auto e : mesh_.edges()) {
      if (!is_special_edge(mesh_, faces_, e, cos_feature_angle_)) continue;
      for (int side = 0; side < 2; ++side) {
        const auto h = mesh_.halfedge_handle(e, side);
        const auto f = mesh_.face_handle(h);
        if (!f.is_valid()) continue;
        const Vec3 a = point_of(mesh_, mesh_.from_vertex_handle(h));
        const Vec3 b = point_of(mesh_, mesh_.to_vertex_handle(h));
        Vec3 n = (b - a) % faces_.normal[f.idx()];
        const double length = n.norm();
        if (length == 0) continue;
        n /= length;
        const Quadric plane = Quadric::from_plane(n, a, kConstraintWeight * (b - a).sqrnorm());
        quadrics_[mesh_.from_vertex_handle(h).idx()] += plane;
        quadrics_[mesh_.to_vertex_handle(h).idx()] += plane;
      }
    }
  }

  void report_progress() {
    if (!options_.progress || collapses.size() % 4096 != 0) return;
    options_.progress(std::min(1.0, double(collapses.size()) / double(mesh_.n_vertices())));
  }

  HalfEdgeMesh& mesh_;
  const std::vector<uint8_t>& pinned_;
  const WeldGroups welds_;
  const std::set<std::pair<uint32_t, uint32_t>> carried_edges_;  // vertex pairs of carried faces
  const EncodeOptions& options_;
  const double cos_feature_angle_, cos_max_flip_;
  FaceGeometry faces_;
  std::vector<Quadric> quadrics_;    // quadric metric: per vertex
  std::unique_ptr<RemovedPoints> removed_;
  std::unique_ptr<SeamDrift> seam_drift_;  // texture seams only
  std::unique_ptr<CornerAttributes> attributes_;  // null: geometry only
  uint32_t new_faces_recorded_ = 0;
  std::vector<uint32_t> version_;
  std::vector<uint8_t> keyed_by_measure_;  // per vertex: its queued key includes a measure
  std::vector<uint8_t> input_corner_;  // classified a corner on the input
  std::vector<uint8_t> sharp_corner_;  // ... with a feature edge sharper than kSharpCornerDeg
  // A binary heap, least key on top (std::push_heap and std::pop_heap with greater).
  std::vector<Candidate> queue_;
  uint32_t pushes_ = 0;
  const Candidate& least() const { return queue_.front(); }
  void push(const Candidate& c) {
    if (queue_.size() == queue_.capacity()) compact();
    queue_.push_back(c);
    queue_.back().sequence = ++pushes_;  // wraps after 2^32 pushes: ties only, still deterministic
    std::push_heap(queue_.begin(), queue_.end(), std::greater<Candidate>());
  }
  // Drops the entries of older versions: at most one entry per vertex is current.
  void compact() {
    queue_.erase(std::remove_if(queue_.begin(), queue_.end(),
                                [&](const Candidate& c) { return c.version != (version_[c.vertex] & kVersionMask); }),
                 queue_.end());
    std::make_heap(queue_.begin(), queue_.end(), std::greater<Candidate>());
  }
  std::size_t faces_alive_ = 0, vertices_alive_ = 0;
  double bound_ = 0;
  bool stopped_ = false;
};

// Numbers vertices and faces as the decoder will create them (base first, then one
// vertex and one or two faces per split, coarse to fine) and turns the collapses,
// last first, into vertex splits.
// Carried faces' corners straight from the input.
void copy_corners(const std::vector<uint32_t>& ids, uint32_t face, std::vector<uint32_t>& to) {
  to.insert(to.end(), ids.begin() + 3 * std::size_t{face}, ids.begin() + 3 * std::size_t{face} + 3);
}

// pmenc --keep-order: out.input_faces holds each input triangle's face id; make it
// 3 * face id + r, r the rotation that gives the input's first corner first. The faces'
// corners at full detail come from replaying the splits (Hoppe 1996, §3).
void record_face_rotations(const Mesh& input, ProgressiveMesh& out) {
  std::vector<uint32_t> corners = out.base_faces;
  for (std::size_t i = 0; i < out.splits.size(); ++i) {
    const VertexSplit& s = out.splits[i];
    const uint32_t v = out.base_vertex_count + static_cast<uint32_t>(i);
    for (uint32_t k = s.moved_begin; k < s.moved_begin + s.moved_count; ++k)
      for (int c = 0; c < 3; ++c)
        if (corners[3 * std::size_t{out.moved_faces[k]} + c] == s.u) corners[3 * std::size_t{out.moved_faces[k]} + c] = v;
    if (s.vl != kNoVertex) corners.insert(corners.end(), {v, s.u, s.vl});
    if (s.vr != kNoVertex) corners.insert(corners.end(), {s.u, v, s.vr});
  }
  corners.insert(corners.end(), out.carried_faces.begin(), out.carried_faces.end());
  // Each vertex id's input vertex: a welded copy stands for its canonical vertex's.
  std::vector<uint32_t> input_of(out.vertex_count(), kNoVertex);
  for (std::size_t i = 0; i < out.input_vertices.size(); ++i)
    input_of[out.input_vertices[i]] = static_cast<uint32_t>(i);
  for (const Weld& w : out.welds) input_of[w.copy] = input_of[w.canonical];
  for (std::size_t t = 0; t < out.input_faces.size(); ++t) {
    const uint32_t f = out.input_faces[t];
    const uint32_t* want = &input.triangles[3 * t];
    const uint32_t* have = &corners[3 * std::size_t{f}];
    uint32_t rotation = 0;
    for (uint32_t r = 0; r < 3; ++r) {
      if (input_of[have[r]] == want[0] && input_of[have[(r + 1) % 3]] == want[1] &&
          input_of[have[(r + 2) % 3]] == want[2]) {
        rotation = r;
        break;
      }
    }
    out.input_faces[t] = 3 * f + rotation;
  }
}

// What a simplifier left: its collapses, the base mesh, and the half-edge mesh's points
// and counts (the mesh itself may be gone: simplify_fast clears it).
struct Simplified {
  const std::vector<Collapse>& collapses;
  const std::vector<uint32_t>& moved_faces;
  const CollapseAttributes& attribute_record;
  const CornerAttributes* attributes;  // null: geometry only
  const BaseMesh& base;
  const float* points;  // three per half-edge-mesh vertex
  std::size_t n_vertices, n_faces;
};

void assemble(const Mesh& input, const ManifoldMesh& repaired, const Simplified& run,
              bool keep_attributes, bool keep_order, ProgressiveMesh& out) {
  const std::size_t n_vertices = run.n_vertices, n_faces = run.n_faces;
  std::vector<uint32_t> vertex_id(n_vertices, kNoVertex);
  std::vector<uint32_t> face_id(n_faces, kNoVertex);
  out = ProgressiveMesh{};
  out.positions.reserve(3 * (n_vertices + repaired.loose_vertices.size()));
  std::vector<uint32_t> vertex_order;  // half-edge-mesh vertex of each vertex id
  vertex_order.reserve(n_vertices);
  auto add_position = [&](uint32_t v) {
    const float* p = run.points + 3 * std::size_t{v};
    out.positions.insert(out.positions.end(), {p[0], p[1], p[2]});
    vertex_order.push_back(v);
  };

  uint32_t next_vertex = 0, next_face = 0;
  for (uint32_t v : run.base.vertices) {
    vertex_id[v] = next_vertex++;
    add_position(v);
  }
  out.base_vertex_count = next_vertex;
  // Attributes: what each face has when it appears (Hoppe 1996, §3), base faces first.
  const CornerAttributes* attributes = run.attributes;
  const bool uvs = attributes && attributes->has_uvs();
  const bool normals = attributes && attributes->has_normals();
  const bool materials = attributes && attributes->has_materials();
  for (std::size_t i = 0; i < run.base.faces.size(); ++i) {
    const uint32_t f = run.base.faces[i];
    face_id[f] = next_face++;
    uint32_t at[3];
    for (int k = 0; k < 3; ++k) {
      const uint32_t w = run.base.corners[3 * i + k];
      out.base_faces.push_back(vertex_id[w]);
      at[k] = w;
    }
    if (!attributes) continue;
    uint32_t uv[3], normal[3];
    attributes->corner_ids(f, at, uv, normal);
    if (uvs) out.face_uvs.insert(out.face_uvs.end(), uv, uv + 3);
    if (normals) out.face_normals.insert(out.face_normals.end(), normal, normal + 3);
    if (materials) out.face_materials.push_back(attributes->material(f));
  }
  const CollapseAttributes& record = run.attribute_record;

  const auto& collapses = run.collapses;
  out.splits.reserve(collapses.size());
  out.moved_faces.reserve(run.moved_faces.size());
  // The collapses ahead name the vertices and faces they will look up, scattered over
  // the mesh: fetched that far ahead, the cache misses of several records overlap.
  constexpr std::size_t kFetchAhead = 16;
  for (std::size_t k = collapses.size(); k-- > 0;) {
    if (k >= kFetchAhead) {
      const Collapse& ahead = collapses[k - kFetchAhead];
      for (uint32_t vertex : {ahead.v, ahead.u, ahead.vl, ahead.vr}) {
        if (vertex != kNoVertex) __builtin_prefetch(vertex_id.data() + vertex);
      }
      for (uint32_t i = 0; i < ahead.moved_count; ++i)
        __builtin_prefetch(face_id.data() + run.moved_faces[ahead.moved_begin + i]);
      for (const int face : {ahead.fl, ahead.fr}) {
        if (face >= 0) __builtin_prefetch(face_id.data() + face, 1);
      }
      __builtin_prefetch(run.points + 3 * std::size_t{ahead.v});
    }
    const Collapse* c = &collapses[k];
    vertex_id[c->v] = next_vertex++;
    add_position(c->v);
    VertexSplit split;
    split.u = vertex_id[c->u];
    split.vl = c->vl == kNoVertex ? kNoVertex : vertex_id[c->vl];
    split.vr = c->vr == kNoVertex ? kNoVertex : vertex_id[c->vr];
    split.error = c->bound;
    split.moved_begin = static_cast<uint32_t>(out.moved_faces.size());
    split.moved_count = c->moved_count;
    for (uint32_t i = 0; i < c->moved_count; ++i)
      out.moved_faces.push_back(face_id[run.moved_faces[c->moved_begin + i]]);
    if (c->fl >= 0) face_id[c->fl] = next_face++;
    if (c->fr >= 0) face_id[c->fr] = next_face++;
    out.splits.push_back(split);
    const uint32_t added = (c->fl >= 0) + (c->fr >= 0);
    auto copy = [](const std::vector<uint32_t>& from, std::size_t begin, std::size_t count,
                   std::vector<uint32_t>& to) {
      to.insert(to.end(), from.begin() + begin, from.begin() + begin + count);
    };
    if (uvs) {
      copy(record.moved_uvs, c->moved_begin, c->moved_count, out.moved_uvs);
      copy(record.new_face_uvs, 3 * std::size_t{c->new_faces_begin}, 3 * added, out.face_uvs);
    }
    if (normals) {
      copy(record.moved_normals, c->moved_begin, c->moved_count, out.moved_normals);
      copy(record.new_face_normals, 3 * std::size_t{c->new_faces_begin}, 3 * added,
           out.face_normals);
    }
    if (materials) {
      if (c->fl >= 0) out.face_materials.push_back(attributes->material(static_cast<uint32_t>(c->fl)));
      if (c->fr >= 0) out.face_materials.push_back(attributes->material(static_cast<uint32_t>(c->fr)));
    }
  }

  for (uint32_t v = 0; v < n_vertices; ++v)
    if (repaired.canonical[v] != v)
      out.welds.push_back({vertex_id[v], vertex_id[repaired.canonical[v]]});
  for (uint32_t v : repaired.carried_faces) out.carried_faces.push_back(vertex_id[v]);
  for (uint32_t v : repaired.loose_vertices)
    out.positions.insert(out.positions.end(), input.positions.begin() + 3 * v,
                         input.positions.begin() + 3 * v + 3);
  out.loose_vertex_count = static_cast<uint32_t>(repaired.loose_vertices.size());

  // Carried faces keep the input's corners as they are, at every level.
  for (uint32_t f : repaired.carried_input_faces) {
    if (uvs) copy_corners(input.uv_indices, f, out.face_uvs);
    if (normals) copy_corners(input.normal_indices, f, out.face_normals);
    if (materials) out.face_materials.push_back(input.face_materials[f]);
  }
  if (keep_order) {
    // Each input vertex is one canonical half-edge-mesh vertex, or a loose vertex; each input
    // triangle one half-edge-mesh face, or a carried face (last in creation order).
    out.input_vertices.assign(input.vertex_count(), kNoVertex);
    for (uint32_t x = 0; x < n_vertices; ++x) {
      if (repaired.canonical[x] == x) out.input_vertices[repaired.input_vertex[x]] = vertex_id[x];
    }
    const uint32_t first_loose = next_vertex;
    for (std::size_t k = 0; k < repaired.loose_vertices.size(); ++k) {
      out.input_vertices[repaired.loose_vertices[k]] = first_loose + static_cast<uint32_t>(k);
    }
    out.input_faces.assign(input.face_count(), kNoVertex);
    for (uint32_t f = 0; f < n_faces; ++f) {
      if (face_id[f] != kNoVertex) out.input_faces[repaired.input_face[f]] = face_id[f];
    }
    for (std::size_t k = 0; k < repaired.carried_input_faces.size(); ++k) {
      out.input_faces[repaired.carried_input_faces[k]] = next_face + static_cast<uint32_t>(k);
    }
  }
  if (keep_order) record_face_rotations(input, out);
  if (uvs) out.uvs = input.uvs;
  if (normals) out.normals = input.normals;
  if (keep_attributes) {
    out.material_names = input.material_names;
    out.material_libraries = input.material_libraries;
    if (input.has_colors()) {
      // Per vertex id, like positions: each vertex takes its input vertex's colour.
      const std::size_t cc = input.color_components;
      out.color_components = input.color_components;
      out.colors.reserve(cc * out.vertex_count());
      auto add_color = [&](uint32_t input_vertex) {
        out.colors.insert(out.colors.end(), input.colors.begin() + cc * input_vertex,
                          input.colors.begin() + cc * (input_vertex + 1));
      };
      for (uint32_t x : vertex_order) add_color(repaired.input_vertex[x]);
      for (uint32_t v : repaired.loose_vertices) add_color(v);
    }
  }
}

}  // namespace

double default_feature_angle(Metric metric) {
  return metric == Metric::kQuadric ? 180.0 : 30.0;
}

double effective_feature_angle(const EncodeOptions& options) {
  return options.feature_angle_deg < 0 ? default_feature_angle(options.metric)
                                       : options.feature_angle_deg;
}

namespace {

Status encode_unguarded(const Mesh& input, const EncodeOptions& options, uint32_t chunk_splits,
                        ProgressiveMesh& out, EncodeStats* stats) {
  if (!(options.feature_angle_deg <= 180))  // negative: the default; NaN fails here
    return Status(ErrorCode::kInvalidArgument, "feature angle must be within [0, 180] degrees");
  if (!(options.max_normal_flip_deg >= 0 && options.max_normal_flip_deg <= 180))
    return Status(ErrorCode::kInvalidArgument, "normal flip limit must be within [0, 180] degrees");
  if (!(options.layer_window >= 0))  // NaN fails here; infinity: whole chunks
    return Status(ErrorCode::kInvalidArgument, "layer window must be a share >= 0");
  if (options.layer_window > 0 && chunk_splits == 0)
    return Status(ErrorCode::kInvalidArgument, "layer chunks must hold at least one split");

  if (Status valid = validate_attributes(input); !valid)
    return Status(valid.code(), "mesh attributes: " + valid.message());
  if (!options.drop_attributes) {
    if (Status s = check_material_strings(input.material_names, input.material_libraries); !s)
      return s;
  }

  // Stage 1: a manifold half-edge mesh, so that collapses can keep topology exactly.
  // Stage 2: the collapse sequence. Stage 3: the progressive mesh.
  const bool fast = options.fast;  // either metric
  ManifoldMesh repaired;
  if (fast) {
    // The fast loop takes a manifold input as it is, with no OpenMesh mesh built for it;
    // only the others go through the repair.
    if (Status s = check_encodable(input); !s) return s;
    FastSimplification run;
    const std::size_t n_vertices = input.vertex_count(), n_faces = input.face_count();
    if (simplify_fast_direct(input, options, run)) {
      repaired.input_vertex.resize(n_vertices);
      std::iota(repaired.input_vertex.begin(), repaired.input_vertex.end(), uint32_t{0});
      repaired.canonical = repaired.input_vertex;
      repaired.pinned.assign(n_vertices, 0);
      repaired.input_face.resize(n_faces);
      std::iota(repaired.input_face.begin(), repaired.input_face.end(), uint32_t{0});
    } else {
      if (Status s = build_manifold_mesh(input, repaired); !s) return s;
      if (Status s = simplify_fast(input, repaired, options, run); !s) return s;
    }
    assemble(input, repaired,
             Simplified{run.collapses, run.moved_faces, run.attribute_record,
                        run.attributes.get(), run.base, run.points.data(),
                        run.points.size() / 3, repaired.input_face.size()},
             !options.drop_attributes, options.keep_order, out);
  } else {
    if (Status s = build_manifold_mesh(input, repaired); !s) return s;
    SchroederSimplifier simplifier(input, repaired, options);
    simplifier.run();
    const HalfEdgeMesh& mesh = repaired.mesh;
    BaseMesh base;
    for (auto v : mesh.vertices()) base.vertices.push_back(static_cast<uint32_t>(v.idx()));
    for (auto f : mesh.faces()) {  // skip deleted elements
      base.faces.push_back(static_cast<uint32_t>(f.idx()));
      for (auto w : mesh.fv_range(f)) base.corners.push_back(static_cast<uint32_t>(w.idx()));
    }
    static_assert(sizeof(HalfEdgeMesh::Point) == 3 * sizeof(float));
    assemble(
        input, repaired,
        Simplified{simplifier.collapses, simplifier.moved_faces, simplifier.attribute_record,
                   simplifier.attributes(), base, reinterpret_cast<const float*>(mesh.points()),
                   mesh.n_vertices(), mesh.n_faces()},
        !options.drop_attributes, options.keep_order, out);
  }
  // The progressive mesh, checked as a decoder would check it.
  if (options.layer_window > 0)
    layer_splits(out, chunk_splits, options.layer_window, options.threads);
  order_attribute_tables(out);  // after the splits' order is final
  if (Status valid = validate(out); !valid)
    return Status(ErrorCode::kInternal, "encoder produced " + valid.message());

  if (stats) {
    stats->repair = repaired.report;
    stats->input_faces = input.face_count();
    stats->base_faces = out.base_face_count();
    stats->base_vertices = out.base_vertex_count;
    stats->collapses = out.splits.size();
    stats->fast = fast;
  }
  if (options.progress) options.progress(1.0);
  return Status::ok();
}

}  // namespace

Status encode(const Mesh& input, const EncodeOptions& options, ProgressiveMesh& out,
              EncodeStats* stats) {
  return encode(input, options, WriteOptions{}, out, stats);
}

Status encode(const Mesh& input, const EncodeOptions& options, const WriteOptions& stream,
              ProgressiveMesh& out, EncodeStats* stats) {
  // OpenMesh's logs are off while the half-edge mesh is built and simplified, as the caller
  // left them afterwards; no exception leaves (status.h).
  const QuietOpenMeshLogs quiet;
  try {
    return encode_unguarded(input, options, stream.chunk_splits, out, stats);
  } catch (const std::bad_alloc&) {
    out = ProgressiveMesh();
    return Status(ErrorCode::kResourceLimit, "out of memory");
  } catch (const std::length_error&) {  // a container asked for more than it can hold
    out = ProgressiveMesh();
    return Status(ErrorCode::kResourceLimit, "out of memory");
  }
}

}  // namespace pm
