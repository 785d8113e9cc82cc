// Contact planes between the tool and exact primitive scene shapes, for
// penalty_analytic. A sphere tool has one exact contact per scene object:
// its centre against the shape, the plane linearised at the closest surface
// point and pushed out by the radius, so the force passes through the centre
// and turning the sphere changes nothing. Any other tool contributes every
// mesh vertex as a contact point.
#pragma once

#include <vector>

#include "hapticbench/proxy/penalty_contact.h"
#include "hapticbench/proxy/rigid_body.h"
#include "hapticbench/renderer.h"
#include "hapticbench/scene.h"

namespace hb {

/// A linearised contact and how to report it.
struct PrimitiveContact {
  ContactPlane plane;
  /// m: the reported point on the tool surface is the plane's tool point
  /// moved by this much against the normal (the sphere radius; 0 for a vertex).
  double surface_offset_m = 0;
};

/// Work counters of penalty rendering on primitives (WorkCounters slots).
struct PrimitiveWork {
  enum Slot : std::size_t {
    kObstacleBoundTests,  ///< broad phase, per scene shape
    kToolPointsTested,    ///< tool points against a shape
    kPlanesEvaluated,     ///< slow-loop planes a tick used
    kNewtonSteps,         ///< quasi-static solver steps
  };
  // Each slot beside its name, so that the two cannot drift apart.
  static constexpr WorkCounters::Names kNames = [] {
    WorkCounters::Names names{};
    names[kObstacleBoundTests] = "obstacle_bound_tests";
    names[kToolPointsTested] = "tool_points_tested";
    names[kPlanesEvaluated] = "planes_evaluated";
    names[kNewtonSteps] = "newton_steps";
    return names;
  }();
};

class PrimitiveContactFinder {
 public:
  /// Throws InputError at "/scene/<i>" for a scene object without a primitive shape.
  /// `body` gives the centre of mass the tool points are taken relative to.
  PrimitiveContactFinder(const std::vector<SceneObject>& scene, const Tool& tool,
                         const RigidBody& body);

  /// Appends to `out` the planes of every tool point whose distance to a
  /// scene shape is below margin_m (m; 0: penetrating points only) with the
  /// proxy at `state`. Counts points and bounding tests in `work` (PrimitiveWork).
  void find(const RigidBodyState& state, double margin_m, std::vector<PrimitiveContact>& out,
            WorkCounters& work) const;

  /// Largest distance of a tool contact point from the centre of mass (m),
  /// including the sphere radius.
  double tool_radius_m() const { return tool_radius_m_; }

  /// The contact to report for a plane at `state` (point on the tool surface, world).
  static Contact report(const PrimitiveContact& contact, const RigidBodyState& state);

 private:
  struct Obstacle {
    Shape shape;
    Pose pose;
  };
  std::vector<Obstacle> obstacles_;
  std::vector<Vec3> tool_points_;  ///< m, tool axes, relative to the centre of mass
  double sphere_radius_m_ = 0;     ///< > 0 for a sphere tool
  double tool_radius_m_ = 0;
};

}  // namespace hb
