// Sensation-preserving simplification with implicit integration (Otaduy &
// Lin 2003/2005; lecture notes, "Stable & Responsive Manipulation" to
// "Dynamic Proxy Limitations"). The contact query (hierarchy_contacts.h:
// convex hierarchies of tool and scene, refined only where the detail is
// perceptible, GJK/EPA on the pieces) runs on the slow loop; its contacts
// are clustered by k-means into representative point + normal, and the
// haptic loop integrates, at 1 kHz with implicit Euler, a proxy with mass
// on the virtual coupling against the viscoelastic penalty of each cluster
//   F_p = −kN(x + Rr − p₀) − kdn − bN(v + ω × r),   T_p = (Rr) × F_p
// linearised at the latest query (hapticbench/proxy/penalty_contact.h).
#pragma once

#include <memory>

#include "hapticbench/param_set.h"
#include "hapticbench/renderer.h"
#include "hapticbench/scene.h"

namespace hb {

/// Parameters (scenario `params`):
///   perceptibility_threshold  unitless ≥ 0: refine a node pair while
///                             max(δ_a, δ_b) > threshold · min(r_a, r_b);
///                             0 = full resolution (default 0.05)
///   clusters                  k of k-means, ≥ 1; 0 keeps every piece contact
///                             as its own cluster (default 5)
///   contact_margin            m, pieces this close count as contacts (default 0)
///   contact_stiffness, contact_damping   k (N/m) and b (N·s/m) per cluster
///   integrator, proxy_mass_kg            the dynamic proxy (implicit Euler default)
///   max_piece_vertices        vertices a merged convex piece keeps (default 32)
///   cache                     false: build the hierarchies, bypassing the cache
///   slow_loop_latency         (read by the harness) "measured" (default: the
///                             query's own time, in whole ticks) or a fixed
///                             number of ticks until its result is installed
/// Hierarchies are cached on disk by content hash and settings
/// ($HAPTICBENCH_CACHE_DIR, else $XDG_CACHE_HOME/hapticbench, else
/// ~/.cache/hapticbench). Throws InputError naming the field.
std::unique_ptr<Renderer> create_sensation_preserving(const RenderContext& context,
                                                      const ParamSet& params);

}  // namespace hb
