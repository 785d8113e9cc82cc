// The smallest renderer: no proxy. The device's tool-frame origin is a
// point; inside a scene box it is pushed out through the nearest face by a
// spring of `stiffness` N/m and a damper of `damping` N·s/m (without it a
// spring sampled at 1 kHz gives energy: the run fails its passivity check).
#include <hapticbench/input_error.h>
#include <hapticbench/plugin.h>
#include <hapticbench/proxy/device_output.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

namespace {

class OriginPenalty final : public hb::Renderer {
 public:
  OriginPenalty(const hb::RenderContext& context, const hb::ParamSet& params)
      : context_(context),
        stiffness_(params.number("stiffness", 2000, 0, 1e6)),
        damping_(params.number("damping", 2, 0, 1e3)) {
    for (std::size_t i = 0; i < context.scene.size(); ++i)
      if (!context.scene[i].shape || context.scene[i].shape->type != hb::ShapeType::kBox)
        throw hb::InputError("", "/scene/" + std::to_string(i),
                             "origin_penalty renders boxes only");
  }

  void reset(const hb::Pose&) override {}

  hb::TickResult step(const hb::DeviceSample& device) override {
    contacts_.clear();
    hb::Wrench raw;  // N and N·m, world; zero by default
    const hb::Vec3 point = device.pose.p;
    for (const hb::SceneObject& box : context_.scene) {
      const hb::Vec3 local = box.pose.inverse_transform_point(point);
      const hb::Vec3 room = box.shape->size / 2 - local.cwiseAbs();  // m to each face pair
      if ((room.array() <= 0).any()) continue;                       // outside this box
      int axis = 0;
      const double depth = room.minCoeff(&axis);
      hb::Vec3 normal = hb::Vec3::Zero();
      normal[axis] = local[axis] >= 0 ? 1 : -1;
      normal = box.pose.q * normal;
      const double push = stiffness_ * depth - damping_ * device.twist.v.dot(normal);  // N
      raw.force += std::max(0.0, push) * normal;
      contacts_.push_back({point, normal, depth});  // the oracle checks depth and normal here
    }
    hb::TickResult result;
    result.display = hb::device_output(raw, context_.device, result.flags);
    result.proxy = device.pose;  // no proxy: the tool is where the device is
    result.contacts = contacts_;
    return result;
  }

 private:
  hb::RenderContext context_;
  double stiffness_;  ///< N/m
  double damping_;    ///< N·s/m
  std::vector<hb::Contact> contacts_;
};

std::unique_ptr<hb::Renderer> create(const hb::RenderContext& context, const hb::ParamSet& params) {
  return std::make_unique<OriginPenalty>(context, params);
}

const hb::AlgorithmEntry kAlgorithms[] = {
    {.name = "origin_penalty",
     .summary = "example plugin: a spring on the tool's origin inside boxes, no proxy",
     .create = &create}};

}  // namespace

HAPTICBENCH_PLUGIN("origin_penalty", kAlgorithms)
