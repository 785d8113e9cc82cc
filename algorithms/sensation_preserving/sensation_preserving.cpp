#include "algorithms/sensation_preserving/sensation_preserving.h"

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "algorithms/core/build_progress.h"
#include "algorithms/sensation_preserving/convex_hierarchy.h"
#include "algorithms/sensation_preserving/hierarchy_contacts.h"
#include "hapticbench/proxy/device_output.h"
#include "hapticbench/proxy/dynamic_proxy.h"
#include "hapticbench/proxy/penalty_contact.h"
#include "hapticbench/proxy/proxy_settings.h"
#include "hapticbench/proxy/slow_loop_mailbox.h"

namespace hb {

namespace {

struct SensationPreservingSettings {
  HierarchyContactSettings query;
  int clusters = 5;   ///< 0: no clustering
  bool cache = true;  ///< load and store hierarchies in the cache folder
  ConvexHierarchySettings hierarchy;
  ProxySettings proxy;
  PenaltyGains gains;
};

SensationPreservingSettings read_settings(const RenderContext& context, const ParamSet& params) {
  SensationPreservingSettings settings;
  settings.query.perceptibility_threshold =
      params.number("perceptibility_threshold", settings.query.perceptibility_threshold, 0.0, 1e6);
  settings.query.contact_margin_m = params.number("contact_margin", 0.0, 0.0, 1.0);
  settings.clusters = static_cast<int>(params.integer("clusters", settings.clusters, 0, 1000));
  settings.hierarchy.max_piece_vertices = static_cast<int>(
      params.integer("max_piece_vertices", settings.hierarchy.max_piece_vertices, 4, 100000));
  settings.cache = params.flag("cache", settings.cache);
  settings.proxy = read_proxy_settings(params, context.tool);
  settings.gains = read_penalty_gains(params);
  return settings;
}

// Linearised contact planes from the latest query, on their way to the haptic step.
struct ClusterPlanes {
  std::vector<ContactPlane> planes;
  HierarchyContactStats stats;
  int raw_contacts = 0;
};

// Sensation-preserving's work counters (WorkCounters slots and names): the
// slow loop's contact query, counted on the tick that installs it.
struct SensationPreservingWork {
  enum Slot : std::size_t {
    kNodePairsTested,
    kPieceTests,
    kGjkCalls,
    kAxisSeparations,
  };
  // Each slot beside its name, so that the two cannot drift apart.
  static constexpr WorkCounters::Names kNames = [] {
    WorkCounters::Names names{};
    names[kNodePairsTested] = "node_pairs_tested";
    names[kPieceTests] = "piece_tests";
    names[kGjkCalls] = "gjk_calls";
    names[kAxisSeparations] = "axis_separations";
    return names;
  }();
};

class SensationPreservingRenderer : public Renderer, public SlowLoop {
 public:
  SensationPreservingRenderer(const RenderContext& context,
                              const SensationPreservingSettings& settings)
      : settings_(settings),
        limits_(context.device),
        proxy_(proxy_body(context.tool, settings.proxy.proxy_mass_kg, context.gravity),
               context.coupling, settings.proxy.integrator, context.dt_s) {
    proxy_.follow_device_in_free_space(
        {.tool_radius_m = context.tool.mesh.radius_about(context.tool.mass.centre_of_mass)});
    bool all_cached = settings.cache;
    const auto hierarchy_of = [&](const TriangleMesh& mesh, const std::string& content_hash,
                                  const std::string& name) {
      if (!settings.cache) {
        announce_build_stage("convex hierarchy of " + name + ": building (cache off)");
        return build_convex_hierarchy(mesh, settings.hierarchy);
      }
      bool hit = false;
      ConvexHierarchy hierarchy =
          cached_convex_hierarchy(mesh, content_hash, settings.hierarchy, &hit, name);
      all_cached = all_cached && hit;
      return hierarchy;
    };
    tool_ = hierarchy_of(context.tool.mesh, context.tool.content_hash, "tool");
    for (const SceneObject& object : context.scene) {
      scene_.push_back(hierarchy_of(object.mesh, object.content_hash,
                                    object.name.empty() ? "scene object" : object.name));
      scene_poses_.push_back(object.pose);
    }
    axes_.resize(scene_.size());
    report_.cache_hit = all_cached;
    auto add_size = [&](const ConvexHierarchy& h) {
      double vertices = 0;
      for (const ConvexNode& node : h.nodes) vertices += static_cast<double>(node.vertices.size());
      report_.memory_bytes += static_cast<int64_t>(vertices * sizeof(Vec3));
      return static_cast<double>(h.pieces_per_level.empty() ? 0 : h.pieces_per_level.front());
    };
    report_.details.emplace_back("tool_pieces", add_size(tool_));
    report_.details.emplace_back("tool_levels", static_cast<double>(tool_.pieces_per_level.size()));
    double scene_pieces = 0;
    for (const ConvexHierarchy& h : scene_) scene_pieces += add_size(h);
    report_.details.emplace_back("scene_pieces", scene_pieces);
  }

