// Resampling a whole trace at once: the device trajectory's rules, every tick.
#include "harness/trace/device_trajectory.h"
#include "harness/trace/trace.h"

namespace hb {

std::vector<DeviceSample> resample_to_ticks(const Trace& trace, int64_t duration_ticks) {
  return DeviceTrajectory::of_trace(trace, duration_ticks).all();
}

}  // namespace hb
