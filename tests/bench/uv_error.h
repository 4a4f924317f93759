// Texture-coordinate error of a level of detail (issue 4): how far, in UV space, the LOD's
// texture coordinates are from the original's at the same place of the surface. The same
// function measures every method's LOD, so that they are compared by one ruler.
//
// The LOD's surface is sampled as Metro samples it (Cignoni, Rocchini and Scopigno 1998,
// "Metro: measuring error on simplified surfaces", §3: every vertex, plus each face cut
// into m x m similar triangles with one random point in each); each sample carries the
// UV the LOD interpolates there. Its closest point on the original surface (found through
// a bounding volume hierarchy, ClosestTriangles below) gives the original's UV, and the
// sample's error is the Euclidean distance between the two UVs.
//
// Seams. On a UV seam the original has two charts that meet in 3D but not in UV space, so
// "the original's UV at the closest point" is not one value there, and a LOD sample that
// lies a little off the original surface near a seam may find its closest point on the
// other chart: its error is then the distance between the two charts in the texture
// (often most of the texture's width), although the texture there is continuous and the
// picture right. Such samples lie in a band around the seams as wide as the geometric
// error, and they dominate the RMS. Two measures are therefore given, both the same for
// every method:
//  - nearest: the closest point on the nearest original face; among faces whose distance
//    ties with the nearest within tie_tolerance (a seam edge or vertex is as near to both
//    of its charts' faces), the one whose UV is closest to the sample's. The samples that
//    still land on the other chart are counted (`seam_band`).
//  - same chart: the closest point among the original faces of the sample's own chart. A
//    chart is a connected piece of the texture: UV entries used by one face are in one
//    chart. The sample's chart is that of its face's UVs (each LOD corner's UV is one of the
//    original's values, whichever tool made it); a LOD face whose corners come from two
//    charts (a seam not held) has none, and its samples are measured as by `nearest`.
//    This is what the texture shows: a sample is compared with the original's texel at the
//    nearest point where the original shows the same piece of the texture, so a seam that
//    drifts in 3D still counts (the LOD samples the texture beyond the chart's border).
//    It needs the LOD's UVs to be values of the original's: true of pmenc and meshopt, which
//    both keep one of the collapsed edge's wedges; a tool that places new UVs would leave
//    its faces without a chart (UvError::chartless), measured as by `nearest`.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "pm/mesh.h"

namespace pm::bench {

// A point on a mesh's triangle: the face, the barycentric coordinates of the point (weights
// of the face's corners 0, 1, 2) and its distance to the query point.
struct SurfacePoint {
  uint32_t face = 0;
  std::array<double, 3> barycentric{};
  double distance = 0;
};

// A bounding volume hierarchy over a mesh's triangles (binary, median split on the longest
// axis of the face centroids), for closest-point queries. The mesh must outlive it.
class ClosestTriangles {
 public:
  // Over every face of the mesh, or over `faces` only.
  explicit ClosestTriangles(const pm::Mesh& mesh);
  ClosestTriangles(const pm::Mesh& mesh, std::vector<uint32_t> faces);

  // The closest point of the surface to p (Ericson 2005, "Real-Time Collision Detection",
  // §5.1.5). The mesh must have a face.
  SurfacePoint nearest(const std::array<double, 3>& p) const;
  bool empty() const { return faces_.empty(); }
  // Every face within `radius` of p, with its closest point, appended to `out`.
  void within(const std::array<double, 3>& p, double radius, std::vector<SurfacePoint>& out) const;

 private:
  struct Node {
    std::array<double, 3> lo, hi;
    uint32_t first = 0, count = 0;  // leaf: faces_[first, first + count); inner: count 0
    uint32_t left = 0, right = 0;   // inner: children
  };
  uint32_t build(uint32_t first, uint32_t count, std::vector<std::array<double, 3>>& centroids);
  SurfacePoint closest_on_face(uint32_t face, const std::array<double, 3>& p) const;
  void build_all();

  const pm::Mesh& mesh_;
  std::vector<uint32_t> faces_;
  std::vector<Node> nodes_;
};

// The UV charts of a mesh: UV entries used by one face are in one chart (union-find over
// the entries of each face).
struct UvCharts {
  static constexpr uint32_t kNone = 0xFFFFFFFFu;
  std::size_t count = 0;
  std::vector<uint32_t> chart_of_face;  // 0 .. count-1, or kNone for a face without UVs
  // Each UV value used (u, v as stored) to its chart; kNone for a value that two charts use.
  std::map<std::pair<float, float>, uint32_t> chart_of_value;

  // The chart of a UV value, kNone when unknown or shared.
  uint32_t chart_of(float u, float v) const;
  // The chart of another mesh's face, whose corners' UVs are values of this mesh: kNone
  // when a corner has no UV, an unknown or shared value, or when the corners' charts differ.
  uint32_t chart_of_face_of(const pm::Mesh& mesh, std::size_t face) const;
};
UvCharts uv_charts(const pm::Mesh& mesh);

struct UvErrorOptions {
  // Samples in the LOD's faces: this many times the original's face count in all, shared
  // among the LOD's faces by area, so that every method's LOD of a mesh gets the same
  // density whatever its face count. Each face gets m x m samples, m = round(sqrt(its
  // share)), at least 1.
  double samples_per_original_face = 10;
  // Ties with the nearest face (see the file comment), as a fraction of the original's
  // bounding-box diagonal.
  double tie_tolerance = 1e-6;
  // A sample's error counts in `seam_band` when it is at least this (in UV units) and the
  // original face chosen has a seam vertex (one whose corners carry two or more UVs).
  double seam_band_threshold = 0.05;
  uint64_t seed = 1;
  // Called with every sample, to look at where the errors are (may be empty): its position,
  // its UV on the LOD, its error by each rule and the original face each rule chose.
  std::function<void(const std::array<double, 3>& position, const std::array<double, 2>& uv,
                     double nearest_error, uint32_t nearest_face, double same_chart_error,
                     uint32_t same_chart_face)>
      on_sample;
};

struct UvStatistics {
  double rms = 0;  // over the samples, UV units
  double p95 = 0;  // 95th percentile (nearest rank)
  double max = 0;
};

struct UvError {
  UvStatistics nearest;           // closest point on any chart, ties to the closest UV
  UvStatistics same_chart;        // closest point of the sample's own chart
  std::size_t samples = 0;        // LOD vertices (one per distinct position and UV) and face points
  std::size_t ties_resolved = 0;  // nearest: samples whose tie rule chose another face
  std::size_t seam_band = 0;      // nearest: samples counted at a chart jump
  std::size_t chartless = 0;      // samples with no chart of their own (same_chart as nearest)
  std::size_t without_uv = 0;     // samples on LOD faces without UVs (not measured)
};

// Measures the LOD's UV error against the original (one direction: LOD samples to the
// original surface, since the texture is seen on the LOD). Both meshes need UVs; original
// faces with a corner without a UV are never chosen. Returns false with a message when
// the original has no faces with UVs or the LOD has no faces.
bool measure_uv_error(const pm::Mesh& original, const pm::Mesh& lod, const UvErrorOptions& options,
                      UvError& out, std::string* message);

}  // namespace pm::bench
