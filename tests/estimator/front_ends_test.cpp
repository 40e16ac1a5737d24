// The factor graph's front ends as units, without the orchestrator: the intake's checks and
// stamp-order release, how each front end claims measurements, the encoder front end's pass
// order and disabled paths, the GNSS front end before initialisation and its covariance
// threshold, and the body-velocity front end's refusal before the first state.
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "core/yaml_node.hpp"
#include "estimator/body_velocity_front_end.hpp"
#include "estimator/encoder_front_end.hpp"
#include "estimator/factor_plan.hpp"
#include "estimator/gnss_front_end.hpp"
#include "estimator/lidar_front_end.hpp"
#include "estimator/measurement_intake.hpp"

namespace statebench::est {
namespace {

EstimatorSensorSetup Setup() {
  return ParseEstimatorSensorSetup(YamlNode::LoadString(
      "sensors:\n"
      "  - {type: imu, id: imu, T_body_sensor: {translation: [0, 0, 0]}}\n"
      "  - {type: gnss, id: gnss, latency_s: 0.1, T_body_sensor: {translation: [0.5, 0, 1]}}\n"
      "  - {type: speed_encoder, id: speed, T_body_sensor: {translation: [-0.7, 0, 0.3]}}\n"
      "  - {type: steering_encoder, id: steering, T_body_sensor: {translation: [0.9, 0, 0.3]}}\n"
      "  - {type: body_velocity, id: odom, T_body_sensor: {translation: [0, 0, 0]}}\n"
      "  - {type: lidar, id: lidar, T_body_sensor: {translation: [0, 0, 1.8]}}\n",
      "setup.yaml"));
}

struct Fixture {
  EstimatorSensorSetup setup = Setup();
  FactorGraphOptions options;
  FactorPlan plan = PlanFactors(setup, options);
  FrontEndContext ctx{SmootherOptions(setup, options), options.initialization, options.imu_noise,
                      Vec3::UnitX()};
};

ImuSample Imu(TimeNs t_ns, TimeNs arrival_ns = 0) {
  ImuSample s;
  s.header = {"imu", t_ns, arrival_ns};
  s.accel = Vec3(0, 0, 9.81);
  return s;
}

template <typename M>
M At(const std::string& id, TimeNs t_ns, TimeNs arrival_ns = 0) {
  M m;
  m.header = {id, t_ns, arrival_ns};
  return m;
}

std::uint64_t Rejected(const FrontEndContext& ctx, const std::string& id, RejectReason r) {
  const auto s = ctx.diag.sensors.find(id);
  if (s == ctx.diag.sensors.end()) return 0;
  const auto c = s->second.rejected.find(r);
  return c == s->second.rejected.end() ? 0 : c->second;
}

TEST(MeasurementIntake, ChecksEachMeasurementAndReleasesInStampOrder) {
  Fixture f;
  MeasurementIntake intake(f.setup, FromSeconds(0.15), ImuLimits{});
  const TimeNs ms = kNsPerMillisecond;
  EXPECT_EQ(intake.Admit(Imu(10 * ms), Claim::kOtherKind, f.ctx), Admission::kImu);
  EXPECT_EQ(intake.Admit(Imu(10 * ms), Claim::kOtherKind, f.ctx), Admission::kRejected);
  EXPECT_EQ(Rejected(f.ctx, "imu", RejectReason::kStampBackwards), 1u);
  // Two speed samples out of order, one repeated stamp, one of an unknown sensor.
  EXPECT_EQ(intake.Admit(At<VehicleSpeed>("speed", 8 * ms), Claim::kTaken, f.ctx),
            Admission::kQueued);
  EXPECT_EQ(intake.Admit(At<VehicleSpeed>("speed", 5 * ms), Claim::kTaken, f.ctx),
            Admission::kQueued);
  EXPECT_EQ(intake.Admit(At<VehicleSpeed>("speed", 5 * ms), Claim::kTaken, f.ctx),
            Admission::kRejected);
  EXPECT_EQ(intake.Admit(At<VehicleSpeed>("ghost", 6 * ms), Claim::kUnknownSensor, f.ctx),
            Admission::kRejected);
  EXPECT_EQ(intake.Admit(At<WheelSpeeds>("speed", 6 * ms), Claim::kOtherKind, f.ctx),
            Admission::kRejected);
  EXPECT_EQ(Rejected(f.ctx, "speed", RejectReason::kStampBackwards), 1u);
  EXPECT_EQ(Rejected(f.ctx, "ghost", RejectReason::kUnknownSensor), 1u);
  EXPECT_EQ(Rejected(f.ctx, "speed", RejectReason::kUnsupportedSensor), 1u);
  VehicleSpeed nan = At<VehicleSpeed>("speed", 9 * ms);
  nan.speed_mps = std::nan("");
  EXPECT_EQ(intake.Admit(nan, Claim::kTaken, f.ctx), Admission::kRejected);
  EXPECT_EQ(Rejected(f.ctx, "speed", RejectReason::kNonFinite), 1u);
  // Nothing is released before the IMU is the latency past a stamp; then stamp order.
  EXPECT_EQ(intake.Release(f.ctx.newest_imu_ns).size(), 0u);
  EXPECT_EQ(intake.Admit(Imu(200 * ms), Claim::kOtherKind, f.ctx), Admission::kImu);
  const std::vector<Measurement> out = intake.Release(f.ctx.newest_imu_ns);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(HeaderOf(out[0]).stamp_ns, 5 * ms);
  EXPECT_EQ(HeaderOf(out[1]).stamp_ns, 8 * ms);
  EXPECT_EQ(HeaderOf(out[2]).stamp_ns, 10 * ms);  // the IMU sample
  // Older than what was released: late.
  EXPECT_EQ(intake.Admit(At<VehicleSpeed>("speed", 7 * ms), Claim::kTaken, f.ctx),
            Admission::kLate);
}

TEST(MeasurementIntake, StampAfterItsArrivalIsRefused) {
  Fixture f;
  MeasurementIntake intake(f.setup, FromSeconds(0.15), ImuLimits{});
  EXPECT_EQ(intake.Admit(Imu(FromSeconds(1.0), FromSeconds(1.0)), Claim::kOtherKind, f.ctx),
            Admission::kImu);
  EXPECT_EQ(intake.Admit(Imu(FromSeconds(5.0), FromSeconds(1.01)), Claim::kOtherKind, f.ctx),
            Admission::kRejected);
  EXPECT_EQ(Rejected(f.ctx, "imu", RejectReason::kStampInFuture), 1u);
}

TEST(FrontEnds, EachClaimsItsOwnKindAndSensors) {
  Fixture f;
  GnssFrontEnd gnss(f.setup, f.options, f.ctx);
  EncoderFrontEnd encoders(f.setup, f.plan, f.options, f.ctx);
  LidarFrontEnd lidar(f.setup, f.plan.lidars, f.options, f.ctx);
  BodyVelocityFrontEnd odometry(f.setup, f.options, f.ctx);
  EXPECT_EQ(gnss.Claims(At<GnssFix>("gnss", 0)), Claim::kTaken);
  EXPECT_EQ(gnss.Claims(At<GnssFix>("speed", 0)), Claim::kUnknownSensor);
  EXPECT_EQ(gnss.Claims(At<VehicleSpeed>("speed", 0)), Claim::kOtherKind);
  EXPECT_EQ(encoders.Claims(At<VehicleSpeed>("speed", 0)), Claim::kTaken);
  EXPECT_EQ(encoders.Claims(At<SteeringAngle>("steering", 0)), Claim::kTaken);
  EXPECT_EQ(encoders.Claims(At<SteeringAngle>("speed", 0)), Claim::kUnknownSensor);
  EXPECT_EQ(lidar.Claims(At<LidarScan>("lidar", 0)), Claim::kTaken);
  EXPECT_EQ(lidar.Claims(At<LidarScan>("gnss", 0)), Claim::kUnknownSensor);
  EXPECT_EQ(odometry.Claims(At<BodyVelocity>("odom", 0)), Claim::kTaken);
  EXPECT_EQ(odometry.Claims(At<BodyVelocity>("speed", 0)), Claim::kUnknownSensor);
  EXPECT_EQ(odometry.Claims(Imu(0)), Claim::kOtherKind);
  // Steering is handed over before the speed of the same stamp.
  EXPECT_EQ(encoders.Pass(At<SteeringAngle>("steering", 0)), 0);
  EXPECT_EQ(encoders.Pass(At<VehicleSpeed>("speed", 0)), 1);
}

TEST(FrontEnds, BeforeTheFirstStateMeasurementsFeedTheInitialiserOrAreCounted) {
  Fixture f;
  EncoderFrontEnd encoders(f.setup, f.plan, f.options, f.ctx);
  encoders.Process(At<SteeringAngle>("steering", FromSeconds(1.0)));
  VehicleSpeed v = At<VehicleSpeed>("speed", FromSeconds(1.0));
  v.speed_mps = 2.0;
  encoders.Process(v);
  EXPECT_EQ(Rejected(f.ctx, "speed", RejectReason::kNotInitialized), 1u);
  ASSERT_TRUE(encoders.last_speed().has_value());  // kept for the moving initialisation
  EXPECT_DOUBLE_EQ(encoders.last_speed()->second, 2.0);
  BodyVelocityFrontEnd odometry(f.setup, f.options, f.ctx);
  odometry.Process(At<BodyVelocity>("odom", FromSeconds(1.0)));
  EXPECT_EQ(Rejected(f.ctx, "odom", RejectReason::kNotInitialized), 1u);
  // The kinematic factor switched off: the steering encoder is counted as disabled.
  f.options.kinematic.use = FactorUse::kOff;
  const FactorPlan off = PlanFactors(f.setup, f.options);
  EncoderFrontEnd no_kinematic(f.setup, off, f.options, f.ctx);
  no_kinematic.Process(At<SteeringAngle>("steering", FromSeconds(1.1)));
  EXPECT_EQ(Rejected(f.ctx, "steering", RejectReason::kDisabled), 1u);
}

// The Ceres solver's batch store has no window globals: a configuration asking for both is
// refused before anything runs, naming the options; without the lidar's mount and the IMU's
// triad errors (both on by default) it plans.
TEST(FrontEnds, TheCeresBatchRefusesWindowGlobalsUpFront) {
  Fixture f;
  f.options.solver = WindowSolver::kCeres;
  f.options.batch = true;
  ASSERT_TRUE(f.options.lidar.estimate_mount);  // the default
  try {
    PlanFactors(f.setup, f.options);
    FAIL() << "planned";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("lidar.estimate_mount"), std::string::npos) << e.what();
  }
  f.options.lidar.estimate_mount = false;
  ASSERT_TRUE(f.options.imu_triad.any());  // the default
  try {
    PlanFactors(f.setup, f.options);
    FAIL() << "planned";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("imu_triad"), std::string::npos) << e.what();
  }
  f.options.imu_triad.estimate_gyro = false;
  f.options.imu_triad.estimate_accel = false;
  EXPECT_NO_THROW(PlanFactors(f.setup, f.options));
}