  void reset(const Pose& start) override {
    proxy_.reset(start);
    // A replay starts as a new renderer does: no directions kept.
    axes_.assign(scene_.size(), SeparatingAxes());
    planes_.clear();
    contacts_.clear();
    mailbox_.clear();
  }

  TickResult step(const DeviceSample& device) override {
    TickResult result;
    if (ClusterPlanes* installed = mailbox_.take(result.flags)) {
      planes_.swap(installed->planes);
      result.work.names = &SensationPreservingWork::kNames;
      result.work.add(SensationPreservingWork::kNodePairsTested,
                      installed->stats.node_pairs_tested);
      result.work.add(SensationPreservingWork::kPieceTests, installed->stats.piece_tests);
      result.work.add(SensationPreservingWork::kGjkCalls, installed->stats.gjk_calls);
      result.work.add(SensationPreservingWork::kAxisSeparations, installed->stats.axis_separations);
    }
    // The installed planes' penalty forces, clamped over the implicit step.
    contact_forces_.use(planes_, settings_.gains);
    const Wrench raw = proxy_.advance(device, &contact_forces_, result.flags);
    result.display = device_output(raw, limits_, result.flags);
    result.proxy = proxy_.tool_pose();
    contacts_.clear();
    for (const ContactPlane& plane : planes_) {
      const double depth = contact_depth(plane, proxy_.state());
      if (depth > 0)
        contacts_.push_back(
            Contact{contact_tool_point_world(plane, proxy_.state()), plane.normal, depth});
    }
    result.contacts = contacts_;
    return result;
  }

  SlowLoop* slow_loop() override { return this; }

  std::unique_ptr<Result> run_slow_update() override {
    auto box = mailbox_.box();
    ClusterPlanes& update = box->data;
    const RigidBodyState& state = proxy_.state();
    if (!is_finite(state)) return box;
    const Pose tool_pose = proxy_.tool_pose();
    raw_.clear();
    for (std::size_t i = 0; i < scene_.size(); ++i)
      find_hierarchy_contacts(tool_, tool_pose, scene_[i], scene_poses_[i], settings_.query, raw_,
                              update.stats, &axes_[i]);
    update.raw_contacts = static_cast<int>(raw_.size());
    const Mat3 rotation_t = state.q.conjugate().toRotationMatrix();
    auto add_plane = [&](const Vec3& point, const Vec3& normal, double depth) {
      // The tool's deepest point is half the depth below the contact point,
      // the scene's surface half the depth above it.
      ContactPlane plane;
      plane.normal = normal;
      plane.plane_point = point + 0.5 * depth * normal;
      plane.tool_point = rotation_t * (point - 0.5 * depth * normal - state.x);
      update.planes.push_back(plane);
    };
    if (settings_.clusters == 0) {
      for (const PieceContact& contact : raw_)
        add_plane(contact.point, contact.normal, contact.depth - contact.gap_m);
    } else {
      for (const ContactCluster& cluster : cluster_contacts(raw_, settings_.clusters))
        add_plane(cluster.point, cluster.normal, cluster.depth);
    }
    return box;
  }

  void install_slow_result(std::unique_ptr<Result> result) override {
    mailbox_.install(std::move(result), "sensation_preserving");
  }

  BuildReport build_report() const override { return report_; }

 private:
  SensationPreservingSettings settings_;
  DeviceLimits limits_;
  DynamicProxy proxy_;
  ConvexHierarchy tool_;
  std::vector<ConvexHierarchy> scene_;
  std::vector<Pose> scene_poses_;
  /// Per scene object, the directions that separated inner pieces in the
  /// last contact query (the slow loop's; SeparatingAxes).
  std::vector<SeparatingAxes> axes_;
  BuildReport report_;
  std::vector<PieceContact> raw_;      ///< the slow loop's scratch
  std::vector<ContactPlane> planes_;   ///< installed, evaluated by every haptic step
  PenaltyPlaneForces contact_forces_;  ///< planes_' forces over a step, reused
  std::vector<Contact> contacts_;
  SlowLoopMailbox<ClusterPlanes> mailbox_;
};

}  // namespace

std::unique_ptr<Renderer> create_sensation_preserving(const RenderContext& context,
                                                      const ParamSet& params) {
  return std::make_unique<SensationPreservingRenderer>(context, read_settings(context, params));
}

}  // namespace hb
