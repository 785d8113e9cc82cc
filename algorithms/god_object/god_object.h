// The god-object renderers: the 6-DOF god-object of Ortega, Redon &
// Coquillart (2007) and its 3-DOF special case, a point tool, at the notes'
// rates: every haptic tick the proxy moves toward the device by Gauss'
// least constraint on the feature pairs found near it, bounded so it cannot
// reach a feature that was not found (haptic_proxy.h), and the display is
// the virtual coupling between the device and that proxy; the slow loop
// runs the CCD-limited update (god_object_update.h) from the haptic proxy's
// pose and the proximity query that finds the pairs.
#pragma once

#include <memory>

#include "algorithms/god_object/god_object_update.h"
#include "hapticbench/param_set.h"
#include "hapticbench/renderer.h"
#include "hapticbench/scene.h"

namespace hb {

/// Reads "standoff" (m, default 1e-5), "contact_distance" (m, > standoff,
/// default 1e-4), "max_iterations" (default 8), "ccd_time_tolerance"
/// (default 1e-6), "ccd_max_evaluations" (default 64), "contact_window"
/// (default 1e-3), "haptic_band" (m, > standoff, default 5e-3), "haptic_band_min"
/// (m, default 5e-4) and
/// "haptic_max_pairs" (default 2048); `defaults` gives the values of absent
/// keys. Throws InputError naming the field.
GodObjectSettings read_god_object_settings(const ParamSet& params, bool point_tool,
                                           const GodObjectSettings& defaults = {});

/// The 6-DOF god-object: the whole tool mesh against the scene.
std::unique_ptr<Renderer> create_god_object(const RenderContext& context, const ParamSet& params);

/// The 3-DOF god-object: the tool frame's origin as a point (segment–triangle
/// CCD); displays force only, no torque.
std::unique_ptr<Renderer> create_god_object_3dof(const RenderContext& context,
                                                 const ParamSet& params);

}  // namespace hb
