// Constrained dynamics, the fourth cell of the notes' proxy taxonomy (mass
// and hard contacts): a rigid proxy with the tool's mass and inertia,
// pulled by the virtual coupling (implicit, as the other dynamic proxies)
// and kept out of the scene by contact impulses with Coulomb friction,
// solved every haptic tick at velocity level (Duriez, Dubois, Kheddar &
// Andriot 2006; frictional_contact_solver.h).
//
// One tick, all world frame about the proxy's centre of mass:
//  1. every feature pair of the slow loop's proximity certificate is
//     re-evaluated at the current pose (its closest points give the normal,
//     the lever and the distance d; proximity_certifier.h);
//  2. the step's free velocity u_free solves the linearised implicit Euler
//     step (M − Δt D − Δt² K) Δu = Δt (f + Δt K u) of the coupling, gravity
//     and the gyroscopic torque (integrator.h); the contacts act through
//     that whole effective mass A, which is not symmetric (solve_system in
//     constrained_step.h: the symmetric part as the metric, the skew part
//     carried as a force to a fixed point);
//  3. each pair is a contact with bound b = −(d − s)/Δt on its normal
//     velocity while d ≥ s (s the standoff: a speculative contact, which
//     lets it close the gap this tick but not pass it) and b = β (s − d)/Δt,
//     at most v_max, when a rotation's curvature took it below the standoff
//     (Baumgarte stabilisation: the drift is removed at rate β per tick and
//     never pushes faster than v_max);
//  4. the frictional contact solver gives u⁺; the pose moves by Δt u⁺
//     (x⁺ = x + Δt v⁺, q⁺ = exp(Δt ω⁺) q), cut, with u⁺, to the largest
//     fraction that stays within the certificate's reach, so no pair the
//     certificate did not list can be met;
//  5. the device displays the coupling's reaction at the new state.
// The slow loop only certifies: the proximity query at the proxy's pose,
// with the god-object's band (six times the device's motion between slow
// updates). Why the certificate and not the convex hierarchy: it lists the
// exact mesh features, so non-penetration holds against the real surfaces,
// and its reach bound makes that hold between slow updates too. A new
// certificate is taken when the proxy lies within its reach, otherwise the
// current one stays (it still holds: the proxy never left its reach).
// A start inside the scene is moved out as by the god-object.
#pragma once

#include <memory>

#include "algorithms/contact/contact_settings.h"
#include "algorithms/contact/frictional_contact_solver.h"
#include "hapticbench/param_set.h"
#include "hapticbench/renderer.h"
#include "hapticbench/scene.h"

namespace hb {

struct ConstrainedDynamicsSettings {
  /// Contact discovery: standoff, contact distance, certificate bands and
  /// pair limit, as for the god-object.
  ContactSettings contacts;
  FrictionalContactSettings solver;  ///< "solver_sweeps", "solver_tolerance" (m/s)
  double stabilisation = 0.2;        ///< "stabilisation": β in (0, 1]
  double max_correction_mps = 0.05;  ///< "max_correction_speed": v_max (m/s)
  double proxy_mass_kg = 0;          ///< "proxy_mass_kg" (proxy_settings.h)
};

/// Reads the contact keys shared with the god-object (contact_settings.h:
/// standoff, contact_distance, haptic_band, haptic_band_min,
/// haptic_max_pairs, ccd_*, contact_window),
/// "solver_sweeps" (default 200), "solver_tolerance" (m/s, default 1e-6: a
/// nanometre of slip per tick; the normal constraints are solved exactly
/// whatever it is, constrained_step.h),
/// "stabilisation", "max_correction_speed" and "proxy_mass_kg". Throws
/// InputError naming the field.
ConstrainedDynamicsSettings read_constrained_dynamics_settings(const ParamSet& params,
                                                               const Tool& tool);

std::unique_ptr<Renderer> create_constrained_dynamics(const RenderContext& context,
                                                      const ParamSet& params);

}  // namespace hb
