// Parameters every proxy-with-mass algorithm understands (DESIGN.md,
// scenario `algorithms[].params`), read from a ParamSet and checked when the
// renderer is built. Errors are InputErrors naming the field.
#pragma once

#include "hapticbench/param_set.h"
#include "hapticbench/proxy/integrator.h"
#include "hapticbench/proxy/penalty_contact.h"
#include "hapticbench/proxy/rigid_body.h"
#include "hapticbench/scene.h"

namespace hb {

/// The dynamic proxy: which integrator and how heavy.
struct ProxySettings {
  IntegratorKind integrator = IntegratorKind::kImplicitEuler;  ///< "integrator"
  double proxy_mass_kg = 0;  ///< "proxy_mass_kg", kg, > 0; default the tool's mass
};

/// Reads "integrator" ("explicit_euler" | "implicit_euler", default implicit)
/// and "proxy_mass_kg" (> 0, default tool.mass.mass_kg).
ProxySettings read_proxy_settings(const ParamSet& params, const Tool& tool);

/// Reads only "proxy_mass_kg" (> 0, default tool.mass.mass_kg), for proxies
/// whose integrator is fixed.
double read_proxy_mass(const ParamSet& params, const Tool& tool);

/// Reads "contact_stiffness" (N/m, ≥ 0, default 3000) and
/// "contact_damping" (N·s/m, ≥ 0, default 2).
PenaltyGains read_penalty_gains(const ParamSet& params);

/// Reads only "contact_stiffness", for proxies without velocity (quasi-static).
double read_contact_stiffness(const ParamSet& params);

/// The proxy's rigid body: the tool's centre of mass and inertia, scaled
/// (mass and inertia by the same ratio) to proxy_mass_kg, under `gravity`
/// (m/s², world). Throws InputError at "/tool" when the tool's inertia is
/// not positive definite.
RigidBody proxy_body(const Tool& tool, double proxy_mass_kg, const Vec3& gravity);

}  // namespace hb
