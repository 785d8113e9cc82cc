#include "algorithms/contact/contact_geometry.h"

#include <algorithm>
#include <limits>

namespace hb {

namespace {

// The tool as the CCD sees it: its mesh in a frame at its centre of mass,
// or the single point at its frame's origin.
TriangleMesh ccd_tool_mesh(const Tool& tool, bool point_tool) {
  TriangleMesh mesh;
  if (point_tool) {
    mesh.vertices = {Vec3::Zero()};
    mesh.triangles = {{0, 0, 0}};
    return mesh;
  }
  mesh = tool.mesh;
  for (Vec3& vertex : mesh.vertices) vertex -= tool.mass.centre_of_mass;
  return mesh;
}

}  // namespace

ContactGeometry::ContactGeometry(const Tool& tool, std::span<const SceneObject> scene,
                                 const ContactSettings& settings)
    : settings_(settings),
      frames_{settings.point_tool ? Vec3::Zero() : tool.mass.centre_of_mass},
      ccd_(ccd_tool_mesh(tool, settings.point_tool), scene) {
  for (const SceneObject& object : scene) friction_.push_back(object.friction);
}

StartEscape ContactGeometry::escape(const Pose& start) const {
  StartEscape result{start, 0.0, false};
  const auto [scene_centre, scene_radius] = ccd_.scene_bounding_sphere();
  if (scene_radius < 0) return result;
  const Pose com = frames_.com_frame(start);
  const double radius = settings_.point_tool ? 0.0 : ccd_.tool_radius();
  // From this far along any direction the tool is outside the scene's sphere.
  const double length =
      (com.p - scene_centre).norm() + scene_radius + radius + 2 * settings_.standoff_m;
  double shortest = std::numeric_limits<double>::infinity();
  Pose shortest_pose = com;
  // Straight up first: a free start above the scene is proven so at once.
  for (int z : {1, -1, 0})
    for (int x = -1; x <= 1; ++x)
      for (int y = -1; y <= 1; ++y) {
        if (x == 0 && y == 0 && z == 0) continue;
        const Vec3 direction = Vec3(x, y, z).normalized();
        const ScrewMotion motion(Pose{com.p + length * direction, com.q}, com);
        const MeshCcdResult hit = ccd_.first_contact(motion, settings_.ccd);
        if (!hit.contact) return result;
        const double stop = std::max(0.0, hit.toi - settings_.standoff_m / length);
        if (length * (1 - stop) < shortest) {
          shortest = length * (1 - stop);
          shortest_pose = pose_on(motion, stop);
        }
      }
  result.pose = frames_.tool_frame(shortest_pose);
  result.distance_m = shortest;
  result.escaped = true;
  return result;
}

}  // namespace hb
