#include "algorithms/voxmap_pointshell/voxmap_pointshell.h"

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/voxmap_pointshell/pointshell_contacts.h"
#include "algorithms/voxmap_pointshell/voxmap.h"
#include "hapticbench/cache_directory.h"
#include "hapticbench/disk_cache.h"
#include "hapticbench/input_error.h"
#include "hapticbench/proxy/device_output.h"
#include "hapticbench/proxy/dynamic_proxy.h"
#include "hapticbench/proxy/proxy_settings.h"

namespace hb {

namespace {

// Voxel blocks (8³) the lookup arrays may span over the voxelised region.
constexpr double kMaxBlocks = 64e6;
// Points the pointshell may have (about the tool's area / spacing²).
constexpr double kMaxPointShellPoints = 4e6;
// The reach box is grown by this fraction of the tool's radius (the proxy
// can slide a little beyond the device).
constexpr double kReachMarginPerToolRadius = 0.1;

constexpr double kMinVoxelSize = 2e-5;  // m

// Points looked up a tick at most, about (pointshell_contacts.h); 0: every
// point, McNeely's rendering as published. A budget trades accuracy for
// time where many points crowd the contact (docs/algorithms/voxmap-pointshell.md).
constexpr int64_t kDefaultPointBudget = 0;

struct VoxmapPointShellSettings {
  VoxmapSettings voxmap;
  double pointshell_spacing_m = 0;
  PointShellGains gains;
  int64_t point_budget = 0;  ///< points looked up a tick at most (about); 0: no budget
  ProxySettings proxy;
  bool cache = true;
};

VoxmapPointShellSettings read_settings(const RenderContext& context, const ParamSet& params) {
  VoxmapPointShellSettings settings;
  // At least 20 µm: OpenVDB refuses a linear transform whose scale's cube
  // is within its tolerance of zero (1.2e-5 m fails, 1.5e-5 m does), which
  // was an internal error at the documented 1e-5.
  settings.voxmap.voxel_size_m = params.number("voxel_size", 0.002, kMinVoxelSize, 1.0);
  settings.pointshell_spacing_m =
      params.number("pointshell_spacing", settings.voxmap.voxel_size_m, kMinVoxelSize, 1.0);
  settings.gains.stiffness = params.number("point_stiffness", 10000, 0, 1e9);
  const std::string variant = params.choice("variant", "voxmap", {"voxmap", "signed_distance"});
  settings.voxmap.signed_distance = variant == "signed_distance";
  for (const SceneObject& object : context.scene) {
    if (settings.voxmap.signed_distance && object.distance_only) {
      throw InputError("", params.field("variant"),
                       "scene object \"" + object.name +
                           "\" is distance_only (an open surface without inside): the "
                           "signed_distance variant needs inside/outside; use \"voxmap\"");
    }
  }
  settings.gains.signed_distance = settings.voxmap.signed_distance;
  // Both variants keep φ: the voxmap variant takes a point's depth from it
  // once the point is past the surface layer (pointshell_contacts.h).
  settings.voxmap.signed_distance = true;
  settings.voxmap.interior_layers = static_cast<int>(params.integer("interior_layers", 3, 1, 64));
  settings.voxmap.proximity_layers = static_cast<int>(params.integer("proximity_layers", 2, 0, 64));
  // The signed-distance force is the gradient of one potential only when a
  // point entering the surface layer has a layer outside it to come from:
  // with none, a point 0.5 mm deep felt nothing and a loop generated 51 µJ.
  if (settings.gains.signed_distance && settings.voxmap.proximity_layers == 0)
    throw InputError("", params.field("proximity_layers"),
                     "the signed_distance variant needs at least 1 proximity layer (its force "
                     "is the gradient of one potential only with a layer outside the surface); "
                     "got 0");
  settings.gains.braking_viscosity = params.number("braking_viscosity", 5, 0, 1e9);
  settings.point_budget = params.integer("point_budget", kDefaultPointBudget, 0, 100000000);
  settings.proxy = read_proxy_settings(params, context.tool);
  settings.cache = params.flag("cache", true);
  return settings;
}

Eigen::AlignedBox3d scene_bounds(const std::vector<SceneObject>& scene) {
  Eigen::AlignedBox3d box;
  for (const SceneObject& object : scene)
    for (const Vec3& v : object.mesh.vertices) box.extend(object.pose.transform_point(v));
  return box;
}

// The region to voxelise: the reach box grown by the proximity band and a
// margin, or the whole scene grown by the band.
Eigen::AlignedBox3d voxelised_region(const RenderContext& context,
                                     const VoxmapPointShellSettings& settings, double tool_radius_m,
                                     const ParamSet& params) {
  const double h = settings.voxmap.voxel_size_m;
  const double band = exterior_band_m(settings.voxmap) + h;
  Eigen::AlignedBox3d region = scene_bounds(context.scene);
  double margin = band;
  if (context.reach && !context.reach->isEmpty()) {
    region = *context.reach;
    margin += kReachMarginPerToolRadius * tool_radius_m;
  }
  if (region.isEmpty()) return region;
  region.min().array() -= margin;
  region.max().array() += margin;
  const Eigen::AlignedBox3d scene = scene_bounds(context.scene);
  if (!scene.isEmpty()) {
    const Eigen::AlignedBox3d used = region.intersection(
        Eigen::AlignedBox3d(scene.min().array() - band, scene.max().array() + band));
    const Vec3 blocks = (used.sizes() / (VoxelLookup::kBlockEdge * h)).array() + 2;
    if (!used.isEmpty() && blocks.prod() > kMaxBlocks) {
      throw InputError("", params.field("voxel_size"),
                       "a voxel size of " + std::to_string(h) + " m needs about " +
                           std::to_string(static_cast<long long>(blocks.prod())) +
                           " blocks of 8³ voxels over the reachable scene (limit " +
                           std::to_string(static_cast<long long>(kMaxBlocks)) +
                           "); use a larger voxel_size");
    }
  }
  return region;
}

// About one point per spacing² of the tool's surface: refuse spacings that
// would give an unreasonable pointshell.
void check_pointshell_size(const TriangleMesh& tool, double spacing_m, const ParamSet& params) {
  double area = 0;
  for (const auto& t : tool.triangles) {
    const Vec3& a = tool.vertices[static_cast<std::size_t>(t[0])];
    const Vec3& b = tool.vertices[static_cast<std::size_t>(t[1])];
    const Vec3& c = tool.vertices[static_cast<std::size_t>(t[2])];
    area += 0.5 * (b - a).cross(c - a).norm();
  }
  const double points = area / (spacing_m * spacing_m);
  if (points > kMaxPointShellPoints) {
    throw InputError(
        "", params.field(params.has("pointshell_spacing") ? "pointshell_spacing" : "voxel_size"),
        "a pointshell spacing of " + std::to_string(spacing_m) + " m gives about " +
            std::to_string(static_cast<long long>(points)) + " points on the tool (limit " +
            std::to_string(static_cast<long long>(kMaxPointShellPoints)) +
            "); use a larger spacing");
  }
}

class VoxmapPointShellRenderer : public Renderer {
 public:
  VoxmapPointShellRenderer(const RenderContext& context, const VoxmapPointShellSettings& settings,
                           const ParamSet& params)
      : limits_(context.device),
        gains_(settings.gains),
        point_budget_(settings.point_budget),
        body_(proxy_body(context.tool, settings.proxy.proxy_mass_kg, context.gravity)),
        proxy_(body_, context.coupling, settings.proxy.integrator, context.dt_s) {
    CacheSettings cache;
    cache.enabled = false;  // "cache": false, or no cache folder: nothing is read or written
    if (settings.cache) {
      const std::optional<std::filesystem::path> directory = default_cache_directory();
      cache.enabled = directory.has_value();
      if (directory) cache.directory = *directory;
    }
    // Sizes are checked before anything is built.
    const double tool_radius = context.tool.mesh.radius_about(Vec3::Zero());
    const Eigen::AlignedBox3d region = voxelised_region(context, settings, tool_radius, params);
    check_pointshell_size(context.tool.mesh, settings.pointshell_spacing_m, params);
    const PointShellPoints points =
        build_pointshell(context.tool.mesh, settings.pointshell_spacing_m, cache);
    if (points.points.empty())
      throw InputError(
          "", params.field(params.has("pointshell_spacing") ? "pointshell_spacing" : "voxel_size"),
          "the tool (" + std::to_string(context.tool.mesh.triangles.size()) +
              " triangles) has no surface voxel at a pointshell spacing of " +
              std::to_string(settings.pointshell_spacing_m) +
              " m: it fits within one voxel; use a smaller spacing");
    shell_ = make_pointshell(points.points, points.normals, context.tool.mass.centre_of_mass);
    // Out of contact the proxy is the device, jumping to it at most a voxel
    // at a time, so that it never steps over the proximity voxels, where
    // braking acts.
    proxy_.follow_device_in_free_space(
        {.tool_radius_m = shell_.radius, .max_point_step_m = settings.voxmap.voxel_size_m});
    shell_stats_ = points.stats;
    scene_ = build_scene_voxmap(context.scene, region, settings.voxmap, cache);
    voxel_size_m_ = settings.voxmap.voxel_size_m;
    hits_.contacts.reserve(shell_.points.size());
    hits_.braking.reserve(shell_.points.size());
    hits_.braking_fields.reserve(shell_.points.size());
    contacts_.reserve(shell_.points.size());
  }

