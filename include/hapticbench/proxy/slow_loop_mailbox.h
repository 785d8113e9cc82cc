// The mailbox between a multi-rate renderer's slow update and its haptic
// step: run_slow_update fills a box, install_slow_result moves its data into
// the mailbox (outside step(), as a real haptic thread's handoff would be),
// and the next step() takes it once (flagging the tick).
// Every multi-rate renderer uses it instead of its own result subclass,
// cast and "installed" flag.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "hapticbench/renderer.h"

namespace hb {

template <class Data>
class SlowLoopMailbox {
 public:
  /// What run_slow_update fills (`box->data`) and returns.
  struct Box : SlowLoop::Result {
    Data data;
  };
  static std::unique_ptr<Box> box() { return std::make_unique<Box>(); }

  /// For install_slow_result: moves the data into the mailbox for the next
  /// take(). Throws std::invalid_argument naming `renderer` for a result it
  /// did not box.
  void install(std::unique_ptr<SlowLoop::Result> result, const char* renderer) {
    auto* box = dynamic_cast<Box*>(result.get());
    if (!box) throw std::invalid_argument(std::string(renderer) + ": foreign slow-loop result");
    latest_ = std::move(box->data);
    fresh_ = true;
  }

  /// For step(): the data installed since the last take, once (nullptr
  /// otherwise); sets kFlagSlowResultInstalled in `flags` when there is
  /// some. The data stays in the mailbox until the next install: the step
  /// may swap it out.
  Data* take(uint32_t& flags) {
    if (!fresh_) return nullptr;
    fresh_ = false;
    flags |= kFlagSlowResultInstalled;
    return &latest_;
  }

  /// For reset(): forgets an installed result not yet taken.
  void clear() {
    latest_ = Data{};
    fresh_ = false;
  }

 private:
  Data latest_{};
  bool fresh_ = false;
};

}  // namespace hb
