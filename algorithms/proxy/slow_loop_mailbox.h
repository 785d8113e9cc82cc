// The mailbox between a multi-rate renderer's slow update and its haptic
// step: run_slow_update wraps what it computed, install_slow_result puts it
// in the mailbox, and the next step() takes it out once (flagging the tick).
// Every multi-rate renderer uses it instead of its own result subclass,
// cast and "installed" flag.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "algorithms/proxy/renderer.h"

namespace hb {

template <class Data>
class SlowLoopMailbox {
 public:
  /// What run_slow_update returns for `data`.
  static std::unique_ptr<SlowLoop::Result> wrap(Data data) {
    auto box = std::make_unique<Box>();
    box->data = std::move(data);
    return box;
  }

  /// For install_slow_result: keeps the data for the next take(). Throws
  /// std::invalid_argument naming `renderer` for a result it did not wrap.
  void install(std::unique_ptr<SlowLoop::Result> result, const char* renderer) {
    auto* box = dynamic_cast<Box*>(result.get());
    if (!box) throw std::invalid_argument(std::string(renderer) + ": foreign slow-loop result");
    pending_ = std::move(box->data);
  }

  /// For step(): the data installed since the last take, once; sets
  /// kFlagSlowResultInstalled in `flags` when there is some.
  std::optional<Data> take(uint32_t& flags) {
    if (!pending_) return std::nullopt;
    flags |= kFlagSlowResultInstalled;
    std::optional<Data> data = std::move(pending_);
    pending_.reset();
    return data;
  }

  /// For reset(): forgets an installed result not yet taken.
  void clear() { pending_.reset(); }

 private:
  struct Box : SlowLoop::Result {
    Data data;
  };
  std::optional<Data> pending_;
};

}  // namespace hb
