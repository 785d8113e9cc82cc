// Tests for harness/reference/coupling_damper.cpp against closed forms: a
// sphere pressed at constant speed into a box's face displays
// k_T · depth + b_T · speed (the ideal proxy rests on the face, so
// v_p = 0); out of contact the damper adds nothing; a sphere twisted while
// pressed displays no torque (its ideal proxy turns with the device).
#include "harness/reference/coupling_damper.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "tests/support/shape_fixtures.h"

namespace hb::coupling_damper_test {

constexpr double kStiffness = 2000;   // k_T, N/m
constexpr double kDamping = 5;        // b_T, N·s/m
constexpr double kRotDamping = 0.05;  // b_R, N·m·s/rad
constexpr double kRadius = 0.02;      // m
constexpr double kDt = 1e-3;          // s

AnalyticScene plate_and_sphere() {
  RenderContext context;
  SceneObject plate;
  plate.name = "scene[0]";
  plate.pose = Pose{Vec3(0, 0, -0.01), Quat::Identity()};  // top face at z = 0
  plate.shape = test::box_shape(Vec3(0.4, 0.4, 0.02));
  context.scene.push_back(plate);
  Shape sphere;
  sphere.type = ShapeType::kSphere;
  sphere.radius = kRadius;
  context.tool.shape = sphere;
  context.coupling.k_t = kStiffness;
  context.coupling.k_r = 5;
  context.coupling.b_t = kDamping;
  context.coupling.b_r = kRotDamping;
  std::optional<AnalyticScene> scene = make_analytic_scene(context);
  REQUIRE(scene);
  return *scene;
}

TEST_CASE("a press at constant speed displays k_T depth + b_T speed") {
  const AnalyticScene scene = plate_and_sphere();
  FrictionalContactReference reference(scene);
  IdealCouplingDamper damper(scene.coupling, kDt);
  const double speed = 0.05;  // m/s, into the face
  const double start_z = kRadius + 0.002;
  for (int64_t tick = 0; tick < 200; ++tick) {
    const Pose device{Vec3(0.01, -0.02, start_z - speed * kDt * static_cast<double>(tick)),
                      Quat::Identity()};
    const Twist twist{Vec3(0, 0, -speed), Vec3::Zero()};
    IdealRendering ideal = reference.update(device);
    damper.apply(tick, twist, ideal);
    const double depth = kRadius - device.p.z();
    CAPTURE(tick, depth);
    if (depth < 0) {
      // Free space: the ideal proxy is the device, the coupling idle.
      CHECK(ideal.display.force.norm() == Approx(0).margin(1e-12));
    } else if (depth > speed * kDt) {
      // Resting on the face since the last tick: only the device moves.
      CHECK(ideal.display.force.z() == Approx(kStiffness * depth + kDamping * speed).epsilon(1e-9));
      CHECK(ideal.display.force.head<2>().norm() == Approx(0).margin(1e-9));
    }
  }
}

TEST_CASE("a sphere twisted while pressed displays no damper torque") {
  const AnalyticScene scene = plate_and_sphere();
  FrictionalContactReference reference(scene);
  IdealCouplingDamper damper(scene.coupling, kDt);
  const Vec3 spin(0.3, -0.2, 2.0);  // rad/s, constant
  for (int64_t tick = 0; tick < 100; ++tick) {
    const Pose device{Vec3(0, 0, kRadius - 0.001),
                      quat_from_rotation_vector(spin * kDt * static_cast<double>(tick))};
    IdealRendering ideal = reference.update(device);
    REQUIRE(ideal.in_contact);
    damper.apply(tick, Twist{Vec3::Zero(), spin}, ideal);
    CHECK(ideal.display.torque.norm() == Approx(0).margin(1e-9));
    CHECK(ideal.display.force.z() == Approx(kStiffness * 0.001).epsilon(1e-9));
  }
}

}  // namespace hb::coupling_damper_test
