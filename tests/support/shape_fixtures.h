// Test support: shape descriptions and poses the unit tests build their
// scenes from.
#pragma once

#include <numbers>

#include "hapticbench/pose.h"
#include "hapticbench/shapes.h"

namespace hb::test {

inline constexpr double kPi = std::numbers::pi;

/// The pose at `p` (m), turned by `angle` (rad) about `axis` (any length).
inline Pose pose(const Vec3& p, double angle = 0, const Vec3& axis = Vec3::UnitZ()) {
  return Pose{p, Quat(Eigen::AngleAxisd(angle, axis.normalized()))};
}

/// The pose at `p` (m) with orientation `q`.
inline Pose at(const Vec3& p, const Quat& q = Quat::Identity()) { return Pose{p, q}; }

/// A box of edges `size` (m) centred on its frame's origin.
inline Shape box_shape(const Vec3& size) {
  Shape s;
  s.type = ShapeType::kBox;
  s.size = size;
  return s;
}

/// A sphere of `radius` (m), its mesh an icosphere subdivided `subdivisions` times.
inline Shape sphere_shape(double radius, int subdivisions) {
  Shape s;
  s.type = ShapeType::kSphere;
  s.radius = radius;
  s.subdivisions = subdivisions;
  return s;
}

/// A capsule of `radius` (m) whose axis segment is `length` (m) long.
inline Shape capsule_shape(double radius, double length, int subdivisions) {
  Shape s;
  s.type = ShapeType::kCapsule;
  s.radius = radius;
  s.length = length;
  s.subdivisions = subdivisions;
  return s;
}

}  // namespace hb::test
