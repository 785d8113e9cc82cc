// Meshes and poses in FCL's types, for the benchmarks that compare with
// FCL (mesh_ccd_bench, vps_vs_fcl_bench).
#pragma once

#include <fcl/fcl.h>

#include <memory>
#include <vector>

#include "hapticbench/pose.h"
#include "hapticbench/triangle_mesh.h"

namespace hb::bench {

using FclModel = fcl::BVHModel<fcl::OBBRSSd>;

/// An OBBRSS hierarchy of the mesh with its vertices placed by `pose` (m).
inline std::shared_ptr<FclModel> fcl_model(const TriangleMesh& mesh, const Pose& pose = Pose{}) {
  auto model = std::make_shared<FclModel>();
  std::vector<fcl::Vector3d> points;
  points.reserve(mesh.vertices.size());
  for (const Vec3& v : mesh.vertices) points.push_back(pose.transform_point(v));
  std::vector<fcl::Triangle> triangles;
  triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    triangles.emplace_back(static_cast<std::size_t>(t[0]), static_cast<std::size_t>(t[1]),
                           static_cast<std::size_t>(t[2]));
  model->beginModel();
  model->addSubModel(points, triangles);
  model->endModel();
  return model;
}

/// The pose as an FCL rigid transform.
inline fcl::Transform3d fcl_transform(const Pose& pose) {
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.linear() = pose.q.normalized().toRotationMatrix();
  tf.translation() = pose.p;
  return tf;
}

}  // namespace hb::bench