  void reset(const Pose& start) override {
    proxy_.reset(start);
    front_.clear();
    hits_valid_ = false;
    hits_.clear();
    contacts_.clear();
  }

  TickResult step(const DeviceSample& device) override {
    TickResult result;
    Forces forces(*this, result.work);
    const Wrench raw = proxy_.advance(device, &forces, result.flags);
    // The points at the pose this tick reports: its contacts, and the
    // contact set the next tick starts from.
    find_hits(proxy_.state(), result.work);
    contacts_.clear();
    report_contacts(shell_, hits_, scene_.lookup, gains_, proxy_.state(), contacts_);
    result.display = device_output(raw, limits_, result.flags);
    result.proxy = proxy_.tool_pose();
    result.contacts = contacts_;
    return result;
  }

  BuildReport build_report() const override {
    BuildReport report;
    const int64_t shell_bytes = static_cast<int64_t>(
        shell_.points.size() * 2 * sizeof(Vec3) + shell_.nodes.size() * sizeof(PointShell::Node));
    report.memory_bytes = scene_.lookup.memory_bytes() + shell_bytes;
    report.cache_hit = scene_.stats.cache_hit && shell_stats_.cache_hit;
    const std::vector<int64_t> states = scene_.lookup.state_counts();
    report.details = {
        {"voxel_size_m", voxel_size_m_},
        {"pointshell_points", static_cast<double>(shell_.points.size())},
        {"pointshell_tree_nodes", static_cast<double>(shell_.nodes.size())},
        {"pointshell_tree_leaves", static_cast<double>(shell_.leaves)},
        {"pointshell_bytes", static_cast<double>(shell_bytes)},
        {"pointshell_seconds", shell_stats_.seconds},
        {"pointshell_cache_hit", shell_stats_.cache_hit ? 1.0 : 0.0},
        {"voxmap_seconds", scene_.stats.seconds},
        {"voxmap_cache_hit", scene_.stats.cache_hit ? 1.0 : 0.0},
        {"voxmap_cache_rebuilt", scene_.stats.cache_problem.empty() ? 0.0 : 1.0},
        {"voxmap_objects", static_cast<double>(scene_.objects_voxelised)},
        {"voxmap_vdb_bytes", static_cast<double>(scene_.stats.vdb_bytes)},
        {"voxmap_vdb_active_voxels", static_cast<double>(scene_.stats.active_voxels)},
        {"voxmap_lookup_bytes", static_cast<double>(scene_.lookup.memory_bytes())},
        {"voxmap_dense_blocks", static_cast<double>(scene_.lookup.dense_blocks())},
        {"voxmap_interior_voxels", static_cast<double>(states[1])},
        {"voxmap_surface_voxels", static_cast<double>(states[2])},
        {"voxmap_proximity_voxels", static_cast<double>(states[3])},
    };
    return report;
  }

