// Mount vibration of the simulated IMU (issue 14, "real IMUs"): an engine's harmonic at idle is a
// tone at its firing frequency with the configured rms and no mean; road vibration is absent at
// standstill and scales with speed; the engine speed follows the vehicle's; the other error
// streams keep their bits when vibration is turned on; bad vibration blocks name their line.
#include "sensors/imu_vibration.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <vector>

#include "core/error.hpp"
#include "core/yaml_node.hpp"
#include "sensors/imu_model.hpp"
#include "sensors/sensor_setup.hpp"
#include "truth_fixtures.hpp"

namespace statebench::sensors {
namespace {

constexpr TimeNs kTruthStepNs = kNsPerMillisecond;

SensorSpec VibratingImuSpec(double rate_hz) {
  SensorSpec spec;
  spec.id = "imu";
  spec.rate_hz = rate_hz;
  return spec;
}

// An engine idling at 800 rpm whose second order (26.7 Hz) dominates, as a 4-cylinder's firing.
ImuVibrationOptions IdlingEngine() {
  EngineVibrationOptions e;
  e.idle_rpm = 800.0;
  e.rpm_per_mps = 100.0;
  e.max_rpm = 3000.0;
  e.harmonics.push_back({2.0, Vec3(0.03, 0.02, 0.015), Vec3(0.15, 0.10, 0.35)});
  ImuVibrationOptions o;
  o.engine = e;
  return o;
}

ImuVibrationOptions Road() {
  RoadVibrationOptions r;
  r.gyro_rms_per_mps = Vec3(0.001, 0.002, 0.0005);
  r.accel_rms_per_mps = Vec3(0.02, 0.015, 0.04);
  ImuVibrationOptions o;
  o.road = r;
  return o;
}

// The IMU's samples minus the exact kinematics at its mount, for `seconds` of truth fed at 1 kHz
// through Observe (as the sensor suite does). Rows: gyro x y z, accel x y z.
template <typename TruthAt>
std::vector<std::vector<double>> VibrationSeen(ImuModel& imu, double seconds, TruthAt truth_at) {
  std::vector<std::vector<double>> rows(6);
  const TimeNs end_ns = FromSeconds(seconds);
  for (TimeNs t = 0; t <= end_ns; t += kTruthStepNs) {
    const TruthSample truth = truth_at(t);
    std::vector<Measurement> out;
    imu.Observe(truth, &out);
    for (const Measurement& m : out) {
      const auto& s = std::get<ImuSample>(m);
      const FrameKinematics exact = truth.body.AtMount(imu.spec().T_body_sensor);
      const Vec3 dg = s.gyro - exact.omega_frame;
      const Vec3 da = s.accel - exact.SpecificForce();
      for (int i = 0; i < 3; ++i) {
        rows[i].push_back(dg(i));
        rows[3 + i].push_back(da(i));
      }
    }
  }
  return rows;
}

double Mean(const std::vector<double>& x) {
  double s = 0.0;
  for (const double v : x) s += v;
  return s / static_cast<double>(x.size());
}

double Rms(const std::vector<double>& x) {
  double s = 0.0;
  for (const double v : x) s += v * v;
  return std::sqrt(s / static_cast<double>(x.size()));
}

// Amplitude of the component at frequency f (Hz) of samples taken at rate_hz.
double AmplitudeAt(const std::vector<double>& x, double rate_hz, double f) {
  std::complex<double> sum = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    sum += x[k] * std::polar(1.0, -2.0 * std::numbers::pi * f * static_cast<double>(k) / rate_hz);
  }
  return 2.0 * std::abs(sum) / static_cast<double>(x.size());
}

TEST(ImuVibration, AnIdlingEngineIsAToneAtItsFiringFrequency) {
  ImuOptions options;  // a perfect IMU: what it reads beyond the truth is the vibration
  options.vibration = IdlingEngine();
  ImuModel imu(VibratingImuSpec(200.0), options, 11);
  const auto rows = VibrationSeen(imu, 30.0, [](TimeNs t) { return testing::StaticTruth(t); });
  const EngineHarmonic& h = options.vibration.engine->harmonics[0];
  const double f = 2.0 * 800.0 / 60.0;
  for (int i = 0; i < 6; ++i) {
    const double rms = i < 3 ? h.gyro_rms_radps(i % 3) : h.accel_rms_mps2(i % 3);
    SCOPED_TRACE(i);
    EXPECT_NEAR(Rms(rows[i]), rms, 0.01 * rms);
    EXPECT_LT(std::abs(Mean(rows[i])), 0.01 * rms);  // no bias: it averages out
    EXPECT_NEAR(AmplitudeAt(rows[i], 200.0, f), std::sqrt(2.0) * rms, 0.01 * rms);
    EXPECT_LT(AmplitudeAt(rows[i], 200.0, 1.1 * f), 0.02 * rms);  // a tone, not a band
  }
  std::printf("[ measured ] idle: gyro rms %.4f %.4f %.4f rad/s at %.2f Hz\n", Rms(rows[0]),
              Rms(rows[1]), Rms(rows[2]), f);
}

TEST(ImuVibration, TheEngineSpeedFollowsTheVehicle) {
  ImuOptions options;
  options.vibration = IdlingEngine();
  ImuModel imu(VibratingImuSpec(200.0), options, 12);
  testing::Circle circle;
  circle.radius_m = 50.0;
  circle.speed_mps = 8.0;  // 800 + 100 x 8 = 1600 rpm: the second order at 53.3 Hz
  const auto rows = VibrationSeen(imu, 20.0, [&](TimeNs t) { return circle.At(t); });
  const double rms = options.vibration.engine->harmonics[0].gyro_rms_radps(0);
  EXPECT_NEAR(AmplitudeAt(rows[0], 200.0, 2.0 * 1600.0 / 60.0), std::sqrt(2.0) * rms, 0.02 * rms);
  EXPECT_LT(AmplitudeAt(rows[0], 200.0, 2.0 * 800.0 / 60.0), 0.02 * rms);
}

TEST(ImuVibration, RoadVibrationVanishesAtStandstillAndScalesWithSpeed) {
  ImuOptions options;
  options.vibration = Road();
  ImuModel still(VibratingImuSpec(100.0), options, 13);
  const auto at_rest = VibrationSeen(still, 5.0, [](TimeNs t) { return testing::StaticTruth(t); });
  for (const auto& row : at_rest) EXPECT_EQ(Rms(row), 0.0);

  ImuModel moving(VibratingImuSpec(100.0), options, 13);
  testing::Circle circle;
  circle.radius_m = 100.0;
  circle.speed_mps = 10.0;
  const auto rows = VibrationSeen(moving, 120.0, [&](TimeNs t) { return circle.At(t); });
  const RoadVibrationOptions& r = *options.vibration.road;
  for (int i = 0; i < 6; ++i) {
    const double rms = 10.0 * (i < 3 ? r.gyro_rms_per_mps(i % 3) : r.accel_rms_per_mps(i % 3));
    SCOPED_TRACE(i);
    // About 2700 independent samples (correlation time 1 / (damping w) = 44 ms): the rms is
    // known to 1.4 %; 5 % is 3.5 of its standard deviations.
    EXPECT_NEAR(Rms(rows[i]), rms, 0.05 * rms);
    EXPECT_LT(std::abs(Mean(rows[i])), 0.05 * rms);
  }
}

TEST(ImuVibration, TurningItOnLeavesTheOtherErrorsBitsAlone) {
  ImuOptions plain = ImuPreset(ImuGrade::kConsumer);
  plain.gyro.quantization = plain.accel.quantization = 0.0;
  ImuOptions vibrating = plain;
  vibrating.vibration = IdlingEngine();
  vibrating.vibration.road = Road().road;
  ImuModel a(VibratingImuSpec(100.0), plain, 14), b(VibratingImuSpec(100.0), vibrating, 14);
  ImuVibration reference(vibrating.vibration, 14, "imu/vibration");
  testing::Circle circle;
  for (TimeNs t = 0; t <= FromSeconds(10.0); t += kTruthStepNs) {
    const TruthSample truth = circle.At(t);
    reference.Advance(t > 0 ? ToSeconds(kTruthStepNs) : 0.0, truth.body.v_world.norm());
    std::vector<Measurement> out_a, out_b;
    a.Observe(truth, &out_a);
    b.Observe(truth, &out_b);
    ASSERT_EQ(out_a.size(), out_b.size());
    if (out_a.empty()) continue;
    const auto& sa = std::get<ImuSample>(out_a[0]);
    const auto& sb = std::get<ImuSample>(out_b[0]);
    // The same noise, biases and scale errors: they differ by M times the vibration alone.
    const Vec3 dg = a.gyro_errors().sensitivity() * reference.gyro_radps();
    const Vec3 da = a.accel_errors().sensitivity() * reference.accel_mps2();
    ASSERT_LT((sb.gyro - sa.gyro - dg).norm(), 1e-12) << t;
    ASSERT_LT((sb.accel - sa.accel - da).norm(), 1e-12) << t;
  }
}

std::string VibrationError(const std::string& vibration) {
  const std::string text = "name: s\nsensors:\n  - type: imu\n    id: imu\n    rate_hz: 100\n"
                           "    T_body_sensor: {translation: [0, 0, 0.5]}\n    latency_s: 0.0\n"
                           "    preset: consumer\n    vibration:\n" + vibration;
  try {
    ParseSensorSetup(YamlNode::LoadString(text, "setup.yaml"));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ImuVibration, BadVibrationBlocksNameTheirLine) {
  EXPECT_EQ(VibrationError("      engine: {idle_rpm: 800, harmonics: [{order: 2, gyro_rms_radps: "
                           "[0.01, 0.01, 0.01]}]}\n      road: {accel_rms_per_mps: [0.02, 0.02, "
                           "0.04]}\n"),
            "");
  EXPECT_NE(VibrationError("      engine: {idle_rpm: 800, max_rpm: 600, harmonics: [{order: 2}]}\n")
                .find("setup.yaml:10"),
            std::string::npos);
  EXPECT_NE(VibrationError("      engine: {idle_rpm: 800, harmonics: []}\n")
                .find("needs at least one harmonic"),
            std::string::npos);
  EXPECT_NE(VibrationError("      road: {damping: 1.0}\n").find("damping"), std::string::npos);
  EXPECT_NE(VibrationError("      road: {accel_rms_per_mps: [0.1, -0.1, 0.1]}\n")
                .find("three numbers >= 0"),
            std::string::npos);
  EXPECT_NE(VibrationError("      wind: {}\n").find("unknown"), std::string::npos);
}

}  // namespace
}  // namespace statebench::sensors
