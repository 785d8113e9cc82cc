#include "harness/metrics/passivity_energy.h"

namespace hb {

double PortEnergy::add(const Wrench& display, const Pose& device) {
  if (!started_) {
    started_ = true;
    if (k_t_ > 0) energy_j_ += display.force.squaredNorm() / (2 * k_t_);
    if (k_r_ > 0) energy_j_ += display.torque.squaredNorm() / (2 * k_r_);
  } else {
    const Vec3 moved = device.p - held_at_.p;
    const Vec3 turned = rotation_vector(device.q * held_at_.q.conjugate());
    energy_j_ += -held_.force.dot(moved) - held_.torque.dot(turned);
  }
  held_ = display;
  held_at_ = device;
  return energy_j_;
}

}  // namespace hb
