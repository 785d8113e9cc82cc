// The physical loop around a renderer in closed-loop replay: the operator's
// hand, holding the device, pulled towards the operator's intent (the
// trace), and the device's own mechanics and sensing. Translation and
// rotation are modelled alike, each isotropic (the same parameters on every
// axis); all quantities in SI units, world frame.
//
// The defaults describe a desk stylus device of the PHANToM Desktop class
// held in a pen grasp. They are representative values, not a measurement of
// hapticbench's: the device's apparent mass (45 g), backdrive friction
// (0.06 N) and position resolution (0.023 mm, 1100 dpi) are the orders its
// maker's specification sheet gives; the hand's impedance is of the order
// reported for a fingertip or pen grasp at light to moderate grip (Hajian &
// Howe 1997; Israr, Choi & Tan 2006) and for the wrist's rotation
// (Kuchenbecker, Park & Niemeyer 2003). docs/closed-loop.md lists them with
// their sources; a scenario overrides any of them ("closed_loop" block).
#pragma once

namespace hb {

/// The hand: a spring–damper from the intent to the device's grip, and the
/// hand's mass, which moves with the device.
struct HandModel {
  double mass_kg = 0.1;        ///< kg, effective mass moving with the grip (>= 0)
  double inertia_kgm2 = 1e-3;  ///< kg·m², effective rotational inertia (>= 0)
  double k_t = 300;            ///< N/m, grip stiffness to the intent (>= 0)
  double b_t = 2;              ///< N·s/m, grip damping (>= 0)
  double k_r = 1;              ///< N·m/rad (>= 0)
  double b_r = 0.02;           ///< N·m·s/rad (>= 0)
};

/// The device: its moving mass and inertia, viscous and Coulomb friction,
/// and what it reports. Force and torque limits are the scenario's "device"
/// block (DeviceLimits), applied by the renderer before display.
struct DeviceModel {
  double mass_kg = 0.045;      ///< kg, apparent mass at the tool frame (> 0)
  double inertia_kgm2 = 1e-5;  ///< kg·m², apparent rotational inertia (> 0)
  double b_t = 0;              ///< N·s/m, viscous friction (>= 0)
  double b_r = 0;              ///< N·m·s/rad (>= 0)
  double friction_n = 0.06;    ///< N, Coulomb (backdrive) friction; 0 = none
  double friction_nm = 0;      ///< N·m, Coulomb friction of the gimbal; 0 = none
  double encoder_m = 2.3e-5;   ///< m, position resolution per world axis; 0 = exact
  double encoder_rad = 0;      ///< rad, resolution of each rotation-vector component; 0 = exact
  /// Hz, cut-off of the first-order filter on the backward-difference
  /// velocity the device reports; 0 = the unfiltered backward difference.
  double velocity_filter_hz = 100;
};

struct ClosedLoopModel {
  HandModel hand;
  DeviceModel device;
};

}  // namespace hb
