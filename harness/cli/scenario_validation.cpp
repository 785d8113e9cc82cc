// What `hapticbench validate` checks of a scenario file (file_validation.h).
#include <algorithm>
#include <iostream>
#include <sstream>

#include "hapticbench/input_error.h"
#include "hapticbench/shapes.h"
#include "harness/cli/file_validation.h"
#include "harness/reference/trace_clearance.h"
#include "harness/run/run_request.h"
#include "harness/scenario/input_error_context.h"
#include "harness/scenario/scenario.h"

namespace hb {

namespace {

// How close the device's trace brings the tool to the scene: the placement
// aid of a scenario's author (the tool at the device's pose, no renderer).
void report_clearance(const Scenario& scenario, std::ostream& report, ProgressDisplay& progress) {
  // Poses evenly spread over the trace, first and last tick included; a
  // subset of the tool's vertices: a fraction of a second on real meshes.
  constexpr int64_t kPoses = 100;
  constexpr std::size_t kVertices = 500;
  const int64_t ticks = scenario.trajectory.ticks();
  if (ticks == 0) return;
  const int64_t count = std::min(ticks, kPoses);
  std::vector<Pose> poses;
  std::vector<int64_t> pose_ticks;
  for (int64_t k = 0; k < count; ++k) {
    const int64_t tick = count == 1 ? 0 : k * (ticks - 1) / (count - 1);
    pose_ticks.push_back(tick);
    poses.push_back(scenario.trajectory.at(tick).pose);
  }
  progress.task(scenario.name);
  progress.phase("the tool's clearance along the trace");
  const TraceClearance clearance =
      trace_clearance(scenario.context.scene, scenario.context.tool.mesh, poses, kVertices);
  progress.finish_task();
  auto gap_text = [&](const ClearanceSample& sample) {
    std::ostringstream text;
    text.precision(3);
    text << std::fixed << sample.gap_m * 1e3 << " mm at t = "
         << static_cast<double>(pose_ticks[sample.pose_index]) * scenario.context.dt_s << " s";
    return text.str();
  };
  report << "clearance of the tool from the scene at the device's pose (" << clearance.vertices
         << " tool vertices, " << clearance.poses << " poses along the trace; below 0: the "
         << "device's tool is inside by that much): " << gap_text(clearance.first)
         << " at the start, least " << gap_text(clearance.closest) << ", "
         << gap_text(clearance.last) << " at the end";
  const bool distance_only =
      std::any_of(scenario.context.scene.begin(), scenario.context.scene.end(),
                  [](const SceneObject& o) { return o.distance_only; });
  if (distance_only) report << " (distance-only objects have no inside: 0 at the closest)";
  report << "\n";
  // Vertices farther than this from the scene all along: the tool never
  // touches it (a face may come closer than its corners, by less than this
  // on any tool the scenarios use).
  if (clearance.first.gap_m < 0)
    std::cerr << "warning: " << scenario.path << ": the trace starts with the device's tool "
              << -clearance.first.gap_m * 1e3
              << " mm inside the scene: the proxy starts inside it (move the trace's start)\n";
  constexpr double kUntouchedGapM = 1e-3;
  if (clearance.closest.gap_m > kUntouchedGapM)
    std::cerr << "warning: " << scenario.path << ": the trace never brings the tool to the scene "
              << "(it stays " << clearance.closest.gap_m * 1e3
              << " mm away at its closest): no algorithm will render a contact\n";
}

}  // namespace

void validate_scenario_file(const std::string& path, std::ostream& report,
                            ProgressDisplay& progress) {
  RunRequest request;
  request.scenario = ScenarioSource::file(path);
  request.options.progress = &progress;
  const Scenario scenario = read_scenario(request);
  for (const std::string& warning : scenario.warnings)
    std::cerr << "warning: " << path << ": " << warning << "\n";
  // Everything `run` builds before it replays: the renderers (which reject
  // bad or unknown algorithm parameters) and the ground truth (whose oracles
  // reject open or self-intersecting scene meshes).
  try {
    prepare_request(scenario, request);
  } catch (const InputError& error) {
    throw with_default_source(error, scenario.path);
  }

  const RenderContext& context = scenario.context;
  std::ostringstream out;
  out << "scenario \"" << scenario.name << "\": " << context.scene.size() << " scene object"
      << (context.scene.size() == 1 ? "" : "s") << " (";
  for (std::size_t i = 0; i < context.scene.size(); ++i) {
    const SceneObject& object = context.scene[i];
    out << (i ? "; " : "") << object.name << ": "
        << (object.shape ? shape_type_name(object.shape->type) : std::string("mesh")) << ", "
        << object.mesh.triangles.size() << " triangles";
  }
  out << "); tool " << (context.tool.shape ? shape_type_name(context.tool.shape->type) : "mesh")
      << ", " << context.tool.mesh.triangles.size() << " triangles, mass "
      << context.tool.mass.mass_kg << " kg, centre of mass "
      << rounded_vector_text(context.tool.mass.centre_of_mass) << " m (tool frame); trace "
      << scenario.trace_description << ", " << scenario.trajectory.ticks() << " ticks ("
      << static_cast<double>(scenario.trajectory.ticks()) * context.dt_s << " s); algorithms ";
  for (std::size_t i = 0; i < scenario.algorithms.size(); ++i)
    out << (i ? ", " : "") << scenario.algorithms[i].label << " (" << scenario.algorithms[i].name
        << ")";
  out << "; oracle " << scenario.reference.oracle << ", analytic " << scenario.reference.analytic
      << "; " << scenario.budgets.size() << " budget" << (scenario.budgets.size() == 1 ? "" : "s")
      << "; content hash " << scenario.content_hash << ".";
  report << out.str() << "\n";
  report_clearance(scenario, report, progress);
}

}  // namespace hb
