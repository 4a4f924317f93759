// Hoppe 1997, "View-dependent refinement of progressive meshes", §3: a vertex (here, the split
// that refines it) is refined when its region is inside the view frustum (§3.1), faces the
// viewer (§3.2) and its deviation projected on the screen exceeds a tolerance (§3.3).
//
// Every test is made conservative for the region's bounding sphere and normal cone, and
// monotone up the hierarchy: a parent's sphere holds its children's and its cone holds
// theirs, so a child wanted implies its parent wanted, which the incremental update relies on.
// Each test value is 1-Lipschitz in the camera motion of motion() (after the scaling noted),
// which gives the margins.
#include "view_criteria.h"

#include <algorithm>
#include <limits>

namespace pm::view {
namespace {

constexpr double kHalfPi = 1.5707963267948966;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

Vec normalized(const Vec& a) { return (1.0 / length(a)) * a; }

}  // namespace

Frame make_frame(const ViewCamera& camera, const ViewOptions& options) {
  Frame f;
  f.eye = vec(camera.eye);
  const Vec forward = normalized(vec(camera.target) - f.eye);
  const Vec right = normalized(cross(forward, vec(camera.up)));
  const Vec up = cross(right, forward);
  f.basis[0] = right;
  f.basis[1] = up;
  f.basis[2] = -1.0 * forward;
  const double half_fov = 0.5 * camera.fov_degrees * 3.14159265358979323846 / 180.0;
  const double width = camera.viewport_width > 0 ? camera.viewport_width : camera.viewport_height;
  const double half_fov_x = std::atan(std::tan(half_fov) * width / camera.viewport_height);
  // A side plane holds the eye and one edge of the image: its inward normal leans from the
  // edge's axis toward the view direction.
  const double sy = std::sin(half_fov), cy = std::cos(half_fov);
  const double sx = std::sin(half_fov_x), cx = std::cos(half_fov_x);
  f.planes[0] = sy * forward + (-cy) * up;  // top
  f.planes[1] = sy * forward + cy * up;     // bottom
  f.planes[2] = sx * forward + (-cx) * right;  // right
  f.planes[3] = sx * forward + cx * right;     // left
  f.planes[4] = forward;                       // in front of the eye
  f.k = camera.viewport_height / (2 * std::tan(half_fov));
  f.k_over_tau = f.k / options.pixel_error;
  f.frustum = options.frustum_culling;
  f.backface = options.backface_culling;
  return f;
}

Decision evaluate(const SplitBounds& b, const Frame& f, bool with_margin) {
  const Vec d = vec(b.center) - f.eye;
  const double distance = length(d);
  const double r = b.radius;
  // Each test: a value whose sign decides, and the margin it gives (|value| over its
  // Lipschitz constant in camera motion). Wanted only when all three pass.
  bool want = true;
  double pass_margin = kInfinity, fail_margin = 0;
  auto record = [&](bool pass, double margin) {
    if (pass) {
      pass_margin = std::min(pass_margin, margin);
    } else {
      want = false;
      fail_margin = std::max(fail_margin, margin);
    }
  };

  // §3.3, screen-space error: deviation * k / (distance - r) > tau, i.e. the eye is nearer than
  // deviation * k / tau + r. The value moves with the eye's distance: 1-Lipschitz.
  const double near = double(b.deviation) * f.k_over_tau + r - distance;
  record(near > 0, std::fabs(near));

  // §3.1, view frustum: the sphere is not entirely outside any plane through the eye.
  if (f.frustum) {
    double outside = kInfinity;
    for (const Vec& n : f.planes) outside = std::min(outside, dot(n, d) + r);
    record(outside >= 0, std::fabs(outside));
  }
  // One failed test is enough: its margin bounds the decision's.
  if (!want) return {false, with_margin ? fail_margin : 0};

  // §3.2, surface orientation: the region is back-facing when every direction from the eye to
  // the sphere (a cone of half-angle asin(r / distance) around d) makes less than 90 degrees
  // minus the normal cone's half-angle with the cone's axis: theta + beta + alpha < pi/2.
  // Moving the eye by m turns each of those directions by at most asin(m / (distance - r)) <=
  // (pi/2) m / (distance - r), hence the margin.
  if (f.backface && b.cone_angle < kHalfPi) {
    if (distance <= r) {
      record(true, r - distance);  // the eye in the sphere: never back-facing
    } else {
      const Vec axis = vec(b.cone_axis);
      const double cos_theta = std::clamp(dot(axis, d) / distance, -1.0, 1.0);
      const double angle = std::acos(cos_theta) + std::asin(r / distance) + b.cone_angle;
      const double slack = angle - kHalfPi;  // > 0: some of it faces the eye
      const double margin = std::min(std::fabs(slack) / kHalfPi, 1.0) * (distance - r);
      record(slack >= 0, margin);
    }
  }
  if (!with_margin) return {want, 0};
  return {want, want ? pass_margin : fail_margin};
}

double motion(const Frame& from, const Frame& to, const Vec& model_center, double model_radius) {
  const double moved = length(to.eye - from.eye);
  // |n_to - n_from| <= ||R_to - R_from||_2 <= ||R_to - R_from||_F for each plane normal n = R s.
  double turned2 = 0;
  for (int i = 0; i < 3; ++i) {
    const Vec delta = to.basis[i] - from.basis[i];
    turned2 += dot(delta, delta);
  }
  const double reach = std::max(length(model_center - from.eye), length(model_center - to.eye)) +
                       model_radius;
  const double m = moved + std::sqrt(turned2) * reach;
  // Rounding in the tests' values: a little more motion than measured.
  return m * (1 + 1e-9) + 1e-12 * (reach + 1);
}

}  // namespace pm::view