// A creeping wheel (0.04 m/s, a tick of 1.66 mm every 41 ms) reads zero in most 20 ms samples:
// the encoder reads zero over a window only when no tick fell in it.
TEST(FrontEnds, TheSpeedEncoderReadsZeroOverAWindowOnlyWithoutATick) {
  Fixture f;
  EncoderFrontEnd encoders(f.setup, f.plan, f.options, f.ctx);
  constexpr double kTickM = 0.00166;
  double distance = 0.0;
  int ticks = 0;
  int zero_samples = 0;
  for (int k = 0; k < 50; ++k) {  // 1 s at 50 Hz, creeping
    VehicleSpeed v = At<VehicleSpeed>("speed", FromSeconds(1.0 + 0.02 * k));
    distance += 0.04 * 0.02;
    const int now = static_cast<int>(distance / kTickM);
    v.speed_mps = (now - ticks) * kTickM / 0.02;
    ticks = now;
    zero_samples += v.speed_mps == 0.0;
    encoders.Process(v);
  }
  EXPECT_GE(zero_samples, 20);  // one sample alone would often say "still"
  EXPECT_FALSE(encoders.ReadsZeroSince(FromSeconds(1.98 - 0.3), 0.005));
  for (int k = 0; k < 20; ++k) {  // then 0.4 s standing
    encoders.Process(At<VehicleSpeed>("speed", FromSeconds(2.0 + 0.02 * k)));
  }
  const TimeNs still = FromSeconds(2.38);
  EXPECT_TRUE(encoders.ReadsZeroSince(still - FromSeconds(0.3), 0.005));
  EXPECT_FALSE(encoders.ReadsZeroSince(still - FromSeconds(0.5), 0.005));  // the creep's ticks
  EXPECT_FALSE(encoders.ReadsZeroSince(FromSeconds(0.5), 0.005));          // before any sample
}

