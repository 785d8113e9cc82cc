// The traversal behind MeshCcd::first_contact (see mesh_ccd.h and
// mesh_ccd_search.cpp): tool tree × scene trees × time, earliest first.
#pragma once

#include <span>

#include "algorithms/ccd/mesh_ccd.h"
#include "algorithms/ccd/mesh_features.h"
#include "algorithms/ccd/screw_motion.h"

namespace hb::ccd_detail {

/// The first contact of the tool (tool frame) moving along `motion` with
/// the scene (world frame). The contacts' geometry is left for the caller
/// to evaluate. The motion's numbers must be within kMaxCcdCoordinate.
MeshCcdResult search_first_contact(const MeshFeatures& tool, std::span<const MeshFeatures> scene,
                                   const ScrewMotion& motion, const MeshCcdSettings& settings);

}  // namespace hb::ccd_detail
