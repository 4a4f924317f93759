// The texture-coordinate error of a LOD; see uv_error.h for the measure and its seam rule.
#include "uv_error.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <set>
#include <tuple>
#include <utility>

namespace pm::bench {
namespace {

using Vec = std::array<double, 3>;

Vec position(const pm::Mesh& mesh, uint32_t v) {
  const float* p = &mesh.positions[3 * std::size_t(v)];
  return {p[0], p[1], p[2]};
}
Vec operator-(const Vec& a, const Vec& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
double dot(const Vec& a, const Vec& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
double ratio(double numerator, double denominator) {  // 0 on a degenerate triangle
  return denominator != 0 ? numerator / denominator : 0;
}

// Barycentric coordinates of the point of triangle (a, b, c) closest to p, by the Voronoi
// regions of its vertices, edges and interior (Ericson 2005, "Real-Time Collision
// Detection", §5.1.5, ClosestPtPointTriangle), with degenerate edges guarded.
std::array<double, 3> closest_barycentric(const Vec& p, const Vec& a, const Vec& b, const Vec& c) {
  const Vec ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
  const Vec bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = ratio(d1, d1 - d3);
    return {1 - v, v, 0};
  }
  const Vec cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = ratio(d2, d2 - d6);
    return {1 - w, 0, w};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    const double w = ratio(d4 - d3, (d4 - d3) + (d5 - d6));
    return {0, 1 - w, w};
  }
  const double v = ratio(vb, va + vb + vc), w = ratio(vc, va + vb + vc);
  return {1 - v - w, v, w};
}

// Squared distance from p to the box [lo, hi] (0 inside).
double box_distance_squared(const Vec& p, const Vec& lo, const Vec& hi) {
  double sum = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const double outside = std::max({lo[axis] - p[axis], 0.0, p[axis] - hi[axis]});
    sum += outside * outside;
  }
  return sum;
}

// A small deterministic generator (Steele, Lea and Flood 2014, "Fast splittable
// pseudorandom number generators": SplitMix64), seeded per face so that a face's samples
// do not depend on the others.
struct SplitMix64 {
  uint64_t state;
  uint64_t next() {
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }  // [0, 1)
};

// The UV of corner c (0..2) of face f, or false when it has none.
bool corner_uv(const pm::Mesh& mesh, std::size_t f, int c, std::array<double, 2>& uv) {
  const uint32_t id = mesh.uv_indices[3 * f + c];
  if (id == pm::kNoAttribute) return false;
  uv = {mesh.uvs[2 * std::size_t(id)], mesh.uvs[2 * std::size_t(id) + 1]};
  return true;
}

bool face_uvs(const pm::Mesh& mesh, std::size_t f, std::array<std::array<double, 2>, 3>& uv) {
  if (!mesh.has_uvs()) return false;
  for (int c = 0; c < 3; ++c)
    if (!corner_uv(mesh, f, c, uv[c])) return false;
  return true;
}

std::array<double, 2> interpolate(const std::array<std::array<double, 2>, 3>& uv,
                                  const std::array<double, 3>& weights) {
  return {weights[0] * uv[0][0] + weights[1] * uv[1][0] + weights[2] * uv[2][0],
          weights[0] * uv[0][1] + weights[1] * uv[1][1] + weights[2] * uv[2][1]};
}

double uv_distance(const std::array<double, 2>& a, const std::array<double, 2>& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1]);
}

// Original faces that touch a seam vertex: a vertex whose corners carry two or more
// distinct UVs (by value, so that a table with repeated entries makes no seam).
std::vector<bool> faces_at_seams(const pm::Mesh& mesh) {
  std::vector<std::set<std::pair<float, float>>> uvs_of_vertex(mesh.vertex_count());
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const uint32_t id = mesh.uv_indices[i];
    if (id != pm::kNoAttribute)
      uvs_of_vertex[mesh.triangles[i]].insert(
          {mesh.uvs[2 * std::size_t(id)], mesh.uvs[2 * std::size_t(id) + 1]});
  }
  std::vector<bool> at_seam(mesh.face_count(), false);
  for (std::size_t f = 0; f < mesh.face_count(); ++f)
    for (int c = 0; c < 3; ++c)
      if (uvs_of_vertex[mesh.triangles[3 * f + c]].size() > 1) at_seam[f] = true;
  return at_seam;
}

}  // namespace

