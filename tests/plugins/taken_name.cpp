// A plugin whose second algorithm takes a built-in algorithm's name: it must
// be refused whole (its first algorithm is not registered either).
#include <hapticbench/plugin.h>

namespace {
std::unique_ptr<hb::Renderer> create_nothing(const hb::RenderContext&, const hb::ParamSet&) {
  return nullptr;
}
const hb::AlgorithmEntry kAlgorithms[] = {
    {"fresh_name", "would be fine alone", &create_nothing},
    {"god_object", "collides with the built-in god-object", &create_nothing}};
}  // namespace

HAPTICBENCH_PLUGIN("taken_name", kAlgorithms)
