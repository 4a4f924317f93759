// Hoppe 1997, "View-dependent refinement of progressive meshes", §3: a vertex (here, the split
// that refines it) is refined when its region is inside the view frustum (§3.1), faces the
// viewer (§3.2) and its deviation projected on the screen exceeds a tolerance (§3.3).
//
// Every test is made conservative for the region's bounding sphere and normal cone, and
// monotone up the hierarchy: a parent's sphere holds its children's and its cone holds
// theirs, so a child wanted implies its parent wanted, which the incremental update relies on.
// Each test value is 1-Lipschitz in the camera motion of motion() (after the scaling noted),
// which gives the margins.
#include "view/view_criteria.h"

#include <algorithm>
#include <limits>

namespace pm::view {
namespace {

constexpr double kHalfPi = 1.5707963267948966;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

Vec normalized(const Vec& a) { return (1.0 / length(a)) * a; }

// A lower bound of sin(x) for x >= 0, capped at 1 from pi/2 on: the larger of the chord 2x/pi
// and x - x^3/6 (sin x >= x - x^3/6 for x >= 0), without a call to sin.
double sin_lower(double x) {
  if (x >= kHalfPi) return 1;
  return std::max(x * (1 / kHalfPi), x * (1 - x * x * (1.0 / 6)));
}

// §3.2, surface orientation: the region is back-facing when every direction from the eye to
// the sphere (a cone of half-angle asin(r / distance) around d) makes less than 90 degrees
// minus the normal cone's half-angle with the cone's axis: theta + beta + alpha < pi/2.
// Moving the eye by m < distance - r turns each of those directions by at most
// asin(m / (distance - r)), so the decision holds while that stays below the slack |theta +
// beta + alpha - pi/2|: for m < (distance - r) sin(slack), hence the margin (written to
// `margin` when asked for), with a lower bound of the sine.
bool back_facing(const SplitBounds& b, const Vec& d, double distance, bool with_margin,
                 double& margin) {
  const double r = b.radius;
  if (b.cone_angle >= kHalfPi) return false;  // normals all around: never back-facing
  if (distance <= r) {
    margin = r - distance;  // the eye in the sphere: never back-facing
    return false;
  }
  const Vec axis = vec(b.cone_axis);
  const double cos_theta = std::clamp(dot(axis, d) / distance, -1.0, 1.0);
  const double sin_beta = r / distance;
  if (cos_theta <= 0) {
    // Facing the eye (theta >= 90 degrees), the common case, without trigonometry: the slack
    // theta + beta + alpha - pi/2 is at least asin(-cos theta) + asin(sin beta) + alpha >=
    // -cos theta + sin beta + alpha.
    if (with_margin) margin = sin_lower(-cos_theta + sin_beta + b.cone_angle) * (distance - r);
    return false;
  }
  // theta + beta + alpha < pi/2 <=> cos(theta) > sin(alpha + beta), when alpha + beta < pi/2,
  // that is when cos(alpha + beta) > 0. The sine and cosine of alpha + beta from those of
  // alpha and beta (sin beta = r / distance), without asin.
  const double cos_beta = std::sqrt(std::max(0.0, 1 - sin_beta * sin_beta));
  const double sin_alpha = std::sin(double(b.cone_angle)), cos_alpha = std::cos(double(b.cone_angle));
  const double sin_sum = sin_alpha * cos_beta + cos_alpha * sin_beta;
  const double cos_sum = cos_alpha * cos_beta - sin_alpha * sin_beta;
  const bool back = cos_sum > 0 && cos_theta > sin_sum;
  if (back || with_margin) {
    // The slack is |theta - phi| with phi = pi/2 - alpha - beta, and the margin (distance - r)
    // sin(slack) up to pi/2: |sin(theta - phi)| = |sin theta cos phi - cos theta sin phi|,
    // with cos phi = sin(alpha + beta), sin phi = cos(alpha + beta); beyond pi/2 it is less
    // than sin(slack) would allow, still a margin. No acos.
    const double sin_theta = std::sqrt(std::max(0.0, 1 - cos_theta * cos_theta));
    margin = std::fabs(sin_theta * sin_sum - cos_theta * cos_sum) * (distance - r);
  }
  return back;
}

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
  // Each test gives a value whose sign decides, and a margin: |value| over its Lipschitz
  // constant in camera motion. Wanted only when all three pass.

  // §3.3, screen-space error: deviation * k / (distance - r) > tau, i.e. the eye is nearer than
  // deviation * k / tau + r. The value moves with the eye's distance: 1-Lipschitz in the eye.
  const double near = double(b.deviation) * f.k_over_tau + r - distance;
  if (!(near > 0)) return {false, with_margin ? std::fabs(near) : 0, kInfinity};

  double facing_margin = kInfinity;
  if (f.backface && back_facing(b, d, distance, with_margin, facing_margin))
    return {false, facing_margin, kInfinity};

  // §3.1, view frustum: the split's box is not entirely outside any plane through the eye (its
  // farthest point along the plane's normal is on the inner side). The planes turn with the
  // camera: each value is 1-Lipschitz in motion().
  double outside = kInfinity;
  if (f.frustum) {
    const Vec lo = vec(b.box_lo), hi = vec(b.box_hi);
    const Vec middle = 0.5 * (lo + hi) - f.eye, half = 0.5 * (hi - lo);
    for (const Vec& n : f.planes)
      outside = std::min(outside, dot(n, middle) + std::fabs(n.x) * half.x +
                                      std::fabs(n.y) * half.y + std::fabs(n.z) * half.z);
    if (outside < 0) return {false, kInfinity, with_margin ? -outside : 0};
  }
  if (!with_margin) return {true, 0, 0};
  return {true, std::min(near, facing_margin), outside};
}

bool box_inside_frustum(const Frame& f, const Point3& lo, const Point3& hi) {
  const Vec middle = 0.5 * (vec(lo) + vec(hi)) - f.eye, half = 0.5 * (vec(hi) - vec(lo));
  const double slack = 1e-9 * (length(middle) + length(half));
  for (const Vec& n : f.planes)
    if (!(dot(n, middle) - std::fabs(n.x) * half.x - std::fabs(n.y) * half.y -
              std::fabs(n.z) * half.z >= slack))
      return false;
  return true;
}

double motion(const Frame& from, const Frame& to, const Vec& model_center, double model_radius) {
  const double moved = length(to.eye - from.eye);
  // Each plane normal turns with the camera's frame R: |n_to - n_from| <= 2 sin(angle / 2) for
  // the angle of the rotation R_to R_from^T, and ||R_to - R_from||_F = 2 sqrt(2) sin(angle / 2)
  // for any rotation, so |n_to - n_from| <= ||R_to - R_from||_F / sqrt(2).
  double turned2 = 0;
  for (int i = 0; i < 3; ++i) {
    const Vec delta = to.basis[i] - from.basis[i];
    turned2 += dot(delta, delta);
  }
  const double reach = std::max(length(model_center - from.eye), length(model_center - to.eye)) +
                       model_radius;
  const double m = moved + std::sqrt(0.5 * turned2) * reach;
  // Rounding in the tests' values: a little more motion than measured.
  return m * (1 + 1e-9) + 1e-12 * (reach + 1);
}

double eye_motion(const Frame& from, const Frame& to, const Vec& model_center, double model_radius) {
  const double reach = std::max(length(model_center - from.eye), length(model_center - to.eye)) +
                       model_radius;
  return length(to.eye - from.eye) * (1 + 1e-9) + 1e-12 * (reach + 1);
}

}  // namespace pm::view
