// Removed points and their faces: see removed_points.h (Klein, Liebich and Straßer 1996).
#include "simplify/removed_points.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pm {

namespace {

// The largest coordinate magnitude: distances' rounding errors scale with it.
double extent_of(const HalfEdgeMesh& mesh) {
  double extent = 0;
  for (auto v : mesh.vertices())
    for (int k = 0; k < 3; ++k) extent = std::max(extent, std::abs(double(mesh.point(v)[k])));
  return extent;
}

}  // namespace

RemovedPoints::RemovedPoints(const HalfEdgeMesh& mesh)
    : RemovedPoints(mesh, BoxedTriangles::slack_for(extent_of(mesh))) {}

RemovedPoints::RemovedPoints(const HalfEdgeMesh& mesh, double slack)
    : mesh_(mesh),
      region_triangles_(slack),
      fan_(slack),
      first_(mesh.n_faces(), kNone),
      next_(mesh.n_vertices(), kNone) {
  // The input's faces and, per vertex, the faces around it (compressed rows), kept
  // because the mesh's own connectivity changes with every collapse.
  input_corners_.reserve(3 * mesh.n_faces());
  std::vector<uint32_t> count(mesh.n_vertices() + 1, 0);
  for (auto f : mesh.faces()) {
    for (auto w : mesh.fv_range(f)) {
      input_corners_.push_back(uint32_t(w.idx()));
      ++count[w.idx() + 1];
    }
  }
  faces_of_begin_.assign(mesh.n_vertices() + 1, 0);
  for (std::size_t v = 0; v < mesh.n_vertices(); ++v)
    faces_of_begin_[v + 1] = faces_of_begin_[v] + count[v + 1];
  faces_of_.resize(input_corners_.size());
  std::vector<uint32_t> fill(faces_of_begin_.begin(), faces_of_begin_.end() - 1);
  for (std::size_t i = 0; i < input_corners_.size(); ++i)
    faces_of_[fill[input_corners_[i]]++] = uint32_t(i / 3);
  thin_input_face_.resize(input_corners_.size() / 3);
  for (std::size_t f = 0; f < thin_input_face_.size(); ++f) {
    auto corner = [&](int c) {
      return point_of(mesh, mesh.vertex_handle(input_corners_[3 * f + c]));
    };
    thin_input_face_[f] = BoxedTriangles::is_thin(corner(0), corner(1), corner(2));
  }
}

void RemovedPoints::collect_input_faces(HalfEdgeMesh::HalfedgeHandle h, const Fan& fan,
                                        bool with_samples) const {
  // The vertices whose input faces make the region, then the faces, each once: a small
  // open-addressing set of face ids (it stays in cache, where a mark per input face would
  // be a scattered load per face on a large input), in the order first met.
  region_vertices_.clear();
  if (with_samples) region_vertices_.assign(sampled_.begin(), sampled_.end());
  for (int i = 0; i < fan.moved; ++i)
    for (auto w : mesh_.fv_range(mesh_.face_handle(fan.face[i])))
      region_vertices_.push_back(uint32_t(w.idx()));
  region_vertices_.push_back(uint32_t(mesh_.to_vertex_handle(h).idx()));
  std::size_t entries = 0;
  for (uint32_t v : region_vertices_) entries += faces_of_begin_[v + 1] - faces_of_begin_[v];
  std::size_t slots = 64;
  while (slots < 2 * entries) slots *= 2;
  seen_.assign(slots, kNone);
  region_.clear();
  for (uint32_t v : region_vertices_)
    for (uint32_t i = faces_of_begin_[v]; i < faces_of_begin_[v + 1]; ++i) {
      const uint32_t f = faces_of_[i];
      std::size_t slot = (f * 0x9E3779B1u) & (slots - 1);  // Fibonacci hashing
      while (seen_[slot] != kNone && seen_[slot] != f) slot = (slot + 1) & (slots - 1);
      if (seen_[slot] == kNone) seen_[slot] = f, region_.push_back(f);
    }
}

bool RemovedPoints::make_fan(HalfEdgeMesh::HalfedgeHandle h, Fan& fan) const {
  const auto v = mesh_.from_vertex_handle(h), u = mesh_.to_vertex_handle(h);
  const HalfEdgeMesh::FaceHandle fl = mesh_.face_handle(h), fr = mesh_.opposite_face_handle(h);
  const Vec3 target = point_of(mesh_, u);
  fan.count = 0;
  fan.triangles.clear(kMaxFan);
  auto add = [&](HalfEdgeMesh::FaceHandle f) {
    Vec3 corner[3];
    int c = 0;
    for (auto w : mesh_.fv_range(f)) corner[c++] = w == v ? target : point_of(mesh_, w);
    fan.triangles.add(corner[0], corner[1], corner[2]);
    fan.face[fan.count++] = f.idx();
  };
  for (auto f : mesh_.vf_range(v)) {
    if (f == fl || f == fr) continue;
    if (fan.count == kMaxFan) return false;
    add(f);
  }
  fan.moved = fan.count;
  // u's other faces do not change, but a point near the border of v's one-ring may be
  // nearer to one of them; and where v's faces all go (a boundary vertex with one face),
  // they are the only place left.
  for (auto f : mesh_.vf_range(u)) {
    if (f == fl || f == fr) continue;
    if (fan.count == kMaxFan) break;
    add(f);
  }
  return fan.count > 0;
}

void RemovedPoints::gather_points(HalfEdgeMesh::HalfedgeHandle h,
                                  std::vector<uint32_t>& points) const {
  for (auto f : mesh_.vf_range(mesh_.from_vertex_handle(h)))
    for (uint32_t p = first_[f.idx()]; p != kNone; p = next_[p]) points.push_back(p);
}