// --- ClosestTriangles ---

ClosestTriangles::ClosestTriangles(const pm::Mesh& mesh) : mesh_(mesh) {
  faces_.resize(mesh.face_count());
  std::iota(faces_.begin(), faces_.end(), 0u);
  build_all();
}

ClosestTriangles::ClosestTriangles(const pm::Mesh& mesh, std::vector<uint32_t> faces)
    : mesh_(mesh), faces_(std::move(faces)) {
  build_all();
}

void ClosestTriangles::build_all() {
  std::vector<Vec> centroids(mesh_.face_count(), Vec{0, 0, 0});
  for (uint32_t f : faces_) {
    for (int c = 0; c < 3; ++c) {
      const Vec p = position(mesh_, mesh_.triangles[3 * std::size_t(f) + c]);
      for (int axis = 0; axis < 3; ++axis) centroids[f][axis] += p[axis] / 3;
    }
  }
  nodes_.reserve(faces_.size());
  if (!faces_.empty()) build(0, uint32_t(faces_.size()), centroids);
}

// Builds the node of faces_[first, first + count): leaves of up to four faces, inner nodes
// split at the median centroid along the longest axis of the centroids' box.
uint32_t ClosestTriangles::build(uint32_t first, uint32_t count, std::vector<Vec>& centroids) {
  const uint32_t index = uint32_t(nodes_.size());
  nodes_.emplace_back();
  Node node;
  node.lo.fill(std::numeric_limits<double>::infinity());
  node.hi.fill(-std::numeric_limits<double>::infinity());
  Vec centroid_lo = node.lo, centroid_hi = node.hi;
  for (uint32_t i = first; i < first + count; ++i) {
    for (int c = 0; c < 3; ++c) {
      const Vec p = position(mesh_, mesh_.triangles[3 * std::size_t(faces_[i]) + c]);
      for (int axis = 0; axis < 3; ++axis) {
        node.lo[axis] = std::min(node.lo[axis], p[axis]);
        node.hi[axis] = std::max(node.hi[axis], p[axis]);
      }
    }
    for (int axis = 0; axis < 3; ++axis) {
      centroid_lo[axis] = std::min(centroid_lo[axis], centroids[faces_[i]][axis]);
      centroid_hi[axis] = std::max(centroid_hi[axis], centroids[faces_[i]][axis]);
    }
  }
  if (count <= 4) {
    node.first = first;
    node.count = count;
  } else {
    int axis = 0;
    for (int a = 1; a < 3; ++a)
      if (centroid_hi[a] - centroid_lo[a] > centroid_hi[axis] - centroid_lo[axis]) axis = a;
    const uint32_t half = count / 2;
    std::nth_element(faces_.begin() + first, faces_.begin() + first + half,
                     faces_.begin() + first + count, [&](uint32_t x, uint32_t y) {
                       return std::tie(centroids[x][axis], x) < std::tie(centroids[y][axis], y);
                     });
    node.left = build(first, half, centroids);
    node.right = build(first + half, count - half, centroids);
  }
  nodes_[index] = node;
  return index;
}

SurfacePoint ClosestTriangles::closest_on_face(uint32_t face, const Vec& p) const {
  const uint32_t* corners = &mesh_.triangles[3 * std::size_t(face)];
  const Vec a = position(mesh_, corners[0]), b = position(mesh_, corners[1]),
            c = position(mesh_, corners[2]);
  SurfacePoint point;
  point.face = face;
  point.barycentric = closest_barycentric(p, a, b, c);
  const auto& w = point.barycentric;
  Vec q;
  for (int axis = 0; axis < 3; ++axis) q[axis] = w[0] * a[axis] + w[1] * b[axis] + w[2] * c[axis];
  point.distance = std::sqrt(dot(p - q, p - q));
  return point;
}

