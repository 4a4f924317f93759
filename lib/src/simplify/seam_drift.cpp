// Seam drift (see seam_drift.h): removed seam points attached to the seam edges that
// replaced them.
#include "simplify/seam_drift.h"

#include <algorithm>

#include "simplify/geometry.h"

namespace pm {

namespace {

double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double length2 = ab.sqrnorm();
  double t = length2 > 0 ? ((p - a) | ab) / length2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

}  // namespace

SeamDrift::SeamDrift(const HalfEdgeMesh& mesh, const CornerAttributes& attributes)
    : mesh_(mesh), attributes_(attributes) {}

uint32_t SeamDrift::other_seam_end(HalfEdgeMesh::HalfedgeHandle h) const {
  const auto v = mesh_.from_vertex_handle(h), u = mesh_.to_vertex_handle(h);
  if (!attributes_.is_uv_seam(mesh_, mesh_.edge_handle(h))) return kNone;
  uint32_t other = kNone;
  int seams = 0;
  for (auto out : mesh_.voh_range(v)) {
    if (!attributes_.is_uv_seam(mesh_, mesh_.edge_handle(out))) continue;
    ++seams;
    const auto w = mesh_.to_vertex_handle(out);
    if (w != u) other = static_cast<uint32_t>(w.idx());
  }
  return seams == 2 ? other : kNone;
}

double SeamDrift::collapse_drift(HalfEdgeMesh::HalfedgeHandle h) const {
  const uint32_t w = other_seam_end(h);
  if (w == kNone) return 0;
  const uint32_t v = mesh_.from_vertex_handle(h).idx(), u = mesh_.to_vertex_handle(h).idx();
  const Vec3 a = point_of(mesh_, mesh_.vertex_handle(u));
  const Vec3 b = point_of(mesh_, mesh_.vertex_handle(w));
  double worst = distance_to_segment(point_of(mesh_, mesh_.vertex_handle(v)), a, b);
  for (const uint64_t edge : {key(v, u), key(v, w)}) {
    const auto it = points_.find(edge);
    if (it == points_.end()) continue;
    // Near the base mesh a seam edge stands for a long stretch of the input's seam; an
    // evenly spread subset bounds the cost, as RemovedPoints does for faces.
    const std::vector<uint32_t>& points = it->second;
    const std::size_t stride = points.size() / kMeasuredPoints + 1;
    for (std::size_t i = 0; i < points.size(); i += stride)
      worst = std::max(worst,
                       distance_to_segment(point_of(mesh_, mesh_.vertex_handle(points[i])), a, b));
  }
  return worst;
}

void SeamDrift::collapse(HalfEdgeMesh::HalfedgeHandle h) {
  const uint32_t w = other_seam_end(h);
  if (w == kNone) return;
  const uint32_t v = mesh_.from_vertex_handle(h).idx(), u = mesh_.to_vertex_handle(h).idx();
  std::vector<uint32_t> merged{v};
  for (const uint64_t edge : {key(v, u), key(v, w)}) {
    const auto it = points_.find(edge);
    if (it == points_.end()) continue;
    merged.insert(merged.end(), it->second.begin(), it->second.end());
    points_.erase(it);
  }
  std::vector<uint32_t>& target = points_[key(u, w)];
  target.insert(target.end(), merged.begin(), merged.end());
}

}  // namespace pm
