// The README's "add an algorithm" recipe, followed by
// scripts/check-algorithm-recipe: a penalty spring that pushes the tool's
// bounding sphere out of the plane z = plane_height_m, with no proxy
// dynamics (the proxy is the device pose, lifted onto the plane).
#pragma once

#include <memory>

#include "hapticbench/param_set.h"
#include "hapticbench/renderer.h"
#include "hapticbench/scene.h"

namespace hb {

/// Parameters: stiffness (N/m, default 1000), plane_height_m (m, default 0).
/// Throws InputError naming the field.
std::unique_ptr<Renderer> create_my_algo(const RenderContext& context, const ParamSet& params);

}  // namespace hb
