// The EKF's moving start from one GNSS antenna (ekf_course_start.hpp): the chord's newest end and
// the speed the IMU added along it. A car parked with its receiver on, then driving off: before,
// the course came from the log's first fix, so the start speed was the chord over the whole
// parked time (0.15 m/s for 6.6 m/s in a simulated parked start) and the filter lost itself.
#include "estimator/ekf_course_start.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/so3.hpp"
#include "ekf_test_drive.hpp"
#include "estimator/ekf_single_track.hpp"

namespace statebench::est {
namespace {

// Exact fixes of a point parked for 30 s, then accelerating at 2 m/s^2 along yaw 0.7; IMU at
// 100 Hz with the exact longitudinal force, fixes at 4 Hz.
TEST(EkfCourseStart, SpeedAtTheChordsEndAfterAStandstill) {
  const double yaw = 0.7, a = 2.0, parked_s = 30.0;
  const Vec3 p0(10.0, -4.0, 1.0);
  const Mat3 cov = Mat3::Identity() * 0.01;
  EkfCourseStart start;
  std::optional<EkfCourseStart::Course> course;
  double t_course = 0.0;
  for (int k = 0; k <= 4000 && !course; ++k) {
    const TimeNs t_ns = static_cast<TimeNs>(k) * 10'000'000;
    const double t = ToSeconds(t_ns);
    start.AddForwardAccel(t_ns, t > parked_s ? a : 0.0);
    if (k % 25 != 0) continue;
    const double s = t > parked_s ? 0.5 * a * (t - parked_s) * (t - parked_s) : 0.0;
    course = start.AddFix(t_ns, p0 + s * Vec3(std::cos(yaw), std::sin(yaw), 0.0), cov, 5.0, 0.15);
    t_course = t;
  }
  ASSERT_TRUE(course.has_value());
  std::printf("[ figures ] course at %.2f s: yaw %.6f, speed %.6f m/s (truth %.6f), sigma %.3f\n",
              t_course, course->yaw_rad, course->speed_mps, a * (t_course - parked_s),
              std::sqrt(course->speed_variance));
  EXPECT_NEAR(course->yaw_rad, yaw, 1e-9);
  // The force steps up between two samples: the held sample adds at most a 10 ms share.
  EXPECT_NEAR(course->speed_mps, a * (t_course - parked_s), 0.03);
  EXPECT_LT(std::sqrt(course->speed_variance), 2.0);
}

TEST(EkfCourseStart, WaitsForAChordLongEnoughForItsFixes) {
  EkfCourseStart start;
  const Mat3 cov = Mat3::Identity();  // 1 m per axis: sqrt(2) / 0.15 = 9.4 m needed
  EXPECT_FALSE(start.AddFix(0, Vec3::Zero(), cov, 5.0, 0.15));
  EXPECT_FALSE(start.AddFix(kNsPerSecond, Vec3(6.0, 0.0, 0.0), cov, 5.0, 0.15));
  EXPECT_NEAR(start.longest_chord_m(), 6.0, 1e-12);
  EXPECT_NEAR(start.needed_m(), std::sqrt(2.0) / 0.15, 1e-9);
  EXPECT_TRUE(start.AddFix(2 * kNsPerSecond, Vec3(0.0, 10.0, 0.0), cov, 5.0, 0.15));
  // Fixes older than the history are forgotten.
  EkfCourseStart late;
  EXPECT_FALSE(late.AddFix(0, Vec3::Zero(), cov, 5.0, 0.15));
  EXPECT_FALSE(late.AddFix(FromSeconds(EkfCourseStart::kHistoryS + 1.0), Vec3(20.0, 0.0, 0.0),
                           cov, 5.0, 0.15));
}

// The filter on a drive parked 20 s, then accelerating at 2 m/s^2 to 10 m/s on a straight line
// (IMU and one antenna of 1 m noise at 10 Hz, no encoders), seeds 11-15: the first estimate's
// speed is within 3 of its reported sigmas and 2 m/s of the truth (before: the parked time's
// chord, 4-5 m/s too slow), the filter never starts over, and it is within 1.5 m of
// the truth from 10 s after its start on.
TEST(EkfCourseStart, ParkedThenDrivingOffWithoutEncoders) {
  for (std::uint64_t seed = 11; seed <= 15; ++seed) {
    testing::DriveOptions o;
    o.duration_s = 60.0;
    o.speed_profile = [](double t) {
      if (t < 20.0) return Vec2(0.0, 0.0);
      if (t < 25.0) return Vec2(2.0 * (t - 20.0), 2.0);
      return Vec2(10.0, 0.0);
    };
    o.start_steady = false;
    o.steering = [](double) { return 0.0; };
    o.initial_yaw_rad = 0.4;
    o.gnss_sigma_m = 1.0;
    o.reported_gnss_sigma_m = 1.0;
    o.gyro_sigma_radps = 0.002;
    o.accel_sigma_mps2 = 0.05;
    o.seed = seed;
    EkfOptions options;
    testing::Drive d = testing::MakeDrive(options.vehicle, o);
    std::erase_if(d.stream, [](const Measurement& m) {
      return std::holds_alternative<SteeringAngle>(m) || std::holds_alternative<VehicleSpeed>(m);
    });
    EkfSingleTrackEstimator ekf(testing::MakeMinimalDriveSetup(), options);
    std::optional<double> start_s, start_speed_error;
    double start_speed_sigma = 0.0;
    double max_position_error = 0.0;
    for (const Measurement& m : d.stream) {
      ekf.Add(m);
      const auto* imu = std::get_if<ImuSample>(&m);
      if (imu == nullptr || imu->header.stamp_ns % 100'000'000 != 0) continue;
      const auto est = ekf.StateAt(imu->header.stamp_ns);
      if (!est) continue;
      const double t = ToSeconds(imu->header.stamp_ns);
      const auto& truth = d.truth[static_cast<std::size_t>(imu->header.stamp_ns / 10'000'000)];
      const Mat3 R = est->state.q_world_imu.toRotationMatrix();
      const Vec3 v_body = R.transpose() * est->state.v_world;
      if (!start_s) {
        start_s = t;
        start_speed_error = v_body.x() - truth.vx;
        start_speed_sigma =
            std::sqrt((R.transpose() * est->covariance.block<3, 3>(6, 6) * R)(0, 0));
      }
      if (t < *start_s + 10.0) continue;
      const Vec3 p = d.frame.ToEnu({est->latitude_deg, est->longitude_deg, est->altitude_m});
      max_position_error = std::max(max_position_error, (p - testing::TruthImuPosition(truth)).norm());
    }
    ASSERT_TRUE(start_s.has_value()) << "seed " << seed;
    const EstimatorDiagnostics diag = ekf.diagnostics();
    std::printf("[ figures ] seed %llu: start %.1f s, speed error there %.2f m/s (sigma %.2f), "
                "max position error from 10 s later %.2f m, starts over %zu\n",
                static_cast<unsigned long long>(seed), *start_s, *start_speed_error,
                start_speed_sigma, max_position_error, diag.lost.size());
    EXPECT_GT(*start_s, 20.0) << "seed " << seed;
    EXPECT_LT(std::abs(*start_speed_error), 3.0 * start_speed_sigma) << "seed " << seed;
    EXPECT_LT(std::abs(*start_speed_error), 2.0) << "seed " << seed;
    EXPECT_TRUE(diag.lost.empty()) << "seed " << seed;
    EXPECT_LT(max_position_error, 1.5) << "seed " << seed;
  }
}

}  // namespace
}  // namespace statebench::est
