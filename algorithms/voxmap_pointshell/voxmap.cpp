// The only file that includes OpenVDB.
#include "algorithms/voxmap_pointshell/voxmap.h"

#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/MeshToVolume.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <fstream>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "algorithms/core/build_progress.h"
#include "hapticbench/content_hash.h"
#include "hapticbench/disk_cache.h"

namespace hb {

namespace {

// OpenVDB's mesh-to-volume conversion asks this, from its worker threads,
// whether to give up: it does once the user asked the build to stop. The
// caller then throws with check_build_stop() on its own thread.
struct BuildStopInterrupter : openvdb::util::NullInterrupter {
  bool wasInterrupted(int /*percent*/ = -1) override { return build_stop_requested(); }
};

// Bump when what a cache file holds, or how it is computed, changes.
// Layout version and a hash of this file and its header (set by CMake):
// caches built by other code do not match.
constexpr const char* kFormat =
    "hapticbench voxmap_pointshell cache v1 builder " HB_BUILDER_SOURCES_HASH;
constexpr const char* kStatesGrid = "voxmap_states";
constexpr const char* kDistanceGrid = "signed_distance";
constexpr const char* kPointShellGrid = "pointshell_normals";

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

void initialise_openvdb() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

// A triangle mesh placed by a pose, in OpenVDB's index space (world / h).
class MeshAdapter {
 public:
  MeshAdapter(const TriangleMesh& mesh, const Pose& pose, double voxel_size_m)
      : triangles_(mesh.triangles) {
    points_.reserve(mesh.vertices.size());
    for (const Vec3& v : mesh.vertices) {
      const Vec3 index = pose.transform_point(v) / voxel_size_m;
      points_.emplace_back(index.x(), index.y(), index.z());
    }
  }
  std::size_t polygonCount() const { return triangles_.size(); }
  std::size_t pointCount() const { return points_.size(); }
  std::size_t vertexCount(std::size_t) const { return 3; }
  // OpenVDB reads every triangle through here, also inside its narrow-band
  // expansion, which asks its interrupter nothing for minutes: a stop
  // request throws here, on a TBB worker, and TBB passes the exception on
  // to the thread that called meshToVolume.
  void getIndexSpacePoint(std::size_t n, std::size_t v, openvdb::Vec3d& pos) const {
    if (v == 0) check_build_stop();
    pos = points_[static_cast<std::size_t>(triangles_[n][v])];
  }

