#include "estimator/encoder_scale_calibration.hpp"

#include <gtest/gtest.h>

#include "core/so3.hpp"

namespace statebench::est {
namespace {

// A car driving a circle at 8 m/s with an encoder whose wheel radius is 1.2 % too large (it
// reads low): the smoothed states (here the truth) give the scale back.
TEST(EncoderScaleCalibration, RecoversTheWheelRadiusErrorOnACircle) {
  const SE3 T_imu_axle(Quat::Identity(), Vec3(-0.76, 0.0, -0.23));
  EncoderScaleCalibration calib(T_imu_axle, 300.0, 50.0);
  const double v = 8.0, yaw_rate = 0.3, true_scale = 1.012;
  for (int k = 0; k <= 400; ++k) {  // 40 s at 10 Hz of states, encoder at 50 Hz
    const TimeNs t = k * 100 * kNsPerMillisecond;
    for (int j = 1; j <= 5; ++j) {
      // The rear axle's speed: the IMU point's forward speed (same on the body axis).
      calib.AddSpeed(t - (5 - j) * 20 * kNsPerMillisecond, v / true_scale);
    }
    NavState s;
    s.t_ns = t;
    const double yaw = yaw_rate * ToSeconds(t);
    s.q_world_imu = Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ()));
    // IMU velocity: the axle moves at v along x; the IMU ahead of it also sweeps sideways.
    const Vec3 v_imu = Vec3(v, 0.0, 0.0) + Vec3(0, 0, yaw_rate).cross(-T_imu_axle.translation());
    s.v_world = s.q_world_imu * v_imu;
    calib.AddSmoothedStates({s});  // states leave the window while the encoder runs on
    if (k == 5) {
      EXPECT_FALSE(calib.scale().has_value()) << "under 50 m compared";
    }
  }
  ASSERT_TRUE(calib.scale().has_value());
  std::printf("calibrated scale %.5f (true %.5f)\n", *calib.scale(), true_scale);
  EXPECT_NEAR(*calib.scale(), true_scale, 2e-4);
}

TEST(EncoderScaleCalibration, IgnoresStandstillAndImplausibleRatios) {
  EncoderScaleCalibration calib(SE3(), 300.0, 50.0);
  for (int k = 0; k <= 200; ++k) {
    const TimeNs t = k * 100 * kNsPerMillisecond;
    calib.AddSpeed(t, 10.0);
    NavState s;
    s.t_ns = t;
    s.v_world = Vec3(5.0, 0.0, 0.0);  // half the encoder speed: not a radius error
    calib.AddSmoothedStates({s});
  }
  EXPECT_FALSE(calib.scale().has_value());
}

}  // namespace
}  // namespace statebench::est
