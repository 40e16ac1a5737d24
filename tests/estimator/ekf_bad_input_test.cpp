// The single-track EKF rejects and counts bad data and keeps a finite, accurate estimate.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "ekf_test_drive.hpp"
#include "estimator/ekf_single_track.hpp"

namespace statebench::est {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::uint64_t Rejected(const EstimatorDiagnostics& d, const std::string& id, RejectReason r) {
  const auto s = d.sensors.find(id);
  if (s == d.sensors.end()) return 0;
  const auto it = s->second.rejected.find(r);
  return it == s->second.rejected.end() ? 0 : it->second;
}

TEST(EkfSingleTrackBadInput, RejectedCountedAndEstimateStaysAccurate) {
  testing::DriveOptions o;
  o.duration_s = 40.0;
  EkfOptions options;
  const testing::Drive d = testing::MakeDrive(options.vehicle, o);
  EkfSingleTrackEstimator ekf(testing::MakeDriveSetup(), options);
  const TimeNs t_bad = FromSeconds(25.0);
  GnssFix good_fix;
  for (const Measurement& m : d.stream) {
    if (const auto* fix = std::get_if<GnssFix>(&m)) good_fix = *fix;
    ekf.Add(m);
    const auto* imu = std::get_if<ImuSample>(&m);
    if (imu == nullptr || imu->header.stamp_ns != t_bad) continue;
    const TimeNs t = t_bad;
    // IMU: non-finite, absurd, repeated stamp, stamp after arrival.
    ImuSample bad_imu = *imu;
    bad_imu.header = {"imu", t + 1'000'000, t + 1'000'000};
    bad_imu.gyro.x() = kNaN;
    ekf.Add(bad_imu);
    bad_imu.gyro.x() = 0.0;
    bad_imu.accel.x() = 1000.0;
    ekf.Add(bad_imu);
    ekf.Add(*imu);  // same stamp again
    bad_imu.accel.x() = 0.0;
    bad_imu.header = {"imu", t + 2'000'000, t};
    ekf.Add(bad_imu);
    // GNSS: NaN, absurd latitude, no fix, invalid covariance, too uncertain, 30 m outlier.
    GnssFix fix = good_fix;
    TimeNs stamp = good_fix.header.stamp_ns;
    const auto next = [&](GnssFix f) {
      stamp += 1'000'000;
      f.header = {"gnss", stamp, t};
      ekf.Add(f);
    };
    fix.latitude_deg = kNaN;
    next(fix);
    fix = good_fix;
    fix.latitude_deg = 95.0;
    next(fix);
    fix = good_fix;
    fix.status = GnssFixStatus::kNone;
    next(fix);
    fix = good_fix;
    fix.covariance_enu(0, 0) = -1.0;
    next(fix);
    fix = good_fix;
    fix.covariance_enu = Mat3::Identity() * 100.0;  // sigma 10 m > 5 m threshold
    next(fix);
    fix = good_fix;
    fix.latitude_deg += 30.0 / 111'000.0;  // ~30 m north
    next(fix);
    // Encoders: NaN and absurd values; unknown and mistyped sensors; unsupported sensor.
    VehicleSpeed speed;
    speed.header = {"speed", t - 1'000'000, t};
    speed.speed_mps = kNaN;
    ekf.Add(speed);
    speed.speed_mps = 500.0;
    ekf.Add(speed);
    SteeringAngle steer;
    steer.header = {"steering", t - 1'000'000, t};
    steer.angle_rad = kNaN;
    ekf.Add(steer);
    steer.angle_rad = 2.0;
    ekf.Add(steer);
    steer.header.sensor_id = "nobody";
    ekf.Add(steer);
    GnssFix typed = good_fix;
    typed.header.sensor_id = "speed";
    ekf.Add(typed);
    WheelSpeeds wheels;
    wheels.header = {"wheels", t, t};
    ekf.Add(wheels);
  }
  const EstimatorDiagnostics diag = ekf.diagnostics();
  EXPECT_EQ(Rejected(diag, "imu", RejectReason::kNonFinite), 1u);
  EXPECT_EQ(Rejected(diag, "imu", RejectReason::kAbsurdValue), 1u);
  EXPECT_EQ(Rejected(diag, "imu", RejectReason::kStampBackwards), 1u);
  EXPECT_EQ(Rejected(diag, "imu", RejectReason::kStampInFuture), 1u);
  EXPECT_EQ(Rejected(diag, "gnss", RejectReason::kNonFinite), 1u);
  EXPECT_EQ(Rejected(diag, "gnss", RejectReason::kAbsurdValue), 1u);
  EXPECT_EQ(Rejected(diag, "gnss", RejectReason::kNoFix), 1u);
  EXPECT_EQ(Rejected(diag, "gnss", RejectReason::kInvalidCovariance), 1u);
  EXPECT_EQ(Rejected(diag, "gnss", RejectReason::kCovarianceThreshold), 1u);
  EXPECT_EQ(Rejected(diag, "gnss", RejectReason::kMahalanobisGate), 1u);
  EXPECT_EQ(diag.sensors.at("gnss").TotalRejected(), 6u);
  EXPECT_EQ(Rejected(diag, "speed", RejectReason::kNonFinite), 1u);
  EXPECT_EQ(Rejected(diag, "speed", RejectReason::kAbsurdValue), 1u);
  EXPECT_EQ(Rejected(diag, "speed", RejectReason::kUnknownSensor), 1u);
  EXPECT_EQ(Rejected(diag, "steering", RejectReason::kNonFinite), 1u);
  EXPECT_EQ(Rejected(diag, "steering", RejectReason::kAbsurdValue), 1u);
  EXPECT_EQ(Rejected(diag, "nobody", RejectReason::kUnknownSensor), 1u);
  EXPECT_EQ(Rejected(diag, "wheels", RejectReason::kUnsupportedSensor), 1u);

  const TimeNs t_end = d.truth.back().t_ns;
  const auto est = ekf.StateAt(t_end);
  ASSERT_TRUE(est.has_value());
  EXPECT_TRUE(est->covariance.allFinite());
  const Vec3 p = d.frame.ToEnu({est->latitude_deg, est->longitude_deg, est->altitude_m});
  EXPECT_LT((p - testing::TruthImuPosition(d.truth.back())).norm(), 0.02);
}

TEST(EkfSingleTrackBadInput, NothingBeforeInitialisationAndOnlyBadData) {
  EkfOptions options;
  EkfSingleTrackEstimator ekf(testing::MakeDriveSetup(), options);
  ImuSample imu;
  imu.header = {"imu", 10'000'000, 10'000'000};
  imu.gyro = Vec3::Constant(kNaN);
  ekf.Add(imu);
  GnssFix fix;
  fix.header = {"gnss", 5'000'000, 10'000'000};
  fix.latitude_deg = std::numeric_limits<double>::infinity();
  ekf.Add(fix);
  EXPECT_FALSE(ekf.StateAt(10'000'000).has_value());
  EXPECT_FALSE(ekf.diagnostics().initialized);
  EXPECT_FALSE(ekf.origin().has_value());
}

TEST(EkfSingleTrackBadInput, InvalidOptionsThrowASetupWithoutGnssStartsLocal) {
  EkfOptions options;
  options.vehicle.mass_kg = -1.0;
  EXPECT_THROW(EkfSingleTrackEstimator(testing::MakeDriveSetup(), options), InputError);
  // Without a GNSS antenna the EKF runs in a local frame (ekf_local_start_test.cpp).
  const EstimatorSensorSetup no_gnss = ParseEstimatorSensorSetup(YamlNode::LoadString(
      "name: x\nsensors:\n  - {type: imu, id: imu, T_body_sensor: {translation: [0, 0, 0]}}\n",
      "no_gnss.yaml"));
  const EkfSingleTrackEstimator ekf(no_gnss, EkfOptions{});
  EXPECT_EQ(ekf.diagnostics().waiting_for, "no IMU sample");
}

}  // namespace
}  // namespace statebench::est
