// A renderer built outside hapticbench, as a plugin: a 6-DOF penalty proxy
// whose contacts are the tool mesh's vertices inside the scene's boxes.
// Each vertex inside a box is pushed out through the box face nearest to it
// (one linearised point-plane contact, hapticbench/proxy/penalty_contact.h),
// and the proxy with mass follows the device through the virtual coupling,
// integrated with implicit or explicit Euler (hapticbench/proxy/dynamic_proxy.h).
// Contacts are found at the proxy's pose before each step.
#include <hapticbench/input_error.h>
#include <hapticbench/plugin.h>
#include <hapticbench/proxy/device_output.h>
#include <hapticbench/proxy/dynamic_proxy.h>
#include <hapticbench/proxy/penalty_contact.h>
#include <hapticbench/proxy/proxy_settings.h>

#include <memory>
#include <vector>

namespace {

using hb::Vec3;

// A scene box: its pose and half extents (m, box frame).
struct Box {
  hb::Pose pose;
  Vec3 half_extents;
};

class VertexPenalty final : public hb::Renderer {
 public:
  VertexPenalty(const hb::RenderContext& context, const hb::ParamSet& params)
      : settings_(hb::read_proxy_settings(params, context.tool)),
        gains_(hb::read_penalty_gains(params)),
        proxy_(hb::proxy_body(context.tool, settings_.proxy_mass_kg, context.gravity),
               context.coupling, settings_.integrator, context.dt_s),
        limits_(context.device) {
    for (std::size_t i = 0; i < context.scene.size(); ++i) {
      const hb::SceneObject& object = context.scene[i];
      if (!object.shape || object.shape->type != hb::ShapeType::kBox)
        throw hb::InputError("", "/scene/" + std::to_string(i),
                             "vertex_penalty renders box-shaped scene objects only");
      boxes_.push_back({object.pose, object.shape->size / 2});
    }
    for (const Vec3& vertex : context.tool.mesh.vertices)
      tool_points_.push_back(vertex - context.tool.mass.centre_of_mass);
  }

  void reset(const hb::Pose& start) override { proxy_.reset(start); }

  hb::TickResult step(const hb::DeviceSample& device) override {
    find_contacts(proxy_.state());
    forces_.use(planes_, gains_);
    hb::TickResult result;
    const hb::Wrench raw = proxy_.advance(device, &forces_, result.flags);
    result.display = hb::device_output(raw, limits_, result.flags);
    result.proxy = proxy_.tool_pose();
    result.contacts = contacts_;
    return result;
  }

 private:
  // Every tool vertex inside a box, against the box face nearest to it.
  void find_contacts(const hb::RigidBodyState& state) {
    planes_.clear();
    contacts_.clear();
    for (const Vec3& r : tool_points_) {
      const Vec3 point = state.x + state.q * r;  // m, world
      for (const Box& box : boxes_) {
        const Vec3 local = box.pose.inverse_transform_point(point);
        const Vec3 room = box.half_extents - local.cwiseAbs();  // distance to each face pair
        if ((room.array() <= 0).any()) continue;                // outside
        int axis = 0;
        room.minCoeff(&axis);
        Vec3 normal_local = Vec3::Zero();
        normal_local[axis] = local[axis] >= 0 ? 1 : -1;
        Vec3 on_face = local;
        on_face[axis] = normal_local[axis] * box.half_extents[axis];
        const Vec3 normal = box.pose.q * normal_local;
        planes_.push_back({r, box.pose.transform_point(on_face), normal});
        contacts_.push_back({point, normal, room[axis]});
      }
    }
  }

  hb::ProxySettings settings_;
  hb::PenaltyGains gains_;
  hb::DynamicProxy proxy_;
  hb::DeviceLimits limits_;
  std::vector<Box> boxes_;
  std::vector<Vec3> tool_points_;  ///< m, body axes, relative to the centre of mass
  std::vector<hb::ContactPlane> planes_;
  std::vector<hb::Contact> contacts_;
  hb::PenaltyPlaneForces forces_;
};

std::unique_ptr<hb::Renderer> create_vertex_penalty(const hb::RenderContext& context,
                                                    const hb::ParamSet& params) {
  return std::make_unique<VertexPenalty>(context, params);
}

const hb::AlgorithmEntry kAlgorithms[] = {
    {.name = "vertex_penalty",
     .summary = "example plugin: penalty proxy on the tool's vertices inside the scene's boxes",
     .create = &create_vertex_penalty},
};

}  // namespace

HAPTICBENCH_PLUGIN("out_of_tree_renderer", kAlgorithms)