 private:
  const std::vector<std::array<int, 3>>& triangles_;
  std::vector<openvdb::Vec3d> points_;
};

VoxelState classify(double phi, double h, int proximity_layers) {
  if (phi < -0.5 * h) return VoxelState::kInterior;
  if (phi <= 0.5 * h) return VoxelState::kSurface;
  if (phi <= (proximity_layers + 0.5) * h) return VoxelState::kProximity;
  return VoxelState::kFree;
}

int exterior_band_voxels(const VoxmapSettings& settings) { return settings.proximity_layers + 2; }

int interior_band_voxels(const VoxmapSettings& settings) {
  return settings.signed_distance ? std::max(settings.interior_layers, 1) + 1 : 2;
}

Eigen::AlignedBox3d world_bounds(const SceneObject& object) {
  Eigen::AlignedBox3d box;
  for (const Vec3& v : object.mesh.vertices) box.extend(object.pose.transform_point(v));
  return box;
}

int floor_div(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

// The voxel (index) box covering a world box, widened to whole blocks.
openvdb::CoordBBox block_aligned_index_box(const Eigen::AlignedBox3d& world, double h) {
  const int e = VoxelLookup::kBlockEdge;
  openvdb::Coord low, high;
  for (int a = 0; a < 3; ++a) {
    const int first = static_cast<int>(std::floor(world.min()[a] / h + 0.5));
    const int last = static_cast<int>(std::floor(world.max()[a] / h + 0.5));
    low[a] = floor_div(first, e) * e;
    high[a] = (floor_div(last, e) + 1) * e - 1;
  }
  return openvdb::CoordBBox(low, high);
}

std::string key_of_box(const openvdb::CoordBBox& box) {
  std::string text;
  for (int a = 0; a < 3; ++a)
    text += std::to_string(box.min()[a]) + ":" + std::to_string(box.max()[a]) + " ";
  return text;
}

// A cache entry's payload is the grids as an OpenVDB stream
// (hapticbench/disk_cache.h keeps key, length and checksum).

// Reads the named grids stored under `key`; an empty list (and a reason in
// `problem`) when the entry is absent, damaged or lacks a grid.
openvdb::GridPtrVec read_cache(const DiskCache& cache, const std::string& key,
                               const std::vector<std::string>& names, std::string& problem) {
  DiskCache::Lookup lookup = cache.read(key);
  problem = lookup.problem;
  if (!lookup.payload) return {};
  const auto fail = [&](const std::string& why) {
    problem = "cache file " + cache.path_of(key).string() + " " + why + "; rebuilt";
    return openvdb::GridPtrVec{};
  };
  try {
    std::istringstream vdb(std::string(*lookup.payload), std::ios::binary);
    openvdb::io::Stream reader(vdb, false);
    const openvdb::GridPtrVecPtr all = reader.getGrids();
    openvdb::GridPtrVec grids;
    for (const std::string& name : names) {
      const auto found = std::find_if(all->begin(), all->end(), [&](const auto& grid) {
        return grid && grid->getName() == name;
      });
      if (found == all->end()) return fail("lacks grid " + name);
      grids.push_back(*found);
    }
    return grids;
  } catch (const std::exception& e) {
    return fail(std::string("unreadable (") + e.what() + ")");
  }
}

// Stores the grids under `key`; reports instead of failing.
void write_cache(const DiskCache& cache, const std::string& key, const openvdb::GridCPtrVec& grids,
                 std::string& problem) {
  try {
    std::ostringstream vdb(std::ios::binary);
    openvdb::io::Stream(vdb).write(grids);
    const std::string written = cache.write(key, vdb.str());
    if (!written.empty()) problem = written;
  } catch (const std::exception& e) {
    problem = "cache file " + cache.path_of(key).string() + " not written (" + e.what() + ")";
  }
}

// φ of every selected object, united by the minimum.
openvdb::FloatGrid::Ptr scene_distance(const std::vector<const SceneObject*>& objects,
                                       const VoxmapSettings& settings) {
  const double h = settings.voxel_size_m;
  const openvdb::math::Transform::Ptr transform =
      openvdb::math::Transform::createLinearTransform(h);
  openvdb::FloatGrid::Ptr result;
  for (const SceneObject* object : objects) {
    const MeshAdapter mesh(object->mesh, object->pose, h);
    // An open surface (distance_only) has no inside: unsigned distance, so
    // its voxels are surface, proximity or free, never interior.
    const int flags = openvdb::tools::DISABLE_RENORMALIZATION |
                      (object->distance_only ? openvdb::tools::UNSIGNED_DISTANCE_FIELD : 0);
    BuildStopInterrupter interrupter;
    openvdb::FloatGrid::Ptr grid = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
        interrupter, mesh, *transform, static_cast<float>(exterior_band_voxels(settings)),
        static_cast<float>(interior_band_voxels(settings)), flags);
    check_build_stop();  // a grid cut short by the interrupter is never used
    if (!result) {
      result = grid;
      continue;
    }
    // Union of level sets: the smaller signed distance wins (empties `grid`).
    openvdb::tools::csgUnion(*result, *grid);
  }
  return result;
}

// The states (and, for the signed-distance variant, φ) restricted to `region`.
openvdb::GridPtrVec voxmap_grids(const openvdb::FloatGrid& phi, const openvdb::CoordBBox& region,
                                 const VoxmapSettings& settings) {
  const double h = settings.voxel_size_m;
  const float background = static_cast<float>(exterior_band_voxels(settings) * h);
  openvdb::Int32Grid::Ptr states = openvdb::Int32Grid::create(0);
  states->setName(kStatesGrid);
  states->setTransform(phi.transform().copy());
  openvdb::FloatGrid::Ptr distance;
  if (settings.signed_distance) {
    distance = openvdb::FloatGrid::create(background);
    distance->setName(kDistanceGrid);
    distance->setTransform(phi.transform().copy());
    distance->setGridClass(openvdb::GRID_LEVEL_SET);
  }
  // Tiles above the leaf level: interior tiles of the sign flood fill.
  auto tiles = phi.tree().cbeginValueAll();
  tiles.setMaxDepth(openvdb::FloatTree::ValueAllCIter::LEAF_DEPTH - 1);
  for (; tiles; ++tiles) {
    openvdb::CoordBBox box;
    tiles.getBoundingBox(box);
    box.intersect(region);
    if (box.empty()) continue;
    const auto state = static_cast<int32_t>(classify(*tiles, h, settings.proximity_layers));
    if (state != 0) states->fill(box, state, true);
    if (distance) distance->fill(box, *tiles, tiles.isValueOn());
  }
  openvdb::Int32Grid::Accessor state_access = states->getAccessor();
  std::optional<openvdb::FloatGrid::Accessor> distance_access;
  if (distance) distance_access.emplace(distance->getAccessor());
  for (auto leaf = phi.tree().cbeginLeaf(); leaf; ++leaf) {
    check_build_stop();
    if (!region.hasOverlap(leaf->getNodeBoundingBox())) continue;
    for (auto v = leaf->cbeginValueAll(); v; ++v) {
      const openvdb::Coord c = v.getCoord();
      if (!region.isInside(c)) continue;
      const auto state = static_cast<int32_t>(classify(*v, h, settings.proximity_layers));
      if (state != 0) state_access.setValue(c, state);
      if (distance) {
        if (v.isValueOn()) {
          distance_access->setValue(c, *v);
        } else {
          distance_access->setValueOff(c, *v);
        }
      }
    }
  }
  openvdb::GridPtrVec grids{states};
  if (distance) grids.push_back(distance);
  return grids;
}

// Copies the grids into the haptic loop's arrays over `region`.
VoxelLookup fill_lookup(const openvdb::Int32Grid& states, const openvdb::FloatGrid* distance,
                        const openvdb::CoordBBox& region, const VoxmapSettings& settings) {
  const int e = VoxelLookup::kBlockEdge;
  const Eigen::Vector3i block_min(region.min().x() / e, region.min().y() / e, region.min().z() / e);
  const Eigen::Vector3i block_count((region.max().x() + 1) / e - block_min.x(),
                                    (region.max().y() + 1) / e - block_min.y(),
                                    (region.max().z() + 1) / e - block_min.z());
  const double h = settings.voxel_size_m;
  VoxelLookup lookup(h, block_min, block_count, distance != nullptr,
                     static_cast<float>(exterior_band_m(settings)));
  openvdb::Int32Grid::ConstAccessor state_access = states.getConstAccessor();
  std::optional<openvdb::FloatGrid::ConstAccessor> distance_access;
  if (distance) distance_access.emplace(distance->getConstAccessor());
  std::array<uint8_t, VoxelLookup::kBlockVoxels> block_states;
  std::array<float, VoxelLookup::kBlockVoxels> block_distances;
  for (int x = 0; x < block_count.x(); ++x) {
    check_build_stop();
    for (int y = 0; y < block_count.y(); ++y) {
      for (int z = 0; z < block_count.z(); ++z) {
        const Eigen::Vector3i b(x, y, z);
        const Eigen::Vector3i first = (block_min + b) * e;
        const openvdb::Coord origin(first.x(), first.y(), first.z());
        const openvdb::Int32Tree::LeafNodeType* state_leaf = states.tree().probeConstLeaf(origin);
        const openvdb::FloatTree::LeafNodeType* distance_leaf =
            distance ? distance->tree().probeConstLeaf(origin) : nullptr;
        if (!state_leaf && !distance_leaf) {
          const float phi = distance ? distance_access->getValue(origin) : 0.0f;
          lookup.set_uniform_block(b, static_cast<VoxelState>(state_access.getValue(origin)), phi);
          continue;
        }
        for (int n = 0; n < VoxelLookup::kBlockVoxels; ++n) {
          const openvdb::Coord c = origin + openvdb::Coord(n >> 6, (n >> 3) & 7, n & 7);
          block_states[n] =
              static_cast<uint8_t>(state_leaf ? state_leaf->getValue(c) : state_access.getValue(c));
          if (distance)
            block_distances[n] =
                distance_leaf ? distance_leaf->getValue(c) : distance_access->getValue(c);
        }
        const bool uniform =
            !distance && std::all_of(block_states.begin(), block_states.end(),
                                     [&](uint8_t s) { return s == block_states[0]; });
        if (uniform) {
          lookup.set_uniform_block(b, static_cast<VoxelState>(block_states[0]), 0.0f);
        } else {
          lookup.set_dense_block(b, block_states.data(), block_distances.data());
        }
      }
    }
  }
  lookup.finish();
  return lookup;
}

int64_t memory_of(const openvdb::GridPtrVec& grids) {
  int64_t bytes = 0;
  for (const openvdb::GridBase::Ptr& grid : grids) bytes += static_cast<int64_t>(grid->memUsage());
  return bytes;
}

}  // namespace

double exterior_band_m(const VoxmapSettings& settings) {
  return exterior_band_voxels(settings) * settings.voxel_size_m;
}

SceneVoxmap build_scene_voxmap(const std::vector<SceneObject>& scene,
                               const Eigen::AlignedBox3d& region, const VoxmapSettings& settings,
                               const CacheSettings& cache) {
  initialise_openvdb();
  const auto start = Clock::now();
  const double h = settings.voxel_size_m;
  const double band = (exterior_band_voxels(settings) + 1) * h;
  SceneVoxmap result;

  // Only objects whose band meets the region, and only the part of the
  // region their bands cover.
  std::vector<const SceneObject*> objects;
  Eigen::AlignedBox3d covered;
  for (const SceneObject& object : scene) {
    Eigen::AlignedBox3d grown = world_bounds(object);
    grown.min().array() -= band;
    grown.max().array() += band;
    if (!grown.intersects(region)) continue;
    objects.push_back(&object);
    covered.extend(grown.intersection(region));
  }
  result.objects_voxelised = static_cast<int>(objects.size());
  if (objects.empty()) {
    result.stats.seconds = seconds_since(start);
    return result;
  }
  const openvdb::CoordBBox index_region = block_aligned_index_box(covered, h);

  std::string key = std::string(kFormat) + "\nscene voxmap\nvoxel_size " + exact_key_text(h) +
                    "\nproximity_layers " + std::to_string(settings.proximity_layers) +
                    "\nvariant " + (settings.signed_distance ? "signed_distance" : "voxmap") +
                    "\ninterior_band " + std::to_string(interior_band_voxels(settings)) +
                    "\nregion " + key_of_box(index_region);
  for (const SceneObject* object : objects) {
    key += "\nobject " + object->content_hash + " " + mesh_geometry_hash(object->mesh) + " pose " +
           exact_key_text(object->pose);
  }
  std::vector<std::string> names{kStatesGrid};
  if (settings.signed_distance) names.push_back(kDistanceGrid);

  openvdb::GridPtrVec grids;
  const DiskCache disk(cache.enabled ? std::optional(cache.directory) : std::nullopt, "voxmap");
  const std::filesystem::path file = disk.path_of(key);
  if (cache.enabled) {
    result.stats.cache_file = file.string();
    grids = read_cache(disk, key, names, result.stats.cache_problem);
    const bool complete =
        grids.size() == names.size() &&
        openvdb::gridPtrCast<openvdb::Int32Grid>(grids[0]) != nullptr &&
        (!settings.signed_distance || openvdb::gridPtrCast<openvdb::FloatGrid>(grids[1]));
    if (!grids.empty() && !complete) {
      result.stats.cache_problem = "cache file " + file.string() + " incomplete; rebuilt";
      grids.clear();
    }
    result.stats.cache_hit = !grids.empty();
  }
  announce_cached_build("voxmap", !grids.empty());
  if (grids.empty()) {
    const openvdb::FloatGrid::Ptr phi = scene_distance(objects, settings);
    grids = voxmap_grids(*phi, index_region, settings);
    if (cache.enabled) {
      openvdb::GridCPtrVec to_write(grids.begin(), grids.end());
      write_cache(disk, key, to_write, result.stats.cache_problem);
    }
  }
  const auto states = openvdb::gridPtrCast<openvdb::Int32Grid>(grids[0]);
  const auto distance =
      settings.signed_distance ? openvdb::gridPtrCast<openvdb::FloatGrid>(grids[1]) : nullptr;
  result.lookup = fill_lookup(*states, distance.get(), index_region, settings);
  result.stats.vdb_bytes = memory_of(grids);
  result.stats.active_voxels = static_cast<int64_t>(states->activeVoxelCount());
  result.stats.seconds = seconds_since(start);
  return result;
}

namespace {

// Whether the voxel at `c` is a surface voxel: its centre within half a
// voxel of the surface (|φ| < h/2: about one point per h² of surface), or,
// of a pair of 6-neighbours on opposite sides of the surface (φ ≤ 0 inside,
// φ > 0 outside), the one nearer it (the inside one on a tie). The second
// rule makes every place where the surface passes between two voxel centres
// give a point, whatever the alignment: a face lying exactly halfway between
// two layers of centres (φ = ±h/2 on both, within float rounding) gives one
// layer, where |φ| < h/2 alone could keep neither (a 3 cm cube at 2 mm had
// an empty pointshell).
bool is_surface_voxel(const openvdb::FloatGrid::ConstAccessor& at, const openvdb::Coord& c,
                      double spacing_m) {
  const float here = at.getValue(c);
  if (std::abs(here) < 0.5 * spacing_m) return true;
  for (int a = 0; a < 3; ++a)
    for (int sign : {-1, 1}) {
      openvdb::Coord step(0, 0, 0);
      step[a] = sign;
      const float there = at.getValue(c + step);
      if ((here <= 0) == (there <= 0)) continue;
      const float near = std::abs(here), far = std::abs(there);
      if (near < far || (near == far && here <= 0)) return true;
    }
  return false;
}

}  // namespace

PointShellPoints build_pointshell(const TriangleMesh& tool_mesh, double spacing_m,
                                  const CacheSettings& cache) {
  initialise_openvdb();
  const auto start = Clock::now();
  PointShellPoints result;
  const std::string key = std::string(kFormat) + "\npointshell\nspacing " +
                          exact_key_text(spacing_m) + "\ntool " + mesh_geometry_hash(tool_mesh);

  openvdb::Vec3SGrid::Ptr normals;
  const DiskCache disk(cache.enabled ? std::optional(cache.directory) : std::nullopt, "pointshell");
  if (cache.enabled) {
    result.stats.cache_file = disk.path_of(key).string();
    const openvdb::GridPtrVec grids =
        read_cache(disk, key, {kPointShellGrid}, result.stats.cache_problem);
    if (!grids.empty()) normals = openvdb::gridPtrCast<openvdb::Vec3SGrid>(grids[0]);
    result.stats.cache_hit = normals != nullptr;
  }
  announce_cached_build("pointshell", normals != nullptr);
  if (!normals) {
    const openvdb::math::Transform::Ptr transform =
        openvdb::math::Transform::createLinearTransform(spacing_m);
    const MeshAdapter mesh(tool_mesh, Pose{}, spacing_m);
    openvdb::Int32Grid closest(0);
    BuildStopInterrupter interrupter;
    const openvdb::FloatGrid::Ptr phi = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
        interrupter, mesh, *transform, 2.0f, 2.0f, openvdb::tools::DISABLE_RENORMALIZATION,
        &closest);
    check_build_stop();
    normals = openvdb::Vec3SGrid::create(openvdb::Vec3s(0, 0, 0));
    normals->setName(kPointShellGrid);
    normals->setTransform(transform->copy());
    openvdb::FloatGrid::ConstAccessor at = phi->getConstAccessor();
    openvdb::Int32Grid::ConstAccessor closest_at = closest.getConstAccessor();
    openvdb::Vec3SGrid::Accessor out = normals->getAccessor();
    for (auto v = phi->cbeginValueOn(); v; ++v) {
      const openvdb::Coord c = v.getCoord();
      if (!is_surface_voxel(at, c, spacing_m)) continue;
      Vec3 gradient;
      for (int a = 0; a < 3; ++a) {
        openvdb::Coord step(0, 0, 0);
        step[a] = 1;
        gradient[a] = (at.getValue(c + step) - at.getValue(c - step)) / (2 * spacing_m);
      }
      Vec3 inward;
      if (gradient.norm() > 0.5) {
        inward = -gradient.normalized();
      } else {
        // Where φ has a ridge (thin parts), the nearest face decides.
        const int triangle = closest_at.getValue(c);
        inward = -tool_mesh.face_normal(static_cast<std::size_t>(triangle));
        if (inward.squaredNorm() == 0) continue;
      }
      out.setValue(c, openvdb::Vec3s(static_cast<float>(inward.x()), static_cast<float>(inward.y()),
                                     static_cast<float>(inward.z())));
    }
    // An empty pointshell (a tool within one voxel) is refused by the
    // renderer: never cached.
    if (cache.enabled && normals->activeVoxelCount() > 0) {
      write_cache(disk, key, openvdb::GridCPtrVec{normals}, result.stats.cache_problem);
    }
  }
  // The same values, whether built or loaded: points at voxel centres,
  // normals read back from the grid.
  for (auto v = normals->cbeginValueOn(); v; ++v) {
    const openvdb::Coord c = v.getCoord();
    result.points.push_back(spacing_m * Vec3(c.x(), c.y(), c.z()));
    result.normals.push_back(Vec3((*v).x(), (*v).y(), (*v).z()).normalized());
  }
  result.stats.vdb_bytes = static_cast<int64_t>(normals->memUsage());
  result.stats.active_voxels = static_cast<int64_t>(normals->activeVoxelCount());
  result.stats.seconds = seconds_since(start);
  return result;
}

}  // namespace hb