SurfacePoint ClosestTriangles::nearest(const Vec& p) const {
  SurfacePoint best;
  best.distance = std::numeric_limits<double>::infinity();
  if (nodes_.empty()) return best;
  // Depth-first, nearer child first, skipping boxes no nearer than the best so far.
  std::vector<uint32_t> stack = {0};
  while (!stack.empty()) {
    const Node& node = nodes_[stack.back()];
    stack.pop_back();
    if (box_distance_squared(p, node.lo, node.hi) >= best.distance * best.distance) continue;
    if (node.count > 0) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i) {
        const SurfacePoint candidate = closest_on_face(faces_[i], p);
        if (candidate.distance < best.distance ||
            (candidate.distance == best.distance && candidate.face < best.face))
          best = candidate;
      }
      continue;
    }
    const double left = box_distance_squared(p, nodes_[node.left].lo, nodes_[node.left].hi);
    const double right = box_distance_squared(p, nodes_[node.right].lo, nodes_[node.right].hi);
    if (left <= right) {
      stack.push_back(node.right);
      stack.push_back(node.left);
    } else {
      stack.push_back(node.left);
      stack.push_back(node.right);
    }
  }
  return best;
}

void ClosestTriangles::within(const Vec& p, double radius, std::vector<SurfacePoint>& out) const {
  if (nodes_.empty()) return;
  std::vector<uint32_t> stack = {0};
  while (!stack.empty()) {
    const Node& node = nodes_[stack.back()];
    stack.pop_back();
    if (box_distance_squared(p, node.lo, node.hi) > radius * radius) continue;
    if (node.count > 0) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i) {
        const SurfacePoint candidate = closest_on_face(faces_[i], p);
        if (candidate.distance <= radius) out.push_back(candidate);
      }
      continue;
    }
    stack.push_back(node.left);
    stack.push_back(node.right);
  }
}

// --- Charts ---

uint32_t UvCharts::chart_of(float u, float v) const {
  const auto it = chart_of_value.find({u, v});
  return it == chart_of_value.end() ? kNone : it->second;
}

uint32_t UvCharts::chart_of_face_of(const pm::Mesh& mesh, std::size_t face) const {
  if (!mesh.has_uvs()) return kNone;
  uint32_t chart = kNone;
  for (int c = 0; c < 3; ++c) {
    const uint32_t id = mesh.uv_indices[3 * face + c];
    if (id == pm::kNoAttribute) return kNone;
    const uint32_t corner =
        chart_of(mesh.uvs[2 * std::size_t(id)], mesh.uvs[2 * std::size_t(id) + 1]);
    if (corner == kNone || (c > 0 && corner != chart)) return kNone;
    chart = corner;
  }
  return chart;
}

UvCharts uv_charts(const pm::Mesh& mesh) {
  UvCharts charts;
  charts.chart_of_face.assign(mesh.face_count(), UvCharts::kNone);
  if (!mesh.has_uvs()) return charts;
  std::vector<uint32_t> parent(mesh.uv_count());
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::vector<bool> with_uvs(mesh.face_count(), false);
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const uint32_t* ids = &mesh.uv_indices[3 * f];
    if (ids[0] == pm::kNoAttribute || ids[1] == pm::kNoAttribute || ids[2] == pm::kNoAttribute)
      continue;
    with_uvs[f] = true;
    parent[find(ids[1])] = find(ids[0]);
    parent[find(ids[2])] = find(ids[0]);
  }
  // Charts numbered in order of their first face.
  std::vector<uint32_t> number(mesh.uv_count(), UvCharts::kNone);
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    if (!with_uvs[f]) continue;
    uint32_t& chart = number[find(mesh.uv_indices[3 * f])];
    if (chart == UvCharts::kNone) chart = uint32_t(charts.count++);
    charts.chart_of_face[f] = chart;
    for (int c = 0; c < 3; ++c) {
      const uint32_t id = mesh.uv_indices[3 * f + c];
      const auto [it, inserted] = charts.chart_of_value.emplace(
          std::make_pair(mesh.uvs[2 * std::size_t(id)], mesh.uvs[2 * std::size_t(id) + 1]), chart);
      if (!inserted && it->second != chart) it->second = UvCharts::kNone;
    }
  }
  return charts;
}

