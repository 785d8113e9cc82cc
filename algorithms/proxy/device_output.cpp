#include "hapticbench/proxy/device_output.h"

namespace hb {

namespace {
// Clips a vector to a length, keeping its direction; returns true when it did.
// stableNorm: a huge but finite vector must not overflow to an infinite length.
bool clip_length(Vec3& value, double max_length) {
  const double length = value.stableNorm();
  if (!(length > max_length)) return false;
  value *= max_length / length;
  return true;
}
}  // namespace

Wrench device_output(const Wrench& raw, const DeviceLimits& limits, uint32_t& flags) {
  if (!is_finite(raw)) {
    flags |= kFlagNonFiniteZeroed;
    return Wrench{};
  }
  Wrench shown = raw;
  if (clip_length(shown.force, limits.max_force_n)) flags |= kFlagForceSaturated;
  if (clip_length(shown.torque, limits.max_torque_nm)) flags |= kFlagTorqueSaturated;
  return shown;
}

bool is_finite(const DeviceSample& sample) {
  return is_finite(sample.pose) && sample.twist.v.allFinite() && sample.twist.w.allFinite();
}

bool reset_non_finite_proxy(const RigidBody& body, const Pose& device_pose, RigidBodyState& state,
                            uint32_t& flags) {
  if (is_finite(state)) return false;
  state = state_at_rest(body, device_pose);
  flags |= kFlagProxyReset;
  return true;
}

}  // namespace hb
