#include "algorithms/penalty_analytic/primitive_contacts.h"

#include <algorithm>
#include <string>

#include "hapticbench/input_error.h"
#include "hapticbench/shapes.h"

namespace hb {

PrimitiveContactFinder::PrimitiveContactFinder(const std::vector<SceneObject>& scene,
                                               const Tool& tool, const RigidBody& body) {
  for (std::size_t i = 0; i < scene.size(); ++i) {
    if (!scene[i].shape) {
      const std::string index = std::to_string(i);
      throw InputError("", "/scene/" + index,
                       "penalty_analytic needs primitive shapes (box, sphere, capsule, "
                       "box_with_hole); scene[" +
                           index + "] is a mesh");
    }
    obstacles_.push_back(Obstacle{*scene[i].shape, scene[i].pose});
  }
  if (tool.shape && tool.shape->type == ShapeType::kSphere) {
    sphere_radius_m_ = tool.shape->radius;
    tool_points_.push_back(-body.centre_of_mass);  // the sphere's centre is the tool origin
  } else {
    tool_points_.reserve(tool.mesh.vertices.size());
    for (const Vec3& vertex : tool.mesh.vertices)
      tool_points_.push_back(vertex - body.centre_of_mass);
  }
  for (const Vec3& point : tool_points_)
    tool_radius_m_ = std::max(tool_radius_m_, point.norm() + sphere_radius_m_);
}

void PrimitiveContactFinder::find(const RigidBodyState& state, double margin_m,
                                  std::vector<PrimitiveContact>& out, WorkCounters& work) const {
  work.names = &PrimitiveWork::kNames;
  for (const Obstacle& obstacle : obstacles_) {
    // Broad phase: no tool point can come within the margin when the centre
    // of mass is farther than the tool's radius from the shape.
    work.add(PrimitiveWork::kObstacleBoundTests);
    const Vec3 com_local = obstacle.pose.inverse_transform_point(state.x);
    if (shape_signed_distance(obstacle.shape, com_local) > tool_radius_m_ + margin_m) continue;

    for (const Vec3& point : tool_points_) {
      work.add(PrimitiveWork::kToolPointsTested);
      const Vec3 local = obstacle.pose.inverse_transform_point(state.x + state.q * point);
      if (shape_signed_distance(obstacle.shape, local) - sphere_radius_m_ >= margin_m) continue;
      const SurfacePoint surface = shape_closest_surface_point(obstacle.shape, local);
      PrimitiveContact contact;
      contact.plane.tool_point = point;
      contact.plane.normal = (obstacle.pose.q * surface.normal).normalized();
      contact.plane.plane_point =
          obstacle.pose.transform_point(surface.point) + sphere_radius_m_ * contact.plane.normal;
      contact.surface_offset_m = sphere_radius_m_;
      out.push_back(contact);
    }
  }
}

Contact PrimitiveContactFinder::report(const PrimitiveContact& contact,
                                       const RigidBodyState& state) {
  const Vec3 n = contact.plane.normal;
  return Contact{contact_tool_point_world(contact.plane, state) - contact.surface_offset_m * n, n,
                 contact_depth(contact.plane, state)};
}

}  // namespace hb