void RemovedPoints::sample_points(HalfEdgeMesh::HalfedgeHandle h) const {
  moving_.clear();
  gather_points(h, moving_);
  const std::size_t stride = moving_.size() / kMeasuredPoints + 1;
  sampled_.clear();
  sampled_.push_back(uint32_t(mesh_.from_vertex_handle(h).idx()));
  for (std::size_t i = 0; i < moving_.size(); i += stride) sampled_.push_back(moving_[i]);
}

double RemovedPoints::collapse_distance(HalfEdgeMesh::HalfedgeHandle h) const {
  const double lower = removed_distance(h);
  return lower < 0 ? 0 : collapse_distance_from(h, lower);
}

double RemovedPoints::removed_distance(HalfEdgeMesh::HalfedgeHandle h) const {
  Fan& fan = fan_;
  fan_of_ = -1;
  if (!make_fan(h, fan)) return -1;
  fan_of_ = h.idx();
  sample_points(h);
  // The largest over points of the distance to the nearest face: a point already nearer
  // than the worst so far to some face cannot raise it, so its search stops there.
  double worst = 0;
  int hint = -1;  // the points come face by face: the previous one's face is a good guess
  for (uint32_t p : sampled_) {
    const double nearest =
        fan.triangles.nearest_distance(point_of(mesh_, mesh_.vertex_handle(p)), worst, &hint);
    if (nearest > worst) worst = nearest;
  }
  return worst;
}

double RemovedPoints::collapse_distance_from(HalfEdgeMesh::HalfedgeHandle h, double worst) const {
  if (fan_of_ != h.idx()) return collapse_distance(h);  // not right after removed_distance(h)
  const Fan& fan = fan_;
  int hint = -1;

  // The fan's points (centroids and edge midpoints of the faces that change) to the input.
  // Neighbouring faces of the fan share their edge to u, so most midpoints come twice. A
  // point measured again cannot raise `worst` (its distance is at most `worst` already), so
  // it is measured once; the same sum in either order is the same point, bit for bit.
  measured_midpoints_.clear();
  for (int i = 0; i < fan.moved; ++i) {  // the faces that change
    const Vec3 a = fan.triangles.corner(i, 0), b = fan.triangles.corner(i, 1),
               c = fan.triangles.corner(i, 2);
    measured_midpoints_.push_back((a + b + c) / 3.0);
    for (const Vec3& x : {(a + b) * 0.5, (b + c) * 0.5, (c + a) * 0.5}) {
      if (std::find(measured_midpoints_.begin(), measured_midpoints_.end(), x) !=
          measured_midpoints_.end())
        continue;
      measured_midpoints_.push_back(x);
    }
  }
  // First against the input faces around the fan's corners alone, a part of the region:
  // a point that far from the input is at most `worst` away cannot raise it, since the
  // whole region is nearer still. Most points settle there; the whole region (the input
  // faces around the removed points too, often many more) is gathered only for the rest.
  // The result is the same: the largest of `worst` and the points' distances to the region.
  collect_input_faces(h, fan, false);
  build_region();
  hint = -1;  // the last point's nearest face is a guess for the next
  pending_.clear();
  for (const Vec3& x : measured_midpoints_)
    if (region_triangles_.nearest_distance(x, worst, &hint) > worst) pending_.push_back(x);
  if (pending_.empty()) return worst;
  collect_input_faces(h, fan, true);
  build_region();
  hint = -1;
  for (const Vec3& x : pending_) {
    const double nearest = region_triangles_.nearest_distance(x, worst, &hint);
    if (nearest > worst && nearest != std::numeric_limits<double>::infinity()) worst = nearest;
  }
  return worst;
}

void RemovedPoints::build_region() const {
  region_triangles_.clear(region_.size());
  // The corners are scattered over the input: their loads are asked for (prefetched) a few
  // faces ahead.
  constexpr std::size_t kAhead = 8;
  const uint32_t* corners = input_corners_.data();
  const auto* points = mesh_.points();
  for (std::size_t k = 0; k < region_.size(); ++k) {
    if (k + 2 * kAhead < region_.size()) __builtin_prefetch(corners + 3 * region_[k + 2 * kAhead]);
    if (k + kAhead < region_.size()) {
      const uint32_t* ahead = corners + 3 * region_[k + kAhead];
      for (int c = 0; c < 3; ++c) __builtin_prefetch(points + ahead[c]);
    }
    const uint32_t* corner = corners + 3 * region_[k];
    region_triangles_.add(to_vec3(points[corner[0]]), to_vec3(points[corner[1]]),
                          to_vec3(points[corner[2]]), thin_input_face_[region_[k]]);
  }
}

double RemovedPoints::collapse(HalfEdgeMesh::HalfedgeHandle h) {
  Fan& fan = fan_;
  fan_of_ = -1;  // the mesh changes next
  if (!make_fan(h, fan)) return 0;
  double farthest = 0;
  moving_.assign(1, uint32_t(mesh_.from_vertex_handle(h).idx()));  // v, then its faces' points
  gather_points(h, moving_);
  for (auto f : mesh_.vf_range(mesh_.from_vertex_handle(h))) first_[f.idx()] = kNone;
  for (uint32_t p : moving_) {
    double nearest;
    const int best = fan.triangles.nearest(point_of(mesh_, mesh_.vertex_handle(p)), &nearest);
    next_[p] = first_[fan.face[best]];
    first_[fan.face[best]] = p;
    farthest = std::max(farthest, nearest);
  }
  return farthest;
}

}  // namespace pm
