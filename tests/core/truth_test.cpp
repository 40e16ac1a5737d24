#include "core/truth.hpp"

#include <gtest/gtest.h>

#include "core/state.hpp"

namespace statebench {
namespace {

// A body spinning about z at constant rate: a mount at lever arm r sees centripetal acceleration
// -w^2 r, and its velocity is w x r.
TEST(FrameKinematics, LeverArmOfSpinningBody) {
  FrameKinematics body;
  body.omega_frame = Vec3(0, 0, 2.0);
  const SE3 T_body_mount(Quat::Identity(), Vec3(1.5, 0, 0));
  const FrameKinematics m = body.AtMount(T_body_mount);
  EXPECT_LT((m.v_world - Vec3(0, 3.0, 0)).norm(), 1e-12);
  EXPECT_LT((m.a_world - Vec3(-6.0, 0, 0)).norm(), 1e-12);
  // At rest and level, the accelerometer reads +g upwards.
  EXPECT_LT((body.SpecificForce() - Vec3(0, 0, kGravity)).norm(), 1e-12);
}

TEST(FrameKinematics, RotatedMountExpressesRatesInItsFrame) {
  FrameKinematics body;
  body.omega_frame = Vec3(0, 0, 1.0);
  const SE3 T_body_mount(so3::FromRollPitchYaw(M_PI / 2, 0, 0), Vec3::Zero());
  const FrameKinematics m = body.AtMount(T_body_mount);
  // Mount rolled by +90 deg about x: its y axis is the body z axis.
  EXPECT_LT((m.omega_frame - Vec3(0, 1.0, 0)).norm(), 1e-12);
  EXPECT_LT((m.SpecificForce() - Vec3(0, kGravity, 0)).norm(), 1e-12);
}

}  // namespace
}  // namespace statebench
