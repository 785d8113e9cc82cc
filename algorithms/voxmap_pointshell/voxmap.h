// Building the two Voxmap PointShell structures with OpenVDB (McNeely,
// Puterbaugh & Troy 1999), cached on disk. OpenVDB stays inside voxmap.cpp;
// callers see plain types.
//
// Scene voxmap: the union of the scene objects' signed distance fields,
// φ (m, negative inside), from openvdb::tools::meshToVolume with exact
// distances in a narrow band and inside/outside by OpenVDB's sign flood
// fill (an object marked distance_only, an open surface, gets the unsigned
// distance: no interior). Each voxel of edge h takes a state from φ at its centre:
//   surface    |φ| ≤ h/2
//   interior   φ < −h/2
//   proximity  h/2 < φ ≤ (L + 1/2) h      (L proximity layers)
//   free       otherwise.
// Stored as an OpenVDB Int32Grid of states (and, for the signed-distance
// variant, the FloatGrid of φ), restricted to a region, then copied into a
// VoxelLookup for the haptic loop.
//
// PointShell: the centres of the tool's surface voxels (same rule, voxel
// edge = the pointshell spacing, tool frame), each with the inward unit
// normal −∇φ/|∇φ| (central differences of the tool's signed distance).
// Stored as an OpenVDB Vec3SGrid whose active voxels are the points and
// whose values are the normals.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/voxmap_pointshell/voxel_lookup.h"
#include "hapticbench/pose.h"
#include "hapticbench/scene.h"
#include "hapticbench/triangle_mesh.h"

namespace hb {

/// How to voxelise the scene.
struct VoxmapSettings {
  double voxel_size_m = 0.002;   ///< h, m
  int proximity_layers = 2;      ///< L, voxels of proximity state outside the surface layer
  bool signed_distance = false;  ///< keep φ per voxel (for depths past the surface layer)
  int interior_layers = 3;       ///< voxels of exact φ inside the surface (with φ kept)
};

/// Where and whether to cache (voxmap_cache.cpp resolves the folder).
struct CacheSettings {
  bool enabled = true;
  std::filesystem::path directory;  ///< used when enabled
};

/// What building (or loading) a structure cost and produced.
struct BuildStats {
  bool cache_hit = false;
  double seconds = 0;         ///< wall time, build or load
  int64_t vdb_bytes = 0;      ///< memory of the OpenVDB grids (Grid::memUsage)
  int64_t active_voxels = 0;  ///< active voxels of the OpenVDB grids
  std::string cache_file;     ///< file read or written; empty without cache
  std::string cache_problem;  ///< why a cache file was not used or not written, if so
};

/// The scene voxmap, ready for lookups.
struct SceneVoxmap {
  VoxelLookup lookup;
  BuildStats stats;
  int objects_voxelised = 0;  ///< scene objects whose bounds meet the region
};

/// Voxelises the scene objects whose world bounds, grown by the band, meet
/// `region` (world, m), restricted to `region`. Loads the result from the
/// cache when a file with the same key exists and reads back intact (its
/// length and hash checked before OpenVDB parses it); otherwise builds it
/// and writes the file atomically (a temporary file renamed into place). A
/// cache that cannot be read or written is rebuilt or skipped, never fatal.
SceneVoxmap build_scene_voxmap(const std::vector<SceneObject>& scene,
                               const Eigen::AlignedBox3d& region, const VoxmapSettings& settings,
                               const CacheSettings& cache);

/// The tool's pointshell, tool frame.
struct PointShellPoints {
  std::vector<Vec3> points;   ///< m, tool frame: centres of the tool's surface voxels
  std::vector<Vec3> normals;  ///< unit, tool frame, pointing into the tool
  BuildStats stats;
};

/// Builds (or loads from the cache) the pointshell of a closed tool mesh
/// (tool frame) at the given spacing (m).
PointShellPoints build_pointshell(const TriangleMesh& tool_mesh, double spacing_m,
                                  const CacheSettings& cache);

/// The half-width (m) of φ's exterior narrow band for these settings: the
/// distance reported outside it.
double exterior_band_m(const VoxmapSettings& settings);

}  // namespace hb