TEST(FrontEnds, GnssFixesAboveTheCovarianceThresholdAreDiscarded) {
  Fixture f;
  f.options.origin = GeodeticPoint{48.7, 2.2, 120.0};
  GnssFrontEnd gnss(f.setup, f.options, f.ctx);
  GnssFix good = At<GnssFix>("gnss", FromSeconds(1.0));
  good.latitude_deg = 48.7;
  good.longitude_deg = 2.2;
  good.altitude_m = 121.0;
  good.covariance_enu = Mat3::Identity() * 0.01;
  good.status = GnssFixStatus::kSingle;
  GnssFix bad = good;
  bad.header.sensor_id = "gnss";
  bad.header.stamp_ns = FromSeconds(1.1);
  bad.covariance_enu = Mat3::Identity() * 100.0;  // sigma 10 m > max_sigma_m 5
  gnss.Process(good);
  gnss.EndOfStamp();
  gnss.Process(bad);
  gnss.EndOfStamp();
  EXPECT_EQ(f.ctx.diag.sensors.at("gnss").accepted, 1u);  // to the initialiser
  EXPECT_EQ(Rejected(f.ctx, "gnss", RejectReason::kCovarianceThreshold), 1u);
  ASSERT_TRUE(gnss.frame().has_value());
}

// A fix without a useful height (vertical sigma above max_vertical_sigma_m, or none given) is
// used horizontally: counted, not discarded; its vertical variance carries no information.
TEST(FrontEnds, GnssFixesWithoutAUsefulHeightAreUsedHorizontally) {
  Fixture f;
  f.options.origin = GeodeticPoint{48.7, 2.2, 120.0};
  GnssFrontEnd gnss(f.setup, f.options, f.ctx);
  GnssFix fix = At<GnssFix>("gnss", FromSeconds(1.0));
  fix.latitude_deg = 48.7;
  fix.longitude_deg = 2.2;
  fix.altitude_m = 121.0;
  fix.status = GnssFixStatus::kSingle;
  fix.covariance_enu = Vec3(1.0, 1.0, 400.0).asDiagonal();  // vertical sigma 20 m > 5
  gnss.Process(fix);
  gnss.EndOfStamp();
  fix.header.stamp_ns = FromSeconds(1.1);
  fix.covariance_enu = Vec3(1.0, 1.0, 0.0).asDiagonal();  // no height
  gnss.Process(fix);
  gnss.EndOfStamp();
  fix.header.stamp_ns = FromSeconds(1.2);
  fix.covariance_enu = Vec3(36.0, 1.0, 400.0).asDiagonal();  // horizontal sigma 6 m > 5
  gnss.Process(fix);
  gnss.EndOfStamp();
  const SensorCounters& c = f.ctx.diag.sensors.at("gnss");
  EXPECT_EQ(c.accepted, 2u);
  EXPECT_EQ(c.events.at("horizontal_only"), 2u);
  EXPECT_EQ(Rejected(f.ctx, "gnss", RejectReason::kCovarianceThreshold), 1u);
}

}  // namespace
}  // namespace statebench::est