 private:
  // The contact forces at whatever state the integrator asks; the hits are
  // looked up again only when the pose differs from the last lookup's.
  class Forces : public ForceModel {
   public:
    Forces(VoxmapPointShellRenderer& renderer, WorkCounters& work)
        : renderer_(renderer), work_(work) {}
    ForceEvaluation evaluate(const RigidBodyState& state, bool with_jacobians) override {
      if (!renderer_.hits_valid_ || state.x != renderer_.hits_pose_.p ||
          state.q.coeffs() != renderer_.hits_pose_.q.coeffs()) {
        renderer_.find_hits(state, work_);
      }
      return pointshell_wrench(renderer_.shell_, renderer_.hits_, renderer_.gains_, state,
                               with_jacobians);
    }

   private:
    VoxmapPointShellRenderer& renderer_;
    WorkCounters& work_;
  };

  void find_hits(const RigidBodyState& state, WorkCounters& work) {
    find_pointshell_hits_coherent(shell_, scene_.lookup, gains_, state, point_budget_, front_,
                                  hits_, work);
    hits_pose_ = Pose{state.x, state.q};
    hits_valid_ = true;
  }

  DeviceLimits limits_;
  PointShellGains gains_;
  int64_t point_budget_ = 0;
  RigidBody body_;
  DynamicProxy proxy_;
  PointShell shell_;
  BuildStats shell_stats_;
  SceneVoxmap scene_;
  double voxel_size_m_ = 0;
  PointShellFront front_;  ///< where the last lookup's tree search stopped
  PointShellHits hits_;    ///< at hits_pose_
  Pose hits_pose_;         ///< proxy pose (centre of mass, orientation) of the last lookup
  bool hits_valid_ = false;
  std::vector<Contact> contacts_;  ///< reported by the last step
};

}  // namespace

std::unique_ptr<Renderer> create_voxmap_pointshell(const RenderContext& context,
                                                   const ParamSet& params) {
  const VoxmapPointShellSettings settings = read_settings(context, params);
  // Before the (possibly long) build: a misspelt key fails at once.
  params.reject_unknown();
  return std::make_unique<VoxmapPointShellRenderer>(context, settings, params);
}

}  // namespace hb
