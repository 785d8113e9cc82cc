// Hand-built contexts and finite-difference Jacobians for the proxy-model
// tests. Mass properties come from closed forms here, independent of the
// mesh integrator in algorithms/core.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

#include "hapticbench/proxy/force_model.h"
#include "hapticbench/proxy/rigid_body.h"
#include "hapticbench/scene.h"
#include "hapticbench/shapes.h"

namespace hb::test {

/// Solid sphere of `radius_m` centred on the tool frame: m = ρ·4/3·π·r³, I = 2/5·m·r².
inline Tool sphere_tool(double radius_m, double density_kg_m3 = 1000) {
  Tool tool;
  Shape shape;
  shape.type = ShapeType::kSphere;
  shape.radius = radius_m;
  tool.shape = shape;
  const double mass = density_kg_m3 * 4.0 / 3.0 * std::numbers::pi * std::pow(radius_m, 3);
  tool.mass.mass_kg = mass;
  tool.mass.centre_of_mass = Vec3::Zero();
  tool.mass.inertia_about_com = 0.4 * mass * radius_m * radius_m * Mat3::Identity();
  tool.mass.volume_m3 = mass / density_kg_m3;
  return tool;
}

/// Solid box with full extents `size` centred on the tool frame; its mesh is
/// the 8 corners and 12 outward triangles.
inline Tool box_tool(const Vec3& size, double density_kg_m3 = 1000) {
  Tool tool;
  Shape shape;
  shape.type = ShapeType::kBox;
  shape.size = size;
  tool.shape = shape;
  for (int i = 0; i < 8; ++i) {
    tool.mesh.vertices.push_back(0.5 * Vec3((i & 1) ? size.x() : -size.x(),
                                            (i & 2) ? size.y() : -size.y(),
                                            (i & 4) ? size.z() : -size.z()));
  }
  // Two triangles per face, counter-clockwise from outside (corner bits x, y, z).
  tool.mesh.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                         {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  const double mass = density_kg_m3 * size.prod();
  tool.mass.mass_kg = mass;
  tool.mass.volume_m3 = size.prod();
  const Vec3 s2 = size.cwiseProduct(size);
  tool.mass.inertia_about_com =
      (mass / 12.0 * Vec3(s2.y() + s2.z(), s2.x() + s2.z(), s2.x() + s2.y())).asDiagonal();
  return tool;
}

/// box_tool with the mesh the scenarios give a box shape (shape_mesh).
inline Tool meshed_box_tool(const Vec3& size) {
  Tool tool = box_tool(size);
  tool.mesh = shape_mesh(*tool.shape);
  return tool;
}

/// Lowest z (m, world) of the mesh's vertices placed at `pose`.
inline double lowest_vertex_z(const TriangleMesh& mesh, const Pose& pose) {
  double lowest = 1e300;
  for (const Vec3& vertex : mesh.vertices)
    lowest = std::min(lowest, pose.transform_point(vertex).z());
  return lowest;
}

/// An L-shaped hook (a 1 × 2 × 11 cm stem, a 7 cm arm at its top) in the
/// x–z plane, extruded 2 cm along y; the tool frame is the middle of the
/// arm tip's lower edge (the arm reaches from x = −8 cm to 0 at z = 0 to
/// 1 cm, the stem hangs from x = −8 to −7 cm down to z = −10 cm).
inline TriangleMesh hook_mesh() {
  const double outline[6][2] = {{-0.08, -0.1}, {-0.07, -0.1}, {-0.07, 0},
                                {0, 0},        {0, 0.01},     {-0.08, 0.01}};
  TriangleMesh mesh;
  for (double y : {-0.01, 0.01})
    for (const auto& xz : outline) mesh.vertices.push_back(Vec3(xz[0], y, xz[1]));
  const int cap[4][3] = {{0, 1, 2}, {0, 2, 5}, {2, 3, 4}, {2, 4, 5}};
  for (const auto& t : cap) {
    mesh.triangles.push_back({t[0], t[2], t[1]});  // y = −1 cm, facing −y
    mesh.triangles.push_back({6 + t[0], 6 + t[1], 6 + t[2]});
  }
  for (int i = 0; i < 6; ++i) {
    const int j = (i + 1) % 6;
    mesh.triangles.push_back({i, 6 + i, 6 + j});
    mesh.triangles.push_back({i, 6 + j, j});
  }
  return mesh;
}

/// Signed distance (m) from `p` to the axis-aligned box of half-extents
/// `half` centred at `centre`: negative inside.
inline double box_signed_distance(const Vec3& p, const Vec3& centre, const Vec3& half) {
  const Vec3 q = (p - centre).cwiseAbs() - half;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

/// The least signed distance (m) to that box of any point of any edge of
/// `mesh` posed at `pose`, edges sampled every `spacing` m.
inline double least_edge_distance_to_box(const TriangleMesh& mesh, const Pose& pose,
                                         const Vec3& centre, const Vec3& half,
                                         double spacing = 1e-4) {
  double least = 1e300;
  for (const auto& triangle : mesh.triangles)
    for (int e = 0; e < 3; ++e) {
      const Vec3 a = pose.transform_point(mesh.vertices[triangle[e]]);
      const Vec3 b = pose.transform_point(mesh.vertices[triangle[(e + 1) % 3]]);
      const int samples = static_cast<int>((b - a).norm() / spacing) + 1;
      for (int i = 0; i <= samples; ++i)
        least =
            std::min(least, box_signed_distance(a + (b - a) * (double(i) / samples), centre, half));
    }
  return least;
}

/// A static box scene object of full extents `size` at `pose`.
inline SceneObject box_object(const Vec3& size, const Pose& pose) {
  SceneObject object;
  object.name = "box";
  object.pose = pose;
  Shape shape;
  shape.type = ShapeType::kBox;
  shape.size = size;
  object.shape = shape;
  return object;
}

/// n × n meshed cube tiles of edge `edge` (m), tops at z = 0, from the
/// origin along +x and +y with `gap` (m) between them (0: edge to edge, so
/// that neighbours share corners, edges and faces' places).
inline std::vector<SceneObject> box_tiles(int n, double edge, double gap) {
  std::vector<SceneObject> tiles;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      SceneObject tile =
          box_object(Vec3::Constant(edge),
                     Pose{Vec3((edge + gap) * i, (edge + gap) * j, -0.5 * edge), Quat::Identity()});
      tile.mesh = shape_mesh(*tile.shape);
      tiles.push_back(tile);
    }
  }
  return tiles;
}

/// A static sphere scene object.
inline SceneObject sphere_object(double radius_m, const Pose& pose) {
  SceneObject object;
  object.name = "sphere";
  object.pose = pose;
  Shape shape;
  shape.type = ShapeType::kSphere;
  shape.radius = radius_m;
  object.shape = shape;
  return object;
}

/// The gains of DESIGN.md's example scenario.
inline CouplingGains example_gains() { return CouplingGains{2000, 5, 5, 0.05}; }

/// Wrench as a 6-vector (force, torque).
inline Vec6 as_vector(const Wrench& w) {
  Vec6 out;
  out << w.force, w.torque;
  return out;
}

/// State moved by a perturbation (δx, δθ, δv, δω) in the coordinates of force_model.h.
inline RigidBodyState perturbed(const RigidBodyState& s, int coordinate, double h) {
  RigidBodyState out = s;
  Vec3 delta = Vec3::Zero();
  delta[coordinate % 3] = h;
  switch (coordinate / 3) {
    case 0:
      out.x += delta;
      break;
    case 1:
      out.q = (quat_from_rotation_vector(delta) * s.q).normalized();
      break;
    case 2:
      out.v += delta;
      break;
    default:
      out.w += delta;
  }
  return out;
}

/// Central differences of a wrench function: columns 0-5 w.r.t. (δx, δθ)
/// (stiffness), 6-11 w.r.t. (δv, δω) (damping).
inline Eigen::Matrix<double, 6, 12> numeric_jacobian(
    const std::function<Wrench(const RigidBodyState&)>& wrench, const RigidBodyState& state,
    double h = 1e-6) {
  Eigen::Matrix<double, 6, 12> j;
  for (int c = 0; c < 12; ++c) {
    j.col(c) =
        (as_vector(wrench(perturbed(state, c, h))) - as_vector(wrench(perturbed(state, c, -h)))) /
        (2 * h);
  }
  return j;
}

/// The analytic K and D side by side, in numeric_jacobian's layout.
inline Eigen::Matrix<double, 6, 12> analytic_jacobian(const ForceEvaluation& f) {
  Eigen::Matrix<double, 6, 12> j;
  j << f.stiffness, f.damping;
  return j;
}

}  // namespace hb::test
