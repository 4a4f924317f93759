// The distance from removed input vertices to the simplified surface, tracked through the
// collapses (after Klein, Liebich and Straßer 1996, "Mesh reduction with error control",
// who keep the correspondence between the input and the reduced mesh to bound their
// distance): every removed vertex belongs to one face of the current mesh, the nearest
// of the faces that replaced its own, and a collapse is charged the largest distance of
// the points it moves. Quadrics measure a mean; this measures the worst case, which is
// what the Hausdorff distance of a level to the input is made of. Both ways round, as the
// Hausdorff distance is: removed vertices to the new faces, and points of the new faces to
// the input faces around them (the input one-rings of the region's vertices).
#pragma once

#include <cstdint>
#include <vector>

#include "simplify/geometry.h"
#include "simplify/half_edge_mesh.h"
#include "measure/nearest_triangle.h"

namespace pm {

class RemovedPoints {
 public:
  explicit RemovedPoints(const HalfEdgeMesh& mesh);

  // If half-edge h (v -> u) were collapsed, v's faces other than the two at h would
  // replace v's faces, with u in place of v. Returns the larger of: the largest distance
  // from v and the points of v's faces to those faces, and the largest distance from the
  // centroid and edge midpoints of those faces to the input faces around the region.
  double collapse_distance(HalfEdgeMesh::HalfedgeHandle h) const;

  // The same in two steps, the first a lower bound of the result and much cheaper:
  // removed_distance(h) is the largest distance of v and the points of v's faces alone
  // (negative when there is no fan: then collapse_distance is 0); right after it, on the
  // same mesh, collapse_distance_from(h, that) adds the fan's points and returns what
  // collapse_distance(h) would, bit for bit.
  double removed_distance(HalfEdgeMesh::HalfedgeHandle h) const;
  double collapse_distance_from(HalfEdgeMesh::HalfedgeHandle h, double lower) const;

  // Hands v and the points of its faces to the nearest replacing face, and returns the
  // largest distance of a point to its new face (every point, not a subset). Call just
  // before the mesh collapses h. The running maximum of these bounds the distance from
  // every removed input vertex to the current surface: a point's face changes only here.
  double collapse(HalfEdgeMesh::HalfedgeHandle h);

 private:
  static constexpr uint32_t kNone = 0xffffffffu;

  // `slack`: the nearest-triangle searches' rounding margin (BoxedTriangles::slack_for).
  RemovedPoints(const HalfEdgeMesh& mesh, double slack);

  static constexpr int kMaxFan = 128;
  // The faces the points may go to, as (face id, corners after the collapse): first the
  // `moved` faces replacing v's (u in place of v), then u's other faces.
  struct Fan {
    explicit Fan(double slack) : triangles(slack) {}
    int count = 0, moved = 0;
    int face[kMaxFan];
    BoxedTriangles triangles;  // their corners, in the same order
  };
  // False when v has more faces than Fan holds; the simplifier never collapses a vertex
  // of valence above 64, so this does not happen.
  bool make_fan(HalfEdgeMesh::HalfedgeHandle h, Fan& fan) const;
  // Appends to `points` the points of v's faces (the points that move), in list order.
  void gather_points(HalfEdgeMesh::HalfedgeHandle h, std::vector<uint32_t>& points) const;
  // Near the base mesh a face holds thousands of points; measuring an evenly spread
  // subset of kMeasuredPoints keeps a collapse's cost bounded where errors are large
  // anyway. Every point still moves with every collapse.
  static constexpr uint32_t kMeasuredPoints = 512;
  // Fills sampled_: v, then every stride-th of v's faces' points, stride set by their count.
  void sample_points(HalfEdgeMesh::HalfedgeHandle h) const;

  // The input faces around the corners of the fan and, with_samples, around the sampled
  // points, each once, into region_.
  void collect_input_faces(HalfEdgeMesh::HalfedgeHandle h, const Fan& fan,
                           bool with_samples) const;
  // region_triangles_: region_'s faces.
  void build_region() const;

  const HalfEdgeMesh& mesh_;
  std::vector<uint32_t> input_corners_;      // the input's triangles, three vertex ids each
  std::vector<uint32_t> faces_of_begin_;     // per vertex: its input faces in faces_of_
  std::vector<uint32_t> faces_of_;
  std::vector<bool> thin_input_face_;        // BoxedTriangles::is_thin, per input face
  mutable std::vector<uint32_t> region_vertices_;  // scratch: the vertices around them
  mutable std::vector<uint32_t> seen_;             // scratch: a set of the region's faces
  mutable std::vector<uint32_t> region_;     // scratch: input faces of the current query
  mutable BoxedTriangles region_triangles_;  // scratch: their corners
  mutable Fan fan_;                          // scratch: the current query's fan
  mutable int fan_of_ = -1;                  // the half-edge whose fan fan_ holds, or -1
  std::vector<uint32_t> first_;  // per face: first point of its list, kNone if empty
  std::vector<uint32_t> next_;   // per vertex: the next point in its face's list
  // Scratch, kept to avoid reallocation: the points that move, and those measured.
  mutable std::vector<uint32_t> moving_, sampled_;
  mutable std::vector<Vec3> measured_midpoints_;  // of the current query's fan
  mutable std::vector<Vec3> pending_;  // those not settled by the input near the fan's corners
};

}  // namespace pm
