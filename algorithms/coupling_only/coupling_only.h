// Baseline renderer: a dynamic proxy held by the virtual coupling, with no
// contacts at all. What it displays is the coupling's own lag, i.e. the
// transparency of the proxy model in free space.
#pragma once

#include <memory>

#include "hapticbench/param_set.h"
#include "hapticbench/renderer.h"
#include "hapticbench/scene.h"

namespace hb {

/// Parameters: integrator ("explicit_euler" | "implicit_euler"),
/// proxy_mass_kg (default: the tool's mass). Throws InputError naming the field.
std::unique_ptr<Renderer> create_coupling_only(const RenderContext& context,
                                               const ParamSet& params);

}  // namespace hb
