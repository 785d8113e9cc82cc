// What a renderer is given about the world: scene objects and the tool, each
// with its exact primitive (when it is one) and its triangle mesh.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "hapticbench/mass_properties.h"
#include "hapticbench/pose.h"
#include "hapticbench/shapes.h"
#include "hapticbench/triangle_mesh.h"

namespace hb {

/// A static object of the scene.
struct SceneObject {
  std::string name;            ///< e.g. "scene[0]" or the mesh file name
  Pose pose;                   ///< object frame -> world
  TriangleMesh mesh;           ///< m, object frame
  std::optional<Shape> shape;  ///< set when the object is an exact primitive
  std::string content_hash;    ///< hash of the geometry, for caches
  /// The mesh may be open or self-intersecting: ground truth uses it for
  /// distances only, never for inside/outside (scenario key "distance_only").
  bool distance_only = false;
  /// Coulomb friction coefficient μ (≥ 0) of contacts with this object;
  /// scenario key "friction", default 0 (frictionless).
  double friction = 0;
};

/// The virtual tool held by the device at its tool frame.
struct Tool {
  TriangleMesh mesh;           ///< m, tool frame
  std::optional<Shape> shape;  ///< set when the tool is an exact primitive
  MassProperties mass;         ///< about the centre of mass, tool-frame axes
  std::string content_hash;
};

/// Virtual coupling gains (seed: F_c = k_T x + b_T v, tau_c = k_R theta + b_R omega).
struct CouplingGains {
  double k_t = 2000;  ///< N/m
  double b_t = 5;     ///< N·s/m
  double k_r = 5;     ///< N·m/rad
  double b_r = 0.05;  ///< N·m·s/rad
};

/// Device output limits; infinite means no saturation.
struct DeviceLimits {
  double max_force_n = 1e300;
  double max_torque_nm = 1e300;
};

/// Everything a renderer is built from besides its own parameters.
struct RenderContext {
  std::vector<SceneObject> scene;
  Tool tool;
  CouplingGains coupling;
  DeviceLimits device;
  Vec3 gravity = Vec3::Zero();  ///< m/s², world frame; zero unless the scenario sets it
  double dt_s = 1e-3;           ///< haptic tick, s
  /// Where the tool can be (m, world frame): the device's tool-frame
  /// positions over the trace, grown by the tool's radius about its frame
  /// origin. A renderer may leave out geometry outside it; nullopt: unknown.
  std::optional<Eigen::AlignedBox3d> reach;
};

}  // namespace hb
