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

SeamDrift::SeamDrift(const float* points, std::size_t n_vertices,
                     const CornerAttributes& attributes)
    : points_xyz_(points), attributes_(attributes), points_(n_vertices) {}

const std::vector<uint32_t>* SeamDrift::find(uint32_t a, uint32_t b) const {
  const uint32_t other = std::max(a, b);
  const std::unique_ptr<std::vector<Attached>>& lists = points_[std::min(a, b)];
  if (!lists) return nullptr;
  for (const Attached& e : *lists)
    if (e.other == other) return &e.points;
  return nullptr;
}

uint32_t SeamDrift::other_seam_end(const CollapseStar& c) const {
  uint32_t other = kNone;
  int seams = 0;
  bool along = false;
  for (int i = 0; i < c.n_edges; ++i) {
    const CollapseStar::Edge& e = c.edges[i];
    if (!attributes_.is_uv_seam(e.f, e.g, c.v, e.w)) continue;
    ++seams;
    if (e.w == c.u)
      along = true;
    else
      other = e.w;
  }
  return along && seams == 2 ? other : kNone;
}

double SeamDrift::collapse_drift(const CollapseStar& c) const {
  const uint32_t w = other_seam_end(c);
  if (w == kNone) return 0;
  const Vec3 a = point(c.u), b = point(w);
  double worst = distance_to_segment(point(c.v), a, b);
  for (const uint32_t end : {c.u, w}) {
    const std::vector<uint32_t>* attached = find(c.v, end);
    if (!attached) continue;
    // Near the base mesh a seam edge stands for a long stretch of the input's seam; an
    // evenly spread subset bounds the cost, as the former default loop's RemovedPoints did for faces.
    const std::vector<uint32_t>& points = *attached;
    const std::size_t stride = points.size() / kMeasuredPoints + 1;
    for (std::size_t i = 0; i < points.size(); i += stride)
      worst = std::max(worst, distance_to_segment(point(points[i]), a, b));
  }
  return worst;
}

void SeamDrift::collapse(const CollapseStar& c) {
  const uint32_t w = other_seam_end(c);
  if (w == kNone) return;
  std::vector<uint32_t> merged{c.v};
  for (const uint32_t end : {c.u, w}) {
    std::vector<Attached>& lists = lists_of(c.v, end);
    const uint32_t other = std::max(c.v, end);
    const auto it = std::find_if(lists.begin(), lists.end(),
                                 [&](const Attached& e) { return e.other == other; });
    if (it == lists.end()) continue;
    merged.insert(merged.end(), it->points.begin(), it->points.end());
    lists.erase(it);
  }
  std::vector<Attached>& lists = lists_of(c.u, w);
  const uint32_t other = std::max(c.u, w);
  auto it = std::find_if(lists.begin(), lists.end(),
                         [&](const Attached& e) { return e.other == other; });
  if (it == lists.end()) it = lists.insert(lists.end(), Attached{other, {}});
  it->points.insert(it->points.end(), merged.begin(), merged.end());
}

}  // namespace pm
