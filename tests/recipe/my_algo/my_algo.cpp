#include "algorithms/my_algo/my_algo.h"

#include <algorithm>

namespace hb {

namespace {

class MyAlgoRenderer : public Renderer {
 public:
  MyAlgoRenderer(double radius_m, double stiffness, double plane_height_m)
      : radius_m_(radius_m), stiffness_(stiffness), plane_height_m_(plane_height_m) {}

  void reset(const Pose&) override {}

  TickResult step(const DeviceSample& device) override {
    TickResult result;
    // m: how far the tool's bounding sphere reaches below the plane.
    const double depth = std::max(0.0, plane_height_m_ + radius_m_ - device.pose.p.z());
    result.display.force = Vec3(0, 0, stiffness_ * depth);
    result.proxy = device.pose;
    result.proxy.p.z() += depth;
    return result;
  }

 private:
  double radius_m_, stiffness_, plane_height_m_;
};

}  // namespace

std::unique_ptr<Renderer> create_my_algo(const RenderContext& context, const ParamSet& params) {
  const double stiffness = params.number("stiffness", 1000.0, 0.0, 1e6);
  const double plane_height_m = params.number("plane_height_m", 0.0, -10.0, 10.0);
  return std::make_unique<MyAlgoRenderer>(context.tool.mesh.radius_about(Vec3::Zero()), stiffness,
                                          plane_height_m);
}

}  // namespace hb
