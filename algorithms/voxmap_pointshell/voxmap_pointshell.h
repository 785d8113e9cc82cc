// Voxmap PointShell (McNeely, Puterbaugh & Troy 1999): the scene as a voxmap
// (states free, interior, surface, proximity; voxmap.h), the tool as a
// pointshell (centres of its surface voxels with inward normals), and per
// tick the tangent-plane force model with Hooke's law per point, the N ≥ 10
// averaging rule and pre-contact braking viscosity (pointshell_contacts.h),
// on a dynamic proxy with virtual coupling, explicit Euler (as the paper)
// or implicit Euler (contact Jacobians included).
#pragma once

#include <memory>

#include "hapticbench/param_set.h"
#include "hapticbench/renderer.h"
#include "hapticbench/scene.h"

namespace hb {

/// Parameters (scenario `params`):
///   voxel_size          m, scene voxel edge h (default 0.002)
///   pointshell_spacing  m, tool voxel edge (default voxel_size)
///   point_stiffness     N/m, K_ff per point (default 10000)
///   variant             "voxmap" (tangent plane through the voxel centre, McNeely's
///                       averaging) or "signed_distance" (depth −φ interpolated, the
///                       gradient of one potential), default "voxmap"
///   interior_layers     voxels of exact φ inside the surface, signed_distance
///                       only (default 3; deeper points read the band's depth)
///   proximity_layers    voxels of proximity state outside the surface (default 2)
///   braking_viscosity   N·s²/m², b of the braking force (default 5; 0 switches it off)
///   integrator, proxy_mass_kg   the dynamic proxy (proxy_settings.h)
///   cache               true/false, reuse voxmaps on disk (default true); the
///                       folder is $HAPTICBENCH_CACHE_DIR, else
///                       $XDG_CACHE_HOME/hapticbench, else ~/.cache/hapticbench
/// A scene object marked distance_only (an open surface) gets no interior
/// voxels, and the signed_distance variant refuses it (InputError at
/// "variant"). Only scene objects within the context's reach box (grown by the
/// proximity band and a tenth of the tool's radius) are voxelised, and only
/// there; without a reach box, the whole scene. Throws InputError naming the
/// field for bad values, and for a voxel size that would need an
/// unreasonable number of voxels over that region.
std::unique_ptr<Renderer> create_voxmap_pointshell(const RenderContext& context,
                                                   const ParamSet& params);

}  // namespace hb
