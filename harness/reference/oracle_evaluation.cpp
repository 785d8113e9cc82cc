#include "harness/reference/oracle_evaluation.h"

#include <chrono>
#include <cmath>
#include <numbers>

#include "harness/reference/surface_samples.h"

namespace hb {

namespace {
int64_t ns_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() -
                                                              start)
      .count();
}

// World bounds of a box given in a body frame, placed by pose.
Eigen::AlignedBox3d world_bounds(const Eigen::AlignedBox3d& body_box, const Pose& pose) {
  Eigen::AlignedBox3d box;
  for (int corner = 0; corner < 8; ++corner)
    box.extend(pose.transform_point(
        body_box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner))));
  return box;
}

double angle_deg(const Vec3& a, const Vec3& b) {
  const double c = std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0);
  return std::acos(c) * 180.0 / std::numbers::pi;
}

}  // namespace

OracleEvaluator::OracleEvaluator(const RenderContext& context,
                                 const OracleEvaluationSettings& settings)
    : settings_(settings), tool_mesh_(context.tool.mesh), tool_bounds_(context.tool.mesh.bounds()) {
  spacing_m_ = settings.sample_spacing_m > 0 ? settings.sample_spacing_m
                                             : tool_bounds_.diagonal().norm() / 40.0;
  tool_samples_ = sample_surface(tool_mesh_, spacing_m_);
  world_samples_.resize(tool_samples_.size());
  if (settings.use_embree) embree_ = make_embree_oracle(context.scene);
  if (settings.use_cgal) cgal_ = make_cgal_oracle(context.scene);
  const Oracle* any = embree_ ? embree_.get() : cgal_.get();
  if (any) {
    scene_bounds_ = any->bounds();
    measures_penetration_ = any->distance_only_objects().size() < context.scene.size();
  }
}

OracleEvaluator::~OracleEvaluator() = default;

const std::vector<std::string>& OracleEvaluator::distance_only_objects() const {
  static const std::vector<std::string> none;
  if (embree_) return embree_->distance_only_objects();
  if (cgal_) return cgal_->distance_only_objects();
  return none;
}

OracleTickEvaluation OracleEvaluator::evaluate(int64_t tick, const Pose& tool_pose,
                                               std::span<const Contact> contacts) {
  OracleTickEvaluation out;
  if (!embree_ && !cgal_) return out;
  if (!is_finite(tool_pose) || !world_bounds(tool_bounds_, tool_pose).intersects(scene_bounds_)) {
    out.broad_phase_skipped = true;
    return out;
  }
  for (std::size_t i = 0; i < tool_samples_.size(); ++i)
    world_samples_[i] = tool_pose.transform_point(tool_samples_[i]);

  PointQueryRequest inside_request;
  inside_request.points = world_samples_;
  inside_request.want_inside = true;

  PointQueryResult embree_inside;
  if (embree_ && measures_penetration_) {
    const auto start = std::chrono::steady_clock::now();
    embree_->query_points(inside_request, embree_inside);
    out.embree = penetration_of_inside_points(*embree_, world_samples_, embree_inside.inside);
    out.embree_ns = ns_since(start);
  }

  const bool exact_tick = settings_.exact_every > 0 && tick % settings_.exact_every == 0;
  if (cgal_ && exact_tick && measures_penetration_) {
    const auto start = std::chrono::steady_clock::now();
    PointQueryResult cgal_inside;
    cgal_->query_points(inside_request, cgal_inside);
    out.cgal = penetration_of_inside_points(*cgal_, world_samples_, cgal_inside.inside);
    out.cgal_ns = ns_since(start);
    if (out.embree) {
      for (std::size_t i = 0; i < world_samples_.size(); ++i)
        if (embree_inside.inside[i] != cgal_inside.inside[i]) ++out.inside_disagreements;
    }
    const bool touching = out.cgal->inside > 0 || !contacts.empty();
    if (touching) {
      const auto volume_start = std::chrono::steady_clock::now();
      out.intersection_volume_m3 = cgal_->intersection_volume(transformed(tool_mesh_, tool_pose));
      out.volume_ns = ns_since(volume_start);
    }
  }

  if (!contacts.empty()) {
    const Oracle& oracle = embree_ ? *embree_ : *cgal_;
    std::vector<Vec3> points;
    points.reserve(contacts.size());
    for (const Contact& c : contacts) points.push_back(c.point);
    PointQueryRequest request;
    request.points = points;
    request.want_inside = true;
    request.want_closest = true;
    PointQueryResult truth;
    oracle.query_points(request, truth);
    for (std::size_t i = 0; i < contacts.size(); ++i) {
      const double oracle_depth = truth.inside[i] ? truth.distance[i] : -truth.distance[i];
      out.contact_checks.push_back(
          {angle_deg(contacts[i].normal, truth.normal[i]), contacts[i].depth - oracle_depth});
    }
  }
  return out;
}

}  // namespace hb
