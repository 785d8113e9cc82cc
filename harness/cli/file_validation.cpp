#include "harness/cli/file_validation.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "hapticbench/input_error.h"
#include "hapticbench/mass_properties.h"
#include "hapticbench/triangle_mesh.h"
#include "harness/mesh_io/mesh_io.h"
#include "harness/trace/device_trajectory.h"
#include "harness/trace/trace.h"

namespace hb {

namespace {

std::string lowercase_extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

void validate_mesh(const std::string& path, std::ostream& report) {
  const TriangleMesh mesh = read_mesh_file(path);
  require_valid_mesh(mesh, path);
  const Eigen::AlignedBox3d bounds = mesh.bounds();
  const MassProperties unit_density = mass_properties_from_density(mesh, 1.0);
  report << "mesh: " << mesh.vertices.size() << " vertices, " << mesh.triangles.size()
         << " triangles, closed and outward-oriented; bounds " << rounded_vector_text(bounds.min())
         << " to " << rounded_vector_text(bounds.max()) << ", volume " << unit_density.volume_m3
         << ", centroid " << rounded_vector_text(unit_density.centre_of_mass)
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

}  // namespace

std::string rounded_vector_text(const Vec3& v) {
  // Round-off (1e-17 m in a centre of mass) would read as a real offset.
  const double scale = v.cwiseAbs().maxCoeff();
  auto clean = [&](double x) { return std::abs(x) <= 1e-12 * std::max(scale, 1.0) ? 0.0 : x; };
  std::ostringstream out;
  out << "(" << clean(v.x()) << ", " << clean(v.y()) << ", " << clean(v.z()) << ")";
  return out.str();
}

void validate_file(const std::string& path, std::ostream& report, ProgressDisplay& progress) {
  const std::string extension = lowercase_extension(path);
  if (extension == ".json") {
    validate_scenario_file(path, report, progress);
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

}  // namespace hb
