// Closed-form ground truth for one box and a sphere or box tool. The box
// geometry is written out here rather than taken from shape_signed_distance,
// so the reference stays independent of the code the algorithms use.
// Quaternions in the order qw,qx,qy,qz; units m, N, N·m, rad, J.
#include "harness/reference/analytic_reference.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "algorithms/contact/frictional_contact_solver.h"  // perpendicular_unit

namespace hb {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

double positive_part(double value) { return value > 0 ? value : 0; }

// ---------------------------------------------------------------------------
// Sphere tool

// Signed distance (m) from a point to a box centred on its frame: negative
// inside, where it is minus the distance to the nearest face.
double box_signed_distance(const Vec3& half_extents, const Vec3& point) {
  const Vec3 clamped = point.cwiseMax(-half_extents).cwiseMin(half_extents);
  const Vec3 outside = point - clamped;
  if (outside.squaredNorm() > 0) return outside.norm();
  return -(half_extents - point.cwiseAbs()).minCoeff();
}

// The nearest point at distance exactly `radius` from the box (box frame),
// for a point at distance < radius, and the outward unit normal there.
struct RoundedBoxProjection {
  Vec3 point;
  Vec3 normal;
};

RoundedBoxProjection project_onto_rounded_box(const Vec3& half_extents, double radius,
                                              const Vec3& point) {
  const Vec3 clamped = point.cwiseMax(-half_extents).cwiseMin(half_extents);
  const Vec3 outside = point - clamped;
  const double distance = outside.norm();
  if (distance > 0) {
    // Outside the box: the nearest box point is the clamped one, and the
    // grown surface lies `radius` further along the same direction (on a
    // face, an edge's cylinder or a corner's sphere, as the clamping decides).
    const Vec3 normal = outside / distance;
    return {clamped + radius * normal, normal};
  }
  // Inside (or on) the box: for every unit direction n the grown box reaches
  // sum_i h_i |n_i| + r − n·c ≥ min_i (h_i − |c_i|) + r beyond c, with
  // equality along the nearest face's normal, so leave through that face.
  int axis = 0;
  (half_extents - point.cwiseAbs()).minCoeff(&axis);
  const double side = point[axis] >= 0 ? 1.0 : -1.0;
  Vec3 projected = point;
  projected[axis] = side * (half_extents[axis] + radius);
  Vec3 normal = Vec3::Zero();
  normal[axis] = side;
  return {projected, normal};
}

IdealRendering sphere_rendering(const AnalyticScene& scene, const Pose& device) {
  IdealRendering rendering;
  rendering.proxy = device;
  rendering.device_penetration_m = exact_penetration_depth(scene, device);
  if (!(rendering.device_penetration_m > 0)) return rendering;

  const Vec3 centre_in_box = scene.box_pose.inverse_transform_point(device.p);
  const RoundedBoxProjection projection =
      project_onto_rounded_box(scene.box_half_extents, scene.tool_shape.radius, centre_in_box);
  rendering.proxy.p = scene.box_pose.transform_point(projection.point);
  rendering.in_contact = true;
  rendering.contact_normal = scene.box_pose.q * projection.normal;
  rendering.display.force = scene.coupling.k_t * (rendering.proxy.p - device.p);
  return rendering;  // the orientation follows the device: no torque
}

// ---------------------------------------------------------------------------
// Box tool against one face plane of the scene box
//
// With the face's outward normal n and the tool's orientation R, the lowest
// tool vertex sits s(u) = sum_i t_i |u_i| below the tool origin along n,
// where u = Rᵀ n and t are the tool's half extents. For a given u:
//   - the best translation lifts the device's origin along n by
//     push = (c + s(u))₊, with c = n·(face point − x_h);
//   - the nearest orientation to the device's with Rᵀ n = u is R = R_h Q,
//     Q the minimal rotation taking u to u_h = R_hᵀ n, whose angle is the
//     angle between u and u_h.
// So the energy is G(u) = ½ k_T push² + ½ k_R ∠(u, u_h)² over the unit sphere.
// Flipping a component of u whose sign differs from u_h's keeps s(u) and
// brings u nearer u_h, so the minimiser lies in u_h's closed octant, where
// s(u) = w·u with w_i = sign_i t_i. There, a minimiser is either interior
// (a stationary point, where w, u_h and u are coplanar: u lies on the great
// circle through u_h and w), on one of the three octant edges (u_i = 0), or
// at one of its three corners.

struct FaceOptimum {
  double energy_j = kInfinity;
  Vec3 u = Vec3::Zero();  // face normal in tool coordinates at the optimum
};

struct ArcMinimum {
  double parameter = 0;
  double energy_j = kInfinity;
};

// Smallest value of `energy` over the admissible local minima of a smooth
// function on [lower, upper]: the ends (when admissible) and every root where
// `slope` turns from negative to non-negative between two of `samples`
// samples, narrowed by bisection until the bracket cannot shrink further.
template <class Energy, class Slope, class Admissible>
ArcMinimum minimise_on_arc(const Energy& energy, const Slope& slope, const Admissible& admissible,
                           double lower, double upper, int samples) {
  ArcMinimum best;
  auto consider = [&](double parameter) {
    if (!admissible(parameter)) return;
    const double value = energy(parameter);
    if (value < best.energy_j) best = {parameter, value};
  };
  consider(lower);
  consider(upper);
  double previous = lower;
  double previous_slope = slope(lower);
  for (int k = 1; k <= samples; ++k) {
    const double current = lower + (upper - lower) * k / samples;
    const double current_slope = slope(current);
    if (previous_slope < 0 && current_slope >= 0) {
      double left = previous;
      double right = current;
      for (int iteration = 0; iteration < 200; ++iteration) {
        const double middle = 0.5 * (left + right);
        if (middle <= left || middle >= right) break;
        (slope(middle) < 0 ? left : right) = middle;
      }
      consider(left);
      consider(right);
    }
    previous = current;
    previous_slope = current_slope;
  }
  return best;
}

// Angle (rad) between two unit vectors, accurate near 0.
double angle_between(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// angle / sin(angle), finite at 0.
double angle_over_sine(double angle) {
  if (angle < 1e-4) return 1.0 + angle * angle / 6.0;
  return angle / std::sin(angle);
}

FaceOptimum minimise_over_octant(const Vec3& device_u, const Vec3& tool_half_extents,
                                 double lift_needed_at_origin, double k_t, double k_r) {
  constexpr int kSamples = 128;
  constexpr double kHalfPi = 0.5 * std::numbers::pi;
  const double c = lift_needed_at_origin;
  Vec3 signs;
  for (int i = 0; i < 3; ++i) signs[i] = device_u[i] >= 0 ? 1.0 : -1.0;
  const Vec3 w = signs.cwiseProduct(tool_half_extents);
  auto in_octant = [&](const Vec3& u) { return (signs.cwiseProduct(u).array() >= -1e-14).all(); };
  auto energy_of = [&](const Vec3& u, double angle) {
    const double push = positive_part(c + w.dot(u));
    return 0.5 * k_t * push * push + 0.5 * k_r * angle * angle;
  };
  FaceOptimum best;
  auto keep = [&](const Vec3& u, double energy) {
    if (energy < best.energy_j) best = {energy, u};
  };

  // Interior candidates: the great circle u(t) = cos t u_h + sin t e through
  // u_h and w, where the angle to u_h is |t| (≤ π/2 inside the octant).
  Vec3 e = w - w.dot(device_u) * device_u;
  if (e.norm() <= 1e-12 * w.norm()) {
    // w ∥ u_h: the energy depends on the angle alone, any great circle through u_h will do.
    e = device_u.unitOrthogonal();
  }
  e.normalize();
  {
    auto u_at = [&](double t) { return Vec3(std::cos(t) * device_u + std::sin(t) * e); };
    auto energy = [&](double t) { return energy_of(u_at(t), t); };
    auto slope = [&](double t) {
      const Vec3 u = u_at(t);
      const Vec3 du = -std::sin(t) * device_u + std::cos(t) * e;
      return k_t * positive_part(c + w.dot(u)) * w.dot(du) + k_r * t;
    };
    auto admissible = [&](double t) { return in_octant(u_at(t)); };
    const ArcMinimum minimum =
        minimise_on_arc(energy, slope, admissible, -kHalfPi, kHalfPi, 2 * kSamples);
    if (minimum.energy_j < kInfinity) keep(u_at(minimum.parameter), minimum.energy_j);
  }

  // Octant edges u_i = 0: u(ψ) = cos ψ sign_j e_j + sin ψ sign_k e_k, ψ ∈ [0, π/2];
  // their ends are the octant's corners.
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    const int k = (i + 2) % 3;
    auto u_at = [&](double psi) {
      Vec3 u = Vec3::Zero();
      u[j] = signs[j] * std::cos(psi);
      u[k] = signs[k] * std::sin(psi);
      return u;
    };
    auto energy = [&](double psi) {
      const Vec3 u = u_at(psi);
      return energy_of(u, angle_between(u, device_u));
    };
    auto slope = [&](double psi) {
      const Vec3 u = u_at(psi);
      Vec3 du = Vec3::Zero();
      du[j] = -signs[j] * std::sin(psi);
      du[k] = signs[k] * std::cos(psi);
      const double angle = angle_between(u, device_u);
      // d(½ angle²)/dψ = angle · d(angle)/dψ = −(angle / sin angle) (du · u_h)
      return k_t * positive_part(c + w.dot(u)) * w.dot(du) -
             k_r * angle_over_sine(angle) * du.dot(device_u);
    };
    auto always = [](double) { return true; };
    const ArcMinimum minimum = minimise_on_arc(energy, slope, always, 0.0, kHalfPi, kSamples);
    keep(u_at(minimum.parameter), minimum.energy_j);
  }
  return best;
}

// Half extents of a box shape (full extents in Shape::size).
Vec3 half_extents_of(const Shape& box) { return 0.5 * box.size; }

IdealRendering box_tool_rendering(const AnalyticScene& scene, const Pose& device) {
  IdealRendering rendering;
  rendering.proxy = device;
  rendering.device_penetration_m = exact_penetration_depth(scene, device);
  if (!(rendering.device_penetration_m > 0)) return rendering;

  const double k_t = scene.coupling.k_t;
  const double k_r = scene.coupling.k_r;
  const Vec3 tool_half = half_extents_of(scene.tool_shape);
  const Mat3 box_axes = scene.box_pose.q.toRotationMatrix();
  const Mat3 device_axes = device.q.toRotationMatrix();

  // The tool overlaps the box, so it crosses every face plane: solve each
  // face's half-space problem and keep the lowest energy. Since
  // s(u) = sum_i t_i |u_i| ≥ min_i t_i, a face needing the lift c has energy
  // ≥ ½ k_T (c + min_i t_i)₊²; faces are visited by increasing c and skipped
  // once that bound cannot beat the best found.
  struct FacePlane {
    Vec3 normal;
    double offset;  // n · (a point of the face), m
    double lift;    // c = offset − n · x_h, m
  };
  std::array<FacePlane, 6> faces;
  for (int face = 0; face < 6; ++face) {
    const int axis = face / 2;
    const Vec3 normal = (face % 2 == 0 ? 1.0 : -1.0) * box_axes.col(axis);
    const double offset = normal.dot(scene.box_pose.p) + scene.box_half_extents[axis];
    faces[face] = {normal, offset, offset - normal.dot(device.p)};
  }
  std::stable_sort(faces.begin(), faces.end(),
                   [](const FacePlane& a, const FacePlane& b) { return a.lift < b.lift; });
  const double thinnest_half = tool_half.minCoeff();
  double best_energy = kInfinity;
  const FacePlane* best_face = &faces.front();
  Vec3 best_u = Vec3::Zero();
  for (const FacePlane& face : faces) {
    const double least_push = positive_part(face.lift + thinnest_half);
    if (0.5 * k_t * least_push * least_push >= best_energy) continue;
    const FaceOptimum optimum =
        minimise_over_octant(device_axes.transpose() * face.normal, tool_half, face.lift, k_t, k_r);
    if (optimum.energy_j < best_energy) {
      best_energy = optimum.energy_j;
      best_face = &face;
      best_u = optimum.u;
    }
  }
  const Vec3 best_normal = best_face->normal;
  const double best_face_offset = best_face->offset;

  // Orientation: R_p = R_h Q with Q the minimal rotation taking u to u_h.
  const Vec3 device_u = device_axes.transpose() * best_normal;
  const Vec3 swing_axis = best_u.cross(device_u);
  const double swing_norm = swing_axis.norm();
  Quat swing = Quat::Identity();
  if (swing_norm > 0) {
    swing = quat_from_rotation_vector(swing_axis / swing_norm * angle_between(best_u, device_u));
  }
  rendering.proxy.q = (device.q * swing).normalized();
  // Translation: lift the device's origin along n until the lowest vertex of
  // the proxy's actual orientation touches the plane.
  const Vec3 proxy_u = rendering.proxy.q.conjugate() * best_normal;
  const double support_below = tool_half.dot(proxy_u.cwiseAbs());
  const double push = positive_part(best_face_offset + support_below - best_normal.dot(device.p));
  rendering.proxy.p = device.p + push * best_normal;

  rendering.in_contact = true;
  rendering.contact_normal = best_normal;
  rendering.display.force = k_t * (rendering.proxy.p - device.p);
  rendering.display.torque = -k_r * rotation_vector(device.q * rendering.proxy.q.conjugate());
  return rendering;
}

// ---------------------------------------------------------------------------
// Box-box penetration depth by separating axes

double box_box_penetration_depth(const Pose& a_pose, const Vec3& a_half, const Pose& b_pose,
                                 const Vec3& b_half) {
  const Mat3 a_axes = a_pose.q.toRotationMatrix();
  const Mat3 b_axes = b_pose.q.toRotationMatrix();
  const Vec3 between = b_pose.p - a_pose.p;
  double depth = kInfinity;
  auto test_axis = [&](const Vec3& axis) {
    const double reach = a_half.dot((a_axes.transpose() * axis).cwiseAbs()) +
                         b_half.dot((b_axes.transpose() * axis).cwiseAbs());
    depth = std::min(depth, reach - std::abs(axis.dot(between)));
  };
  for (int i = 0; i < 3; ++i) {
    test_axis(a_axes.col(i));
    test_axis(b_axes.col(i));
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const Vec3 cross = a_axes.col(i).cross(b_axes.col(j));
      const double length = cross.norm();
      if (length > 1e-9) test_axis(cross / length);
    }
  }
  return positive_part(depth);
}

}  // namespace