// --- The measure ---

namespace {

UvStatistics statistics(std::vector<double>& errors) {
  UvStatistics result;
  double sum_squares = 0;
  for (double e : errors) sum_squares += e * e;
  result.rms = std::sqrt(sum_squares / double(errors.size()));
  std::sort(errors.begin(), errors.end());
  // Nearest rank: the smallest error that at least 95% of the samples do not exceed.
  const std::size_t rank = std::size_t(std::ceil(0.95 * double(errors.size())));
  result.p95 = errors[std::max<std::size_t>(rank, 1) - 1];
  result.max = errors.back();
  return result;
}

}  // namespace

bool measure_uv_error(const pm::Mesh& original, const pm::Mesh& lod, const UvErrorOptions& options,
                      UvError& out, std::string* message) {
  out = UvError{};
  auto fail = [&](const char* text) {
    if (message) *message = text;
    return false;
  };
  if (!original.has_uvs()) return fail("the original has no texture coordinates");
  if (lod.face_count() == 0) return fail("the level of detail has no faces");

  // One hierarchy over every face, and one per chart.
  const ClosestTriangles everywhere(original);
  const UvCharts charts = uv_charts(original);
  std::vector<std::vector<uint32_t>> faces_of_chart(charts.count);
  for (uint32_t f = 0; f < original.face_count(); ++f)
    if (charts.chart_of_face[f] != UvCharts::kNone)
      faces_of_chart[charts.chart_of_face[f]].push_back(f);
  std::vector<ClosestTriangles> in_chart;
  in_chart.reserve(charts.count);
  for (auto& faces : faces_of_chart) in_chart.emplace_back(original, std::move(faces));
  const std::vector<bool> at_seam = faces_at_seams(original);

  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (std::size_t i = 0; i < original.positions.size(); ++i) {
    lo[i % 3] = std::min(lo[i % 3], double(original.positions[i]));
    hi[i % 3] = std::max(hi[i % 3], double(original.positions[i]));
  }
  const double tolerance =
      options.tie_tolerance * std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);

  std::vector<double> nearest_errors, chart_errors;
  std::vector<SurfacePoint> ties;
  // The nearest face of `hierarchy`, or among faces tied with it the one whose UV is closest
  // to the sample's (uv_error.h, "Seams"). Infinite when no candidate has UVs.
  auto closest_uv = [&](const ClosestTriangles& hierarchy, const Vec& p,
                        const std::array<double, 2>& uv, uint32_t& chosen, double& at_nearest) {
    const SurfacePoint nearest = hierarchy.nearest(p);
    ties.clear();
    hierarchy.within(p, nearest.distance + tolerance, ties);
    double best = INFINITY;
    at_nearest = INFINITY;
    for (const SurfacePoint& tie : ties) {
      std::array<std::array<double, 2>, 3> corners;
      if (!face_uvs(original, tie.face, corners)) continue;
      const double error = uv_distance(uv, interpolate(corners, tie.barycentric));
      if (tie.face == nearest.face) at_nearest = error;
      if (error < best || (error == best && tie.face < chosen)) {
        best = error;
        chosen = tie.face;
      }
    }
    return best;
  };
  auto measure_sample = [&](const Vec& p, const std::array<double, 2>& uv, uint32_t chart) {
    uint32_t chosen = 0;
    double at_nearest = INFINITY;
    const double nearest = closest_uv(everywhere, p, uv, chosen, at_nearest);
    if (!std::isfinite(nearest)) {
      ++out.without_uv;
      return;
    }
    if (nearest < at_nearest) ++out.ties_resolved;
    if (nearest >= options.seam_band_threshold && at_seam[chosen]) ++out.seam_band;
    nearest_errors.push_back(nearest);
    uint32_t chosen_in_chart = chosen;
    if (chart == UvCharts::kNone || in_chart[chart].empty()) {
      ++out.chartless;
      chart_errors.push_back(nearest);
    } else {
      chart_errors.push_back(closest_uv(in_chart[chart], p, uv, chosen_in_chart, at_nearest));
    }
    if (options.on_sample)
      options.on_sample(p, uv, nearest, chosen, chart_errors.back(), chosen_in_chart);
  };

  // Every LOD vertex, once per distinct UV it shows (a seam vertex once per chart), keyed
  // by values so that split copies of a vertex (a seam-split buffer) count once per UV.
  std::set<std::array<float, 5>> vertex_samples;
  for (std::size_t f = 0; f < lod.face_count(); ++f) {
    for (int c = 0; c < 3; ++c) {
      std::array<double, 2> uv;
      if (!lod.has_uvs() || !corner_uv(lod, f, c, uv)) continue;
      const float* p = &lod.positions[3 * std::size_t(lod.triangles[3 * f + c])];
      vertex_samples.insert({p[0], p[1], p[2], float(uv[0]), float(uv[1])});
    }
  }
  for (const auto& s : vertex_samples)
    measure_sample({s[0], s[1], s[2]}, {s[3], s[4]}, charts.chart_of(s[3], s[4]));

  // Points inside the faces: the face's share of the samples by area, as m x m similar
  // triangles with one random point in each (Metro, §3.1).
  std::vector<double> areas(lod.face_count());
  double total_area = 0;
  for (std::size_t f = 0; f < lod.face_count(); ++f) {
    const Vec a = position(lod, lod.triangles[3 * f]), b = position(lod, lod.triangles[3 * f + 1]),
              c = position(lod, lod.triangles[3 * f + 2]);
    const Vec ab = b - a, ac = c - a;
    const Vec cross = {ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2],
                       ab[0] * ac[1] - ab[1] * ac[0]};
    areas[f] = 0.5 * std::sqrt(dot(cross, cross));
    total_area += areas[f];
  }
  const double total_samples = options.samples_per_original_face * double(original.face_count());
  for (std::size_t f = 0; f < lod.face_count(); ++f) {
    const double share = total_area > 0 ? total_samples * areas[f] / total_area : 1;
    const int m = std::max(1, int(std::lround(std::sqrt(share))));
    std::array<std::array<double, 2>, 3> uv;
    if (!face_uvs(lod, f, uv)) {
      out.without_uv += std::size_t(m) * m;
      continue;
    }
    const uint32_t chart = charts.chart_of_face_of(lod, f);
    const Vec corner[3] = {position(lod, lod.triangles[3 * f]),
                           position(lod, lod.triangles[3 * f + 1]),
                           position(lod, lod.triangles[3 * f + 2])};
    SplitMix64 random{options.seed * 0x9E3779B97F4A7C15ull + f};
    // Sub-triangle (i, j) of the m x m grid in the face's (s, t) coordinates, p = a + s ab +
    // t ac: upright ones for i + j < m, inverted ones for i + j < m - 1.
    auto sample_in = [&](double s0, double t0, double s1, double t1, double s2, double t2) {
      double r1 = random.uniform(), r2 = random.uniform();
      if (r1 + r2 > 1) {
        r1 = 1 - r1;
        r2 = 1 - r2;
      }
      const double s = s0 + r1 * (s1 - s0) + r2 * (s2 - s0);
      const double t = t0 + r1 * (t1 - t0) + r2 * (t2 - t0);
      const std::array<double, 3> weights = {1 - s - t, s, t};
      Vec p;
      for (int axis = 0; axis < 3; ++axis)
        p[axis] = weights[0] * corner[0][axis] + weights[1] * corner[1][axis] +
                  weights[2] * corner[2][axis];
      measure_sample(p, interpolate(uv, weights), chart);
    };
    const double step = 1.0 / m;
    for (int i = 0; i < m; ++i) {
      for (int j = 0; i + j < m; ++j) {
        sample_in(i * step, j * step, (i + 1) * step, j * step, i * step, (j + 1) * step);
        if (i + j < m - 1)
          sample_in((i + 1) * step, j * step, (i + 1) * step, (j + 1) * step, i * step,
                    (j + 1) * step);
      }
    }
  }

  if (nearest_errors.empty())
    return fail("no sample of the level of detail has texture coordinates");
  out.samples = nearest_errors.size();
  out.nearest = statistics(nearest_errors);
  out.same_chart = statistics(chart_errors);
  return true;
}

}  // namespace pm::bench
