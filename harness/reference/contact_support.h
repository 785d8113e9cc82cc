// The few contact rows that carry what many do: rows against one scene
// plane (the same normal and offset, the same friction) whose contact points
// lie inside the support polygon of others, with a bound no higher than
// theirs interpolated there, are implied by them. Each row is
//   n·(δx + φ × (c − p)) ≥ b,
// affine in its contact point c; a point inside the triangle of three others
// with b at most their interpolation is a convex combination of their
// constraints (so the feasible steps are the same), and a Coulomb cone at it
// is a convex combination of cones at theirs (so the contact wrenches are
// the same). A tool's face resting on a scene face (hundreds of sample rows)
// keeps the corners of its support polygon; a sphere on a face keeps its
// lowest row. Units: m; one frame for every point.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "hapticbench/pose.h"

namespace hb {

struct ContactRowGeometry {
  Vec3 point = Vec3::Zero();    ///< c: the contact's point on the scene's side (m)
  Vec3 normal = Vec3::UnitZ();  ///< n: unit, out of the scene
  double bound = 0;             ///< b (m)
  double friction = 0;          ///< Coulomb μ of the row
};

/// Indices (ascending) of the rows to keep: all but those implied by others
/// of their plane (see above). Groups whose support polygon has more than
/// kMaxSupportCorners corners keep every row.
std::vector<std::size_t> supporting_rows(std::span<const ContactRowGeometry> rows);

inline constexpr std::size_t kMaxSupportCorners = 16;

}  // namespace hb
