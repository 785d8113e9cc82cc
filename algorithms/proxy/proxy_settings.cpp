#include "hapticbench/proxy/proxy_settings.h"

#include <Eigen/Eigenvalues>
#include <limits>

#include "hapticbench/input_error.h"

namespace hb {

namespace {
constexpr double kLargest = std::numeric_limits<double>::max();
}  // namespace

ProxySettings read_proxy_settings(const ParamSet& params, const Tool& tool) {
  ProxySettings settings;
  const std::string integrator =
      params.choice("integrator", "implicit_euler", {"explicit_euler", "implicit_euler"});
  settings.integrator = integrator == "explicit_euler" ? IntegratorKind::kExplicitEuler
                                                       : IntegratorKind::kImplicitEuler;
  settings.proxy_mass_kg = read_proxy_mass(params, tool);
  return settings;
}

double read_proxy_mass(const ParamSet& params, const Tool& tool) {
  const double mass_kg = params.number("proxy_mass_kg", tool.mass.mass_kg, 0, kLargest);
  if (!(mass_kg > 0)) {
    throw InputError("", params.field("proxy_mass_kg"),
                     params.has("proxy_mass_kg")
                         ? "expected a mass > 0 kg"
                         : "the tool's mass is not positive; set a proxy mass > 0 kg");
  }
  return mass_kg;
}

PenaltyGains read_penalty_gains(const ParamSet& params) {
  PenaltyGains gains;
  gains.stiffness = read_contact_stiffness(params);
  gains.damping = params.number("contact_damping", 2, 0, kLargest);
  return gains;
}

double read_contact_stiffness(const ParamSet& params) {
  return params.number("contact_stiffness", 3000, 0, kLargest);
}

RigidBody proxy_body(const Tool& tool, double proxy_mass_kg, const Vec3& gravity) {
  RigidBody body;
  body.mass_kg = proxy_mass_kg;
  body.centre_of_mass = tool.mass.centre_of_mass;
  body.gravity = gravity;
  const Mat3 inertia =
      0.5 * (tool.mass.inertia_about_com + tool.mass.inertia_about_com.transpose());
  const double smallest =
      Eigen::SelfAdjointEigenSolver<Mat3>(inertia, Eigen::EigenvaluesOnly).eigenvalues().minCoeff();
  if (!(tool.mass.mass_kg > 0) || !(smallest > 0) || !inertia.allFinite()) {
    throw InputError("", "/tool",
                     "the tool needs a positive mass and a positive definite inertia for a "
                     "proxy with mass");
  }
  body.inertia_body = inertia * (proxy_mass_kg / tool.mass.mass_kg);
  return body;
}

}  // namespace hb
