// What `hapticbench validate` checks of one file: a scenario, a mesh or a
// trace, read the way a run would read it, and what it says of it.
#pragma once

#include <ostream>
#include <string>

#include "hapticbench/pose.h"
#include "harness/progress/progress_display.h"

namespace hb {

/// Checks the file at `path` by its extension (.json scenario, .off .obj
/// .stl .ply mesh, .csv or .txt/.tum trace) and writes what it found to
/// `report`, its warnings to stderr; throws InputError for what is wrong.
void validate_file(const std::string& path, std::ostream& report, ProgressDisplay& progress);

/// A scenario file: read and built as `run` would (renderers and ground
/// truth), described, and how close its trace brings the tool to the scene.
void validate_scenario_file(const std::string& path, std::ostream& report,
                            ProgressDisplay& progress);

/// "(x, y, z)", components within round-off of 0 (relative to the largest)
/// shown as 0.
std::string rounded_vector_text(const Vec3& v);

}  // namespace hb
