// Reading triangle meshes from OFF, OBJ, STL and PLY files, with strict
// readers whose memory is bounded by the file's size (mesh_formats.h).
#pragma once

#include <string>

#include "hapticbench/triangle_mesh.h"

namespace hb {

/// Reads a polygon mesh (format by extension: .off .obj .stl .ply), splits
/// polygons into triangles, merges exactly coincident vertices (STL), and
/// multiplies coordinates by scale (metres per file unit). Throws InputError
/// naming the file for a missing file, an unknown extension or a parse
/// failure. Does not validate closedness: call require_valid_mesh.
TriangleMesh read_mesh_file(const std::string& path, double scale = 1.0);

}  // namespace hb
