#include "harness/reference/oracle_evaluation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "algorithms/core/build_progress.h"
#include "hapticbench/input_error.h"
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

const PenetrationResult* OracleTickEvaluation::first_penetration() const {
  for (const auto& backend : backends)
    if (backend) return &backend->result;
  return nullptr;
}

int64_t OracleTickEvaluation::total_ns() const {
  int64_t ns = volume_ns + distance_ns;
  for (const auto& backend : backends)
    if (backend) ns += backend->ns;
  return ns;
}

OracleEvaluator::OracleEvaluator(const RenderContext& context,
                                 const OracleEvaluationSettings& settings)
    : settings_(settings), tool_mesh_(context.tool.mesh), tool_bounds_(context.tool.mesh.bounds()) {
  for (const std::string& name : settings.backends)
    if (!oracle_backend_index(name))
      throw std::invalid_argument("unknown oracle backend \"" + name + "\"");
  // The oracles sample the tool's surface and CGAL intersects it with the
  // scene: a self-intersecting or open tool has no inside, no volume.
  if (!settings.backends.empty()) {
    announce_build_stage("checking the tool mesh");
    if (auto defect = inside_outside_defect(context.tool.mesh))
      throw InputError("", "/tool",
                       "the tool mesh is " + *defect +
                           "; the oracles' penetration and intersection volume need a closed, "
                           "non-self-intersecting tool (repair it, or set \"reference\": "
                           "{\"oracle\": \"none\"})");
  }
  spacing_m_ = settings.sample_spacing_m > 0 ? settings.sample_spacing_m
                                             : tool_bounds_.diagonal().norm() / 40.0;
  announce_build_stage("tool surface samples");
  tool_samples_ = sample_surface(tool_mesh_, spacing_m_);
  world_samples_.resize(tool_samples_.size());
  const auto entries = oracle_backends();
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (std::find(settings.backends.begin(), settings.backends.end(), entries[i].name) ==
        settings.backends.end())
      continue;
    announce_build_stage(std::string(entries[i].name) + " scene");
    backends_.push_back({i, &entries[i], entries[i].make(context.scene)});
  }
  if (!backends_.empty()) {
    const Oracle& primary = *backends_.front().oracle;
    scene_bounds_ = primary.bounds();
    measures_penetration_ = primary.distance_only_objects().size() < context.scene.size();
    if (!measures_penetration_ && !tool_samples_.empty()) {
      announce_build_stage("tool triangle clusters");
      distance_search_.emplace(tool_mesh_, tool_samples_, spacing_m_);
    }
  }
}

OracleEvaluator::~OracleEvaluator() = default;

const std::vector<std::string>& OracleEvaluator::distance_only_objects() const {
  static const std::vector<std::string> none;
  return backends_.empty() ? none : backends_.front().oracle->distance_only_objects();
}

std::string_view OracleEvaluator::primary_name() const {
  return backends_.empty() ? std::string_view() : backends_.front().entry->name;
}

std::optional<double> OracleEvaluator::primary_penetration(const Pose& tool_pose) {
  if (backends_.empty() || !measures_penetration_ || !is_finite(tool_pose)) return std::nullopt;
  if (!world_bounds(tool_bounds_, tool_pose).intersects(scene_bounds_)) return 0.0;
  for (std::size_t i = 0; i < tool_samples_.size(); ++i)
    world_samples_[i] = tool_pose.transform_point(tool_samples_[i]);
  PointQueryRequest request;
  request.points = world_samples_;
  request.want_inside = true;
  const Oracle& oracle = *backends_.front().oracle;
  oracle.query_points(request, primary_inside_);
  return penetration_of_inside_points(oracle, world_samples_, primary_inside_.inside).max_depth_m;
}

OracleTickEvaluation OracleEvaluator::evaluate(int64_t tick, const Pose& tool_pose,
                                               std::span<const Contact> contacts) {
  OracleTickEvaluation out;
  if (backends_.empty()) return out;
  // Distance-only scenes are measured from one tool diagonal out, where
  // there is a distance worth reporting but nothing to touch yet.
  Eigen::AlignedBox3d reach = scene_bounds_;
  if (!measures_penetration_ && !reach.isEmpty()) {
    const double margin = tool_bounds_.diagonal().norm();
    reach.min().array() -= margin;
    reach.max().array() += margin;
  }
  if (!is_finite(tool_pose) || !world_bounds(tool_bounds_, tool_pose).intersects(reach)) {
    out.broad_phase_skipped = true;
    return out;
  }
  for (std::size_t i = 0; i < tool_samples_.size(); ++i)
    world_samples_[i] = tool_pose.transform_point(tool_samples_[i]);

  PointQueryRequest inside_request;
  inside_request.points = world_samples_;
  inside_request.want_inside = true;

  out.backends.resize(oracle_backends().size());
  const bool exact_tick = settings_.exact_every > 0 && tick % settings_.exact_every == 0;
  bool primary_evaluated = false;
  for (std::size_t b = 0; b < backends_.size() && measures_penetration_; ++b) {
    Backend& backend = backends_[b];
    if (backend.entry->exact_ticks_only && !exact_tick) continue;
    const auto start = std::chrono::steady_clock::now();
    PointQueryResult& inside = b == 0 ? primary_inside_ : inside_;
    backend.oracle->query_points(inside_request, inside);
    BackendPenetration& penetration = out.backends[backend.index].emplace();
    penetration.result =
        penetration_of_inside_points(*backend.oracle, world_samples_, inside.inside);
    penetration.ns = ns_since(start);
    if (b == 0) {
      primary_evaluated = true;
    } else if (primary_evaluated) {
      for (std::size_t i = 0; i < world_samples_.size(); ++i)
        if (primary_inside_.inside[i] != inside.inside[i]) ++out.inside_disagreements;
    }
    const bool touching = penetration.result.inside > 0 || !contacts.empty();
    if (backend.entry->intersection_volume && touching && !out.intersection_volume_m3) {
      const auto volume_start = std::chrono::steady_clock::now();
      out.intersection_volume_m3 =
          backend.oracle->intersection_volume(transformed(tool_mesh_, tool_pose));
      out.volume_ns = ns_since(volume_start);
    }
  }

  if (!measures_penetration_) {
    const auto start = std::chrono::steady_clock::now();
    PointQueryRequest request;
    request.points = world_samples_;
    request.want_inside = false;
    request.want_closest = true;
    const Oracle& oracle = *backends_.front().oracle;
    oracle.query_points(request, inside_);
    // The samples' distances start the search between the tool's triangles
    // and the scene's; a backend that cannot list the triangles near a
    // point leaves both figures null rather than a sample's distance.
    if (distance_search_) {
      if (const std::optional<ToolSceneDistance> mesh =
              distance_search_->evaluate(oracle, tool_pose, inside_)) {
        out.min_distance_m = mesh->distance_m;
        out.crossing = mesh->crossing;
      }
    }
    out.distance_ns = ns_since(start);
  }

  if (!contacts.empty()) {
    const Oracle& oracle = *backends_.front().oracle;
    std::vector<Vec3> points;
    points.reserve(contacts.size());
    for (const Contact& c : contacts) points.push_back(c.point);
    PointQueryResult truth;
    oracle.query_points({.points = points, .want_inside = true, .want_closest = true}, truth);
    for (std::size_t i = 0; i < contacts.size(); ++i) {
      const double oracle_depth = truth.inside[i] ? truth.distance[i] : -truth.distance[i];
      out.contact_checks.push_back(
          {angle_deg(contacts[i].normal, truth.normal[i]), contacts[i].depth - oracle_depth});
    }
  }
  return out;
}

}  // namespace hb
