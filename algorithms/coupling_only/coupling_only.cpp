#include "algorithms/coupling_only/coupling_only.h"

#include "hapticbench/proxy/device_output.h"
#include "hapticbench/proxy/dynamic_proxy.h"
#include "hapticbench/proxy/proxy_settings.h"

namespace hb {

namespace {
class CouplingOnlyRenderer : public Renderer {
 public:
  CouplingOnlyRenderer(const RenderContext& context, const ProxySettings& settings)
      : limits_(context.device),
        proxy_(proxy_body(context.tool, settings.proxy_mass_kg, context.gravity), context.coupling,
               settings.integrator, context.dt_s) {}

  void reset(const Pose& start) override { proxy_.reset(start); }

  TickResult step(const DeviceSample& device) override {
    TickResult result;
    const Wrench raw = proxy_.advance(device, nullptr, result.flags);
    result.display = device_output(raw, limits_, result.flags);
    result.proxy = proxy_.tool_pose();
    return result;
  }

 private:
  DeviceLimits limits_;
  DynamicProxy proxy_;
};
}  // namespace

std::unique_ptr<Renderer> create_coupling_only(const RenderContext& context,
                                               const ParamSet& params) {
  return std::make_unique<CouplingOnlyRenderer>(context, read_proxy_settings(params, context.tool));
}

}  // namespace hb
