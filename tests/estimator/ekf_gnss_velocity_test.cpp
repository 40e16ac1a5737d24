// The EKF's GNSS Doppler velocity update (EkfSingleTrackEstimator, UpdateGnssVelocity): on a
// seeded slalom with speed changes, IMU and one noisy antenna only (no encoders: the speed rests
// on the GNSS), the same fixes with the receiver's velocity give a smaller speed error, and a
// smaller heading error while the filter converges after its start, than without it. Seeds
// 11-15.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/so3.hpp"
#include "ekf_test_drive.hpp"
#include "estimator/ekf_single_track.hpp"
#include "estimator_scenario.hpp"

namespace statebench::est {
namespace {

using testing::Drive;
using testing::DriveOptions;

struct VelocityErrors {
  double start_s = 0.0;            // the first estimate (GNSS course)
  double early_yaw_rms_rad = 0.0;  // over the first kEarlyS after it
  double speed_rms_mps = 0.0;      // from kSettledS on
  double yaw_rms_rad = 0.0;        // from kSettledS on
  std::uint64_t velocity_updates = 0;
};

constexpr double kEarlyS = 5.0;
constexpr double kSettledS = 15.0;

// A slalom at 5-11 m/s with fixes of 1 m noise at 10 Hz, without steering and speed encoders.
Drive NoisyDrive(std::uint64_t seed) {
  DriveOptions o;
  o.duration_s = 60.0;
  o.speed_profile = [](double t) {
    const double w = 2.0 * std::numbers::pi / 20.0;
    return Vec2(8.0 + 3.0 * std::sin(w * t), 3.0 * w * std::cos(w * t));
  };
  o.start_steady = false;
  o.steering = [](double t) { return 0.05 * std::sin(2.0 * std::numbers::pi * 0.2 * t); };
  o.gnss_sigma_m = 1.0;
  o.reported_gnss_sigma_m = 1.0;
  o.gyro_sigma_radps = 0.002;
  o.accel_sigma_mps2 = 0.05;
  o.seed = seed;
  Drive d = MakeDrive(EkfOptions{}.vehicle, o);
  std::erase_if(d.stream, [](const Measurement& m) {
    return std::holds_alternative<SteeringAngle>(m) || std::holds_alternative<VehicleSpeed>(m);
  });
  return d;
}

// The antenna's horizontal velocity from the truth at each fix's stamp, with white noise.
void AddDopplerVelocities(Drive& d, double sigma_mps, std::uint64_t seed) {
  auto rng = MakeRng(seed, "ekf_gnss_velocity_test");
  NormalSampler normal;
  for (Measurement& m : d.stream) {
    auto* fix = std::get_if<GnssFix>(&m);
    if (fix == nullptr) continue;
    const testing::PlanarTruth& s =
        d.truth[static_cast<std::size_t>(fix->header.stamp_ns / 10'000'000)];
    const Vec3& l = testing::kDriveAntenna;
    const Mat2 R = Eigen::Rotation2Dd(s.psi).toRotationMatrix();
    const Vec2 v = R * Vec2(s.vx - s.r * l.y(), s.vy + s.r * l.x());
    GnssVelocity velocity;
    velocity.sigma_enu = Vec3(sigma_mps, sigma_mps, 2.0 * sigma_mps);
    velocity.v_enu = Vec3(v.x() + sigma_mps * normal(rng), v.y() + sigma_mps * normal(rng),
                          2.0 * sigma_mps * normal(rng));
    fix->velocity = velocity;
  }
}

// The errors of the output at every IMU sample from the first estimate on.
VelocityErrors RunWithErrors(const Drive& d) {
  EkfSingleTrackEstimator ekf(testing::MakeMinimalDriveSetup(), EkfOptions{});
  VelocityErrors out;
  double early_yaw2 = 0.0, speed2 = 0.0, yaw2 = 0.0;
  int early = 0, settled = 0;
  bool started = false;
  testing::FeedOutputs(ekf, d.stream, [&](TimeNs t_ns, const std::optional<StateEstimate>& e) {
    if (!e) {
      EXPECT_FALSE(started) << ToSeconds(t_ns);
      return;
    }
    const double t = ToSeconds(t_ns);
    if (!started) out.start_s = t;
    started = true;
    const testing::PlanarTruth& s = d.truth[static_cast<std::size_t>(t_ns / 10'000'000)];
    const double speed_error =
        e->state.v_world.head<2>().norm() - testing::TruthImuVelocity(s).head<2>().norm();
    const double yaw_error = so3::WrapAngle(so3::ToRollPitchYaw(e->state.q_world_imu).z() - s.psi);
    if (t < out.start_s + kEarlyS) {
      early_yaw2 += yaw_error * yaw_error;
      ++early;
    }
    if (t >= kSettledS) {
      speed2 += speed_error * speed_error;
      yaw2 += yaw_error * yaw_error;
      ++settled;
    }
  });
  out.early_yaw_rms_rad = std::sqrt(early_yaw2 / early);
  out.speed_rms_mps = std::sqrt(speed2 / settled);
  out.yaw_rms_rad = std::sqrt(yaw2 / settled);
  const auto events = ekf.diagnostics().sensors.at("gnss").events;
  if (const auto it = events.find("velocity_updates"); it != events.end()) {
    out.velocity_updates = it->second;
  }
  return out;
}

// The speed over the drive, on every seed; the start and the heading while the filter converges
// after it, on every seed: with the velocity the filter starts from it at the first fix above
// 10 sigma (0.05 s instead of the GNSS course's 0.85-1.25 s), its yaw sigma sigma_v / speed
// instead of up to course_max_yaw_sigma_rad + init_yaw_sigma_rad (measured 2026-11-26: mean
// early yaw RMS 0.052 -> 0.0098 rad; before the velocity start, 0.053 -> 0.033 and not on every
// seed). Without a steering input the model takes the side slip as zero, and the velocity's
// direction is the course, not the heading: the settled yaw is no better with the velocity on
// this drive (printed, not asserted).
TEST(EkfGnssVelocity, DopplerVelocityLowersTheSpeedAndEarlyHeadingErrors) {
  double early_yaw_without = 0.0, early_yaw_with = 0.0;
  for (std::uint64_t seed = 11; seed <= 15; ++seed) {
    Drive d = NoisyDrive(seed);
    const VelocityErrors without = RunWithErrors(d);
    AddDopplerVelocities(d, 0.05, seed);
    const VelocityErrors with = RunWithErrors(d);
    std::printf(
        "seed %d, with the Doppler velocity (%llu updates): speed RMS %.3f -> %.3f m/s; yaw RMS "
        "over the first %.0f s %.4f -> %.4f rad, after %.0f s %.4f -> %.4f rad\n",
        static_cast<int>(seed), static_cast<unsigned long long>(with.velocity_updates),
        without.speed_rms_mps, with.speed_rms_mps, kEarlyS, without.early_yaw_rms_rad,
        with.early_yaw_rms_rad, kSettledS, without.yaw_rms_rad, with.yaw_rms_rad);
    EXPECT_EQ(without.velocity_updates, 0u);
    EXPECT_GT(with.velocity_updates, 500u);    // 10 Hz from the start (about 1 s) to 60 s
    EXPECT_LT(with.start_s, without.start_s) << "seed " << seed;  // the velocity's start
    EXPECT_LT(with.early_yaw_rms_rad, without.early_yaw_rms_rad) << "seed " << seed;
    EXPECT_LT(with.speed_rms_mps, without.speed_rms_mps) << "seed " << seed;
    early_yaw_without += without.early_yaw_rms_rad / 5.0;
    early_yaw_with += with.early_yaw_rms_rad / 5.0;
  }
  std::printf("mean yaw RMS over the first %.0f s, seeds 11-15: %.4f -> %.4f rad\n", kEarlyS,
              early_yaw_without, early_yaw_with);
  EXPECT_LT(early_yaw_with, early_yaw_without);
}

}  // namespace
}  // namespace statebench::est
