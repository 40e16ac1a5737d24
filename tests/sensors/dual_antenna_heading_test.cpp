#include "sensors/dual_antenna_heading.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/so3.hpp"
#include "sensors/gnss_receiver.hpp"
#include "truth_fixtures.hpp"

namespace statebench::sensors {
namespace {

const GeodeticPoint kHeadingOrigin{48.7126, 2.2085, 160.0};

struct Pair {
  SensorSpec rear, front;
  DualAntennaHeadingOptions options;
};

Pair QuadricyclePair() {
  Pair p;
  p.rear.id = "gnss_rear";
  p.rear.rate_hz = 10.0;
  p.rear.T_body_sensor = SE3(Quat::Identity(), Vec3(-0.75, 0.0, 1.47));
  p.front.id = "gnss_front";
  p.front.rate_hz = 10.0;
  p.front.T_body_sensor = SE3(Quat::Identity(), Vec3(0.45, 0.0, 1.47));
  p.options = {"gnss_heading", "gnss_rear", "gnss_front", 0.1, GnssFixStatus::kRtkFixed};
  return p;
}

TruthSample PitchedTruth(TimeNs t_ns, double pitch, double yaw) {
  TruthSample s = testing::StaticTruth(t_ns, Vec3(300.0, 200.0, 5.0));
  s.body.T_world_frame = SE3(so3::FromRollPitchYaw(0.02, pitch, yaw), Vec3(300.0, 200.0, 5.0));
  return s;
}

// Zero antenna noise: the baseline along body x gives the body yaw and pitch exactly.
TEST(DualAntennaHeading, NoiseFreeBaselineGivesBodyYawAndPitch) {
  const Pair p = QuadricyclePair();
  GnssOptions exact;
  exact.AccuracyOf(GnssMode::kRtkFixed) = GnssAccuracy{0.0, 0.0};
  const LocalEnuFrame frame(kHeadingOrigin);
  GnssReceiver rear(p.rear, exact, frame, 1), front(p.front, exact, frame, 1);
  const TruthSample truth = PitchedTruth(0, 0.05, 2.5);
  const auto h =
      ComputeDualAntennaHeading(p.options, *rear.Sample(truth), *front.Sample(truth), frame);
  ASSERT_TRUE(h);
  const Vec3 rpy = so3::ToRollPitchYaw(truth.body.T_world_frame.rotation());
  EXPECT_NEAR(h->yaw_rad, rpy.z(), 1e-8);
  EXPECT_NEAR(h->pitch_rad, rpy.y(), 1e-8);
  EXPECT_EQ(h->header.sensor_id, "gnss_heading");
  EXPECT_EQ(h->header.arrival_ns, 100 * kNsPerMillisecond);
}

// RTK-fixed noise (1 cm horizontal, 1.5 cm vertical per antenna) over a 1.2 m baseline: the
// yaw and pitch errors have the reported sigmas.
TEST(DualAntennaHeading, ReportedSigmasMatchTheErrors) {
  const Pair p = QuadricyclePair();
  const LocalEnuFrame frame(kHeadingOrigin);
  GnssReceiver rear(p.rear, GnssOptions{}, frame, 21), front(p.front, GnssOptions{}, frame, 22);
  double sum_yaw2 = 0.0, sum_pitch2 = 0.0;
  DualAntennaHeading last;
  const int n = 5000;
  for (int k = 0; k < n; ++k) {
    const TruthSample truth = PitchedTruth(k * 100 * kNsPerMillisecond, -0.03, -1.0);
    const auto h =
        ComputeDualAntennaHeading(p.options, *rear.Sample(truth), *front.Sample(truth), frame);
    ASSERT_TRUE(h);
    const Vec3 rpy = so3::ToRollPitchYaw(truth.body.T_world_frame.rotation());
    sum_yaw2 += std::pow(so3::WrapAngle(h->yaw_rad - rpy.z()), 2);
    sum_pitch2 += std::pow(h->pitch_rad - rpy.y(), 2);
    last = *h;
  }
  const double yaw_sigma = std::sqrt(sum_yaw2 / n), pitch_sigma = std::sqrt(sum_pitch2 / n);
  std::printf("[ measured ] yaw sigma %.5f rad (reported %.5f), pitch sigma %.5f (reported %.5f)\n",
              yaw_sigma, last.yaw_sigma_rad, pitch_sigma, last.pitch_sigma_rad);
  // sqrt(2) * 1 cm / 1.2 m = 0.0118 rad; sqrt(2) * 1.5 cm / 1.2 m = 0.0177 rad.
  EXPECT_NEAR(last.yaw_sigma_rad, std::sqrt(2.0) * 0.01 / 1.2, 2e-4);
  EXPECT_NEAR(yaw_sigma / last.yaw_sigma_rad, 1.0, 0.05);
  EXPECT_NEAR(pitch_sigma / last.pitch_sigma_rad, 1.0, 0.05);
}

TEST(DualAntennaHeading, NeedsBothFixesAtTheRequiredStatus) {
  const Pair p = QuadricyclePair();
  const LocalEnuFrame frame(kHeadingOrigin);
  GnssOptions float_options;
  float_options.mode = GnssMode::kRtkFloat;
  GnssReceiver rear(p.rear, float_options, frame, 1), front(p.front, GnssOptions{}, frame, 1);
  const TruthSample truth = PitchedTruth(0, 0.0, 0.0);
  EXPECT_FALSE(
      ComputeDualAntennaHeading(p.options, *rear.Sample(truth), *front.Sample(truth), frame));
}

}  // namespace
}  // namespace statebench::sensors
