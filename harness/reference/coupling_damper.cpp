#include "harness/reference/coupling_damper.h"

namespace hb {

void IdealCouplingDamper::apply(int64_t tick, const Twist& device, IdealRendering& ideal) {
  Twist proxy = device;
  if (ideal.in_contact && last_proxy_ && tick > last_tick_) {
    const double elapsed_s = static_cast<double>(tick - last_tick_) * dt_s_;
    proxy.v = (ideal.proxy.p - last_proxy_->p) / elapsed_s;
    proxy.w = rotation_vector(ideal.proxy.q * last_proxy_->q.conjugate()) / elapsed_s;
  }
  ideal.display.force += gains_.b_t * (proxy.v - device.v);
  ideal.display.torque += gains_.b_r * (proxy.w - device.w);
  last_proxy_ = ideal.proxy;
  last_tick_ = tick;
}

}  // namespace hb