std::optional<AnalyticScene> make_analytic_scene(const RenderContext& context,
                                                 std::string* reason_not_covered) {
  auto not_covered = [&](const std::string& why) -> std::optional<AnalyticScene> {
    if (reason_not_covered) *reason_not_covered = why;
    return std::nullopt;
  };
  if (context.scene.size() != 1) {
    return not_covered("the scene has " + std::to_string(context.scene.size()) +
                       " objects; the closed forms need exactly one box");
  }
  const SceneObject& object = context.scene.front();
  if (!object.shape) {
    return not_covered("scene object '" + object.name +
                       "' is a mesh; the closed forms need a primitive box");
  }
  if (object.shape->type != ShapeType::kBox) {
    return not_covered("scene object '" + object.name + "' is a " +
                       shape_type_name(object.shape->type) +
                       "; the closed forms need a primitive box");
  }
  if (!(object.shape->size.array() > 0).all() || !object.shape->size.allFinite()) {
    return not_covered("scene object '" + object.name + "' has a non-positive box size");
  }
  const Tool& tool = context.tool;
  if (!tool.shape)
    return not_covered("the tool is a mesh; the closed forms need a sphere or a box");
  const ShapeType tool_type = tool.shape->type;
  if (tool_type != ShapeType::kSphere && tool_type != ShapeType::kBox) {
    return not_covered("the tool is a " + shape_type_name(tool_type) +
                       "; the closed forms need a sphere or a box");
  }
  if (tool_type == ShapeType::kSphere &&
      !(tool.shape->radius > 0 && std::isfinite(tool.shape->radius))) {
    return not_covered("the tool sphere has a non-positive radius");
  }
  if (tool_type == ShapeType::kBox &&
      (!(tool.shape->size.array() > 0).all() || !tool.shape->size.allFinite())) {
    return not_covered("the tool box has a non-positive size");
  }
  if (context.gravity.squaredNorm() > 0) {
    return not_covered(
        "gravity is set; the quasi-static rendering would depend on each algorithm's proxy mass");
  }
  if (!(context.coupling.k_t > 0 && std::isfinite(context.coupling.k_t))) {
    return not_covered("the coupling stiffness k_t is not positive");
  }
  if (tool_type == ShapeType::kBox &&
      !(context.coupling.k_r > 0 && std::isfinite(context.coupling.k_r))) {
    return not_covered(
        "the rotational coupling stiffness k_r is not positive, so a box tool's ideal "
        "orientation is undetermined");
  }

  AnalyticScene scene;
  scene.box_pose = object.pose;
  scene.box_pose.q.normalize();
  scene.box_half_extents = half_extents_of(*object.shape);
  scene.tool_shape = *tool.shape;
  scene.tool_centre_of_mass = tool.mass.centre_of_mass;
  scene.coupling = context.coupling;
  scene.friction = object.friction;
  return scene;
}

