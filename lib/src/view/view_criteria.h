// The refinement criteria of view-dependent progressive meshes (Hoppe 1997, "View-dependent
// refinement of progressive meshes", §3.1 view frustum, §3.2 surface orientation, §3.3
// screen-space geometric error), each with a margin: how far the camera may move before the
// decision can change, for the incremental update (view_update.cpp).
#pragma once

#include <cmath>

#include "pm/selective_refinement.h"

namespace pm::view {

struct Vec {
  double x = 0, y = 0, z = 0;
};
inline Vec operator-(const Vec& a, const Vec& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec operator+(const Vec& a, const Vec& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec operator*(double s, const Vec& a) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(const Vec& a, const Vec& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec cross(const Vec& a, const Vec& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(const Vec& a) { return std::sqrt(dot(a, a)); }
inline Vec vec(const Point3& p) { return {p[0], p[1], p[2]}; }
inline Vec vec(const float* p) { return {p[0], p[1], p[2]}; }

// A camera ready for the tests: an orthonormal frame and the frustum's side planes.
struct Frame {
  Vec eye;
  Vec basis[3];   // right, up, backward (the camera's axes in model space)
  Vec planes[5];  // unit inward normals of planes through the eye: 4 sides, then the front
  double k = 1;   // viewport_height / (2 tan(fov / 2)): pixels per unit at distance 1
  double k_over_tau = 1;
  bool frustum = true, backface = true;
};

// The camera must pass check_camera() and options.pixel_error must be > 0.
Frame make_frame(const ViewCamera& camera, const ViewOptions& options);

struct Decision {
  bool want = false;
  // How far the camera may move before `want` can change (0 when not asked for): the eye
  // alone (eye_motion(), for the screen-space and orientation tests, which do not depend on
  // where the camera looks), and the camera as a whole (motion(), for the frustum). A wanted
  // split stays wanted within both; an unwanted one within the one given (the other is
  // infinite).
  double eye_margin = 0, margin = 0;
};

// Whether the split is wanted: its sphere meets the frustum, its region is not entirely
// back-facing and its projected deviation exceeds the tolerance. With with_margin false the
// margin is not computed (the from-scratch refinement does not need it).
Decision evaluate(const SplitBounds& bounds, const Frame& frame, bool with_margin);

// Whether the box is inside the frustum (frame.frustum not consulted), by a margin that absorbs
// rounding: then so is every box nested in it, and the frustum test passes for them.
bool box_inside_frustum(const Frame& frame, const Point3& lo, const Point3& hi);

// A bound on how much the camera moved between two frames, in model units, such that no
// test value of evaluate() (all 1-Lipschitz in it) changes by more: the eye's displacement
// plus the rotation of the frame times the largest distance from either eye to the model's
// bounding sphere (which must hold every split's box).
double motion(const Frame& from, const Frame& to, const Vec& model_center, double model_radius);
// How far the eye moved (with the same allowance for rounding).
double eye_motion(const Frame& from, const Frame& to, const Vec& model_center, double model_radius);

}  // namespace pm::view
