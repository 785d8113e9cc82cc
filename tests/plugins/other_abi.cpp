// A plugin built against another plugin ABI version than this hapticbench's.
#include <hapticbench/plugin.h>

namespace {
std::unique_ptr<hb::Renderer> create_nothing(const hb::RenderContext&, const hb::ParamSet&) {
  return nullptr;
}
const hb::AlgorithmEntry kAlgorithms[] = {{"from_the_future", "never registered", &create_nothing}};
}  // namespace

extern "C" __attribute__((visibility("default"))) const hb::PluginDescription*
hapticbench_plugin() {
  static const hb::PluginDescription description{hb::kPluginAbiVersion + 1, "other_abi",
                                                 kAlgorithms, 1};
  return &description;
}