IdealRendering ideal_rigid_contact(const AnalyticScene& scene, const Pose& device) {
  if (scene.tool_shape.type == ShapeType::kSphere) return sphere_rendering(scene, device);
  return box_tool_rendering(scene, device);
}

IdealRendering FrictionalContactReference::update(const Pose& device) {
  IdealRendering rendering = ideal_rigid_contact(scene_, device);
  sticking_ = false;
  if (scene_.friction == 0) return rendering;
  const Vec3 n = rendering.contact_normal;
  // One face: the normal is a box axis (a sphere on a rounded edge or corner
  // has a normal between axes).
  const bool on_face =
      rendering.in_contact && (scene_.box_pose.q.conjugate() * n).cwiseAbs().maxCoeff() > 1 - 1e-12;
  if (!on_face) {
    last_proxy_p_.reset();
    return rendering;
  }
  const double normal_force = n.dot(rendering.display.force);  // N, ≥ 0: the face pushes
  const double k_t = scene_.coupling.k_t;
  Vec3 offset = Vec3::Zero();  // m, ⟂ n: the proxy's place on the face relative to p₀
  if (last_proxy_p_ && last_normal_.dot(n) > 1 - 1e-12) {
    const Vec3 kept = *last_proxy_p_ - rendering.proxy.p;
    offset = kept - n.dot(kept) * n;
  }
  const double limit_m = scene_.friction * std::max(normal_force, 0.0) / k_t;
  const bool sphere = scene_.tool_shape.type == ShapeType::kSphere;
  if (sphere && last_proxy_p_ && last_normal_.dot(n) > 1 - 1e-12) {
    // A sticking sphere may still roll and spin about its contact point
    // (no point of it slides): the pose that minimises the coupling energy
    // among those rolled from the last one.
    const Pose rolled = rolled_sphere(
        *last_proxy_p_ - n.dot(*last_proxy_p_ - rendering.proxy.p) * n, last_proxy_q_, n, device);
    const Vec3 pull = k_t * (rolled.p - device.p);
    if ((pull - n.dot(pull) * n).norm() <= scene_.friction * std::max(normal_force, 0.0)) {
      sticking_ = true;
      rendering.proxy = rolled;
      rendering.display.force = pull;
      rendering.display.torque =
          -scene_.coupling.k_r * rotation_vector(device.q * rolled.q.conjugate());
      last_proxy_p_ = rolled.p;
      last_proxy_q_ = rolled.q;
      return rendering;
    }
  }
  const double length = offset.norm();
  sticking_ = length <= limit_m;  // a sphere gets here sticking only at its first touch
  if (length > limit_m) offset *= limit_m / length;
  rendering.proxy.p += offset;
  rendering.display.force += k_t * offset;
  if (sphere) {
    // The friction acts at the contact point, r below the centre along −n:
    // its moment about the tool origin (the centre), which the proxy's
    // rotational coupling balances by turning: θ(q_h q_p⁻¹) = −τ / k_R.
    // (A sphere's normal force has no moment.)
    const Vec3 moment = (-scene_.tool_shape.radius * n).cross(k_t * offset);
    rendering.display.torque += moment;
    if (scene_.coupling.k_r > 0)
      rendering.proxy.q =
          (quat_from_rotation_vector(moment / scene_.coupling.k_r) * rendering.proxy.q)
              .normalized();
  }
  last_proxy_p_ = rendering.proxy.p;
  last_proxy_q_ = rendering.proxy.q;
  last_normal_ = n;
  return rendering;
}

