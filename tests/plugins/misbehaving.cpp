// A plugin whose renderer fails on purpose at a chosen tick of step(), or
// when it is created ("when": "create"): it dereferences a null pointer
// ("crash"), ends the process with exit code 0 ("exit_0", through _exit, so
// that nothing of the process's own runs), or throws ("throw").
// hapticbench must name the plugin and the label, and never report success.
#include <hapticbench/plugin.h>
#include <unistd.h>

#include <memory>
#include <stdexcept>
#include <string>

namespace {

class Misbehaving final : public hb::Renderer {
 public:
  explicit Misbehaving(const hb::ParamSet& params)
      : failure_(params.choice("failure", "crash", {"crash", "exit_0", "throw"})),
        at_tick_(params.integer("at_tick", 10, 0, 1000000)) {
    if (params.choice("when", "step", {"step", "create"}) == "create") fail();
  }

  void reset(const hb::Pose& start) override {
    pose_ = start;
    tick_ = 0;
  }

  hb::TickResult step(const hb::DeviceSample& device) override {
    if (tick_++ == at_tick_) fail();
    hb::TickResult result;
    result.proxy = device.pose;
    pose_ = device.pose;
    return result;
  }

 private:
  void fail() const {
    if (failure_ == "exit_0") ::_exit(0);
    if (failure_ == "throw") throw std::runtime_error("misbehaving renderer failed on purpose");
    volatile int* nowhere = nullptr;
    *nowhere = 1;
  }

  std::string failure_;
  long long at_tick_;
  long long tick_ = 0;
  hb::Pose pose_;
};

std::unique_ptr<hb::Renderer> create_misbehaving(const hb::RenderContext&,
                                                 const hb::ParamSet& params) {
  return std::make_unique<Misbehaving>(params);
}

const hb::AlgorithmEntry kAlgorithms[] = {
    {"misbehaving", "test plugin: crashes, exits or throws inside step()", &create_misbehaving},
};

}  // namespace

HAPTICBENCH_PLUGIN("misbehaving", kAlgorithms)
