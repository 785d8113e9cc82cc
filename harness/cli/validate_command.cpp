// `hapticbench validate FILE...`: checks scenario, mesh and trace files the
// way a run would read them and says what is wrong and where, without
// running anything. Every file is checked even after one fails.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <exception>
#include <filesystem>
#include <iostream>
#include <new>
#include <sstream>
#include <string>
#include <vector>

#include "algorithms/registry.h"
#include "hapticbench/input_error.h"
#include "hapticbench/mass_properties.h"
#include "hapticbench/shapes.h"
#include "hapticbench/triangle_mesh.h"
#include "harness/cli/command_line.h"
#include "harness/cli/commands.h"
#include "harness/cli/plugin_isolation.h"
#include "harness/mesh_io/mesh_io.h"
#include "harness/plugins/plugin_loader.h"
#include "harness/process/interrupt.h"
#include "harness/process/memory_limit.h"
#include "harness/reference/trace_clearance.h"
#include "harness/run/run_request.h"
#include "harness/scenario/input_error_context.h"
#include "harness/scenario/scenario.h"
#include "harness/trace/device_trajectory.h"
#include "harness/trace/trace.h"

namespace hb {

namespace {

const std::string kUsage =
    "usage: hapticbench validate FILE... [--progress STYLE] [--quiet]\n"
    "  checks each file as a run would read it, by extension:\n"
    "    .json                   scenario (meshes, trace and algorithm parameters included)\n"
    "    .off .obj .stl .ply     triangle mesh (must bound a solid)\n"
    "    .csv                    trace, hapticbench CSV\n"
    "    .txt .tum               trace, TUM format\n"
    "  prints \"OK: FILE\" for each valid file; exit code 2 if any file is invalid.\n" +
    std::string(kProgressUsage);

std::string lowercase_extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

std::string vector_text(const Vec3& v) {
  // Round-off (1e-17 m in a centre of mass) would read as a real offset.
  const double scale = v.cwiseAbs().maxCoeff();
  auto clean = [&](double x) { return std::abs(x) <= 1e-12 * std::max(scale, 1.0) ? 0.0 : x; };
  std::ostringstream out;
  out << "(" << clean(v.x()) << ", " << clean(v.y()) << ", " << clean(v.z()) << ")";
  return out.str();
}

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

void validate_scenario(const std::string& path, std::ostream& report, ProgressDisplay& progress) {
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
      << vector_text(context.tool.mass.centre_of_mass) << " m (tool frame); trace "
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

void validate_mesh(const std::string& path, std::ostream& report) {
  const TriangleMesh mesh = read_mesh_file(path);
  require_valid_mesh(mesh, path);
  const Eigen::AlignedBox3d bounds = mesh.bounds();
  const MassProperties unit_density = mass_properties_from_density(mesh, 1.0);
  report << "mesh: " << mesh.vertices.size() << " vertices, " << mesh.triangles.size()
         << " triangles, closed and outward-oriented; bounds " << vector_text(bounds.min())
         << " to " << vector_text(bounds.max()) << ", volume " << unit_density.volume_m3
         << ", centroid " << vector_text(unit_density.centre_of_mass)
         << " (file units; metres at scale 1)\n";
}

void validate_trace(const std::string& path, TraceFileFormat format, std::ostream& report) {
  const Trace trace = read_trace_file(path, format);
  const std::size_t n = trace.samples.size();
  report << "trace (" << (format == TraceFileFormat::kTum ? "TUM" : "hapticbench CSV") << "): " << n
         << " samples";
  if (n >= 1) {
    const double span_s = static_cast<double>(trace.samples.back().t_ns) * 1e-9;
    report << " from t = 0 to " << span_s << " s";
    if (n >= 2 && span_s > 0)
      report << ", mean rate " << static_cast<double>(n - 1) / span_s << " Hz";
    report << ", " << (trace.samples.front().twist ? "with" : "without") << " velocities"
           << trace_reading_note(trace.info);
  }
  report << "\n";
  for (const std::string& warning : trace_plausibility_warnings(trace))
    std::cerr << "warning: " << path << ": " << warning << "\n";
  // What run does with it: resample onto the 1 kHz clock (spans checked).
  try {
    (void)DeviceTrajectory::of_trace(trace, 0);
  } catch (const InputError& error) {
    throw InputError(path, error.location(), error.message());
  }
}

// Writes what it found to `report`; throws InputError for what is wrong.
void validate_file(const std::string& path, std::ostream& report, ProgressDisplay& progress) {
  const std::string extension = lowercase_extension(path);
  if (extension == ".json") {
    validate_scenario(path, report, progress);
  } else if (extension == ".off" || extension == ".obj" || extension == ".stl" ||
             extension == ".ply") {
    validate_mesh(path, report);
  } else if (extension == ".csv") {
    validate_trace(path, TraceFileFormat::kHapticbenchCsv, report);
  } else if (extension == ".txt" || extension == ".tum") {
    validate_trace(path, TraceFileFormat::kTum, report);
  } else {
    throw InputError(path, "",
                     "unknown file type \"" + extension +
                         "\"; expected .json (scenario), .off/.obj/.stl/.ply (mesh), .csv or "
                         ".txt/.tum (trace)");
  }
}

}  // namespace

namespace {
struct ValidateArguments {
  std::vector<std::string> files;
  std::optional<ProgressStyle> progress;
};

// Throws UsageError or HelpRequested.
ValidateArguments parse_validate_arguments(const std::vector<std::string>& args) {
  ValidateArguments parsed;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    check_help(arg);
    if (parse_progress_option(args, i, parsed.progress)) continue;
    if (arg.size() > 1 && arg[0] == '-')
      throw UsageError{"validate: unknown option \"" + arg + "\""};
    parsed.files.push_back(arg);
  }
  if (parsed.files.empty()) throw UsageError{"validate: no file given"};
  return parsed;
}
}  // namespace

int validate_command(const std::vector<std::string>& args) {
  int exit_code = 0;
  const auto parsed_files =
      parse_command_line([&] { return parse_validate_arguments(args); }, kUsage, exit_code);
  if (!parsed_files) return exit_code;
  const std::vector<std::string>& files = parsed_files->files;
  // Building renderers runs the code of the plugins given (--plugin,
  // HAPTICBENCH_PLUGINS): in a child this process watches.
  std::vector<std::string> plugin_algorithms;
  for (const LoadedPlugin& plugin : loaded_plugins())
    plugin_algorithms.insert(plugin_algorithms.end(), plugin.algorithms.begin(),
                             plugin.algorithms.end());
  if (should_isolate_plugins(plugin_algorithms)) return run_plugins_isolated("validate", args);

  // Building a scenario's renderers and oracles can take a while (meshes
  // without cached structures); progress shows when it takes over a second.
  ProgressDisplay progress = make_progress_display(parsed_files->progress, 1.0);
  int status = kExitOk;
  for (std::size_t i = 0; i < files.size(); ++i) {
    const std::string& file = files[i];
    std::ostringstream prefix;
    if (files.size() > 1) prefix << "[" << i + 1 << "/" << files.size() << "] ";
    progress.set_prefix(prefix.str());
    std::ostringstream report;
    try {
      validate_file(file, report, progress);
      report << "OK: " << file << "\n";
      progress.print_above(std::cout, report.str());
    } catch (const InputError& error) {
      progress.finish_task();  // the file's line ends with it
      progress.print_above(std::cout, report.str());
      progress.print_above(std::cerr, "error: " + std::string(error.what()) + "\n");
      status = std::max<int>(status, kExitBadInput);
    } catch (const Interrupted&) {
      throw;  // main reports it and exits with 128 + the signal
    } catch (const std::bad_alloc&) {
      // An input that needs more memory than the ceiling: the user's.
      progress.finish_task();
      progress.print_above(std::cout, report.str());
      progress.print_above(std::cerr, "error: " + file + ": " + memory_limit_message() + "\n");
      status = std::max<int>(status, kExitBadInput);
    } catch (const std::exception& error) {
      progress.finish_task();
      progress.print_above(std::cout, report.str());
      progress.print_above(std::cerr, "internal error: " + file + ": " + error.what() + "\n");
      status = std::max<int>(status, kExitInternal);
    }
  }
  return status;
}

}  // namespace hb