// The sphere rolled from (p, q) on the face with unit normal n: turned by
// φ = (n × Δ) / r + s n while its centre moves by Δ ⟂ n, so that the point
// touching the face does not slide (rolling and spinning only). Minimises
// ½ k_T |p' − p_h|² + ½ k_R |θ(q_h q'⁻¹)|² over (Δ, s) by Gauss–Newton
// steps (the energy is quadratic to first order in the rotation; three
// unknowns, converged to rounding in a few steps).
Pose FrictionalContactReference::rolled_sphere(const Vec3& p, const Quat& q, const Vec3& n,
                                               const Pose& device) const {
  const double r = scene_.tool_shape.radius;
  const Vec3 u = perpendicular_unit(n), v = n.cross(u);
  const double sk_t = std::sqrt(scene_.coupling.k_t), sk_r = std::sqrt(scene_.coupling.k_r);
  const auto pose_at = [&](const Vec3& x) {
    const Vec3 shift = x[0] * u + x[1] * v;
    return Pose{p + shift,
                (quat_from_rotation_vector(n.cross(shift) / r + x[2] * n) * q).normalized()};
  };
  const auto residual = [&](const Vec3& x) {
    const Pose at = pose_at(x);
    Vec6 e;
    e << sk_t * (at.p - device.p), sk_r * rotation_vector(device.q * at.q.conjugate());
    return e;
  };
  Vec3 x = Vec3::Zero();
  for (int iteration = 0; iteration < 20; ++iteration) {
    const Vec6 e = residual(x);
    Eigen::Matrix<double, 6, 3> jacobian;
    for (int k = 0; k < 3; ++k) {
      Vec3 h = Vec3::Zero();
      h[k] = 1e-7 * (k < 2 ? r : 1.0);
      jacobian.col(k) = (residual(x + h) - residual(x - h)) / (2 * h[k]);
    }
    const Vec3 step = -(jacobian.transpose() * jacobian).ldlt().solve(jacobian.transpose() * e);
    x += step;
    if (step.head<2>().norm() < 1e-13 && std::abs(step[2]) < 1e-12) break;
  }
  return pose_at(x);
}

