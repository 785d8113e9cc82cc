// Baseline renderer: penalty contact against exact primitive scene shapes
// (box, sphere, capsule, box_with_hole), on the generic proxy model with
// either integrator. Not one of the seed algorithms; it exercises the harness
// and gives a stiffness/integrator reference with exact geometry.
#pragma once

#include <memory>

#include "hapticbench/param_set.h"
#include "hapticbench/renderer.h"
#include "hapticbench/scene.h"

namespace hb {

/// Parameters: integrator, proxy_mass_kg, contact_stiffness (N/m),
/// contact_damping (N·s/m), proxy ("dynamic" | "quasi_static"),
/// contact_loop ("haptic" | "slow"). The massless quasi-static proxy has no
/// integrator, mass or velocity: it reads only proxy, contact_loop and
/// contact_stiffness, so the others are left for reject_unknown() to report.
/// Throws InputError naming the field, including for a scene object that is
/// not a primitive shape.
std::unique_ptr<Renderer> create_penalty_analytic(const RenderContext& context,
                                                  const ParamSet& params);

}  // namespace hb