double exact_penetration_depth(const AnalyticScene& scene, const Pose& tool_pose) {
  if (scene.tool_shape.type == ShapeType::kSphere) {
    const Vec3 centre_in_box = scene.box_pose.inverse_transform_point(tool_pose.p);
    return positive_part(scene.tool_shape.radius -
                         box_signed_distance(scene.box_half_extents, centre_in_box));
  }
  return box_box_penetration_depth(scene.box_pose, scene.box_half_extents, tool_pose,
                                   half_extents_of(scene.tool_shape));
}

namespace {

// Whether the segment a–b (box frame) meets the box |x_i| ≤ h_i (slabs).
bool segment_meets_box(const Vec3& a, const Vec3& b, const Vec3& h) {
  double enter = 0, leave = 1;
  const Vec3 d = b - a;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0) {
      if (std::abs(a[i]) > h[i]) return false;
      continue;
    }
    double t0 = (-h[i] - a[i]) / d[i], t1 = (h[i] - a[i]) / d[i];
    if (t0 > t1) std::swap(t0, t1);
    enter = std::max(enter, t0);
    leave = std::min(leave, t1);
    if (enter > leave) return false;
  }
  return true;
}

}  // namespace

bool BoxTunnellingDetector::update(const Vec3& origin_world) {
  if (!origin_world.allFinite()) return false;
  const Vec3 p = scene_.box_pose.inverse_transform_point(origin_world);
  const Vec3 h = scene_.box_half_extents;
  const Vec3 gap = p - p.cwiseMax(-h).cwiseMin(h);
  const double distance = gap.norm();
  if (!(distance > 0)) {  // inside or on the surface: wait for it to come out
    last_tick_outside_ = false;
    return false;
  }
  const Vec3 side = gap / distance;
  bool passed = false;
  if (last_point_) {
    // Consecutive ticks outside: any straight path through the solid
    // (deeper than kTunnellingDepthM) counts, a corner cut included.
    // After ticks inside: only a crossing to the other side.
    const Vec3 shrunk = (h.array() - kTunnellingDepthM).cwiseMax(0.0).matrix();
    passed = (last_tick_outside_ && segment_meets_box(*last_point_, p, shrunk)) ||
             (last_side_.dot(side) < 0 && segment_meets_box(*last_point_, p, h));
  }
  last_point_ = p;
  last_side_ = side;
  last_tick_outside_ = true;
  return passed;
}

}  // namespace hb
