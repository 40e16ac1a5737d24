// Standstill detection with an engine running (issue 14, "real IMUs"): a car with a consumer IMU
// that feels an idle engine (26.7 and 13.3 Hz, gyro rms up to 0.03 rad/s per axis) drives east
// at 5 m/s, stops for 20 s, then creeps at 0.5 m/s; one antenna at CEP 2 m / 4 Hz with Doppler
// velocity. The raw IMU is never quiet; its low band is, and the Doppler velocity tells the stop
// from the creep (which is as quiet to the IMU once its 0.39 m/s^2 ramp is over).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "core/random.hpp"
#include "estimator/ekf_options.hpp"
#include "estimator/ekf_single_track.hpp"
#include "estimator/factor_graph_estimator.hpp"
#include "estimator_scenario.hpp"
#include "idle_tone.hpp"

namespace statebench::est {
namespace {

// Speed along east: constant, or a raised-cosine ramp from v0 to v1 over [t0, t1).
struct SpeedLeg {
  double t0, t1, v0, v1;
};
const std::vector<SpeedLeg> kStopAndCreep = {
    {0.0, 20.0, 5.0, 5.0}, {20.0, 24.0, 5.0, 0.0}, {24.0, 44.0, 0.0, 0.0},
    {44.0, 46.0, 0.0, 0.5}, {46.0, 66.0, 0.5, 0.5}};
constexpr double kStopBeginS = 24.0, kStopEndS = 44.0, kCreepSteadyS = 48.0, kEndS = 66.0;

// Position, speed, acceleration along east at t.
Vec3 Motion(double t) {
  double x = 0.0;
  for (const SpeedLeg& l : kStopAndCreep) {
    const double T = l.t1 - l.t0, tau = std::min(t, l.t1) - l.t0, s = tau / T;
    const double dv = l.v1 - l.v0;
    const double dx =
        l.v0 * tau + 0.5 * dv * (tau - T / std::numbers::pi * std::sin(std::numbers::pi * s));
    if (t < l.t1) {
      return Vec3(x + dx, l.v0 + 0.5 * dv * (1.0 - std::cos(std::numbers::pi * s)),
                  0.5 * dv * std::numbers::pi / T * std::sin(std::numbers::pi * s));
    }
    x += dx;
  }
  return Vec3(x, kStopAndCreep.back().v1, 0.0);
}

// A GNSS outage over [from_s, to_s) during which the accelerometer's x axis reads
// accel_step_mps2 more (a bias the estimator has not seen: its speed drifts).
struct OutageWithBiasStep {
  double from_s = 0.0, to_s = 0.0;
  double accel_step_mps2 = 0.0;
};

// stop_doppler_north_mps: added to the Doppler's north velocity over the stop (a streak of its
// noise that agrees with zero: the mean of 4 readings has 0.035 m/s per axis).
std::vector<Measurement> StopAndCreepStream(std::uint64_t seed, const ImuNoise& white,
                                            const OutageWithBiasStep& outage = {},
                                            double stop_doppler_north_mps = 0.0) {
  const testing::IdleTone tone(seed);
  auto rng = MakeRng(seed, "stop_and_creep");
  NormalSampler normal;
  const auto r3 = [&] { return Vec3(normal(rng), normal(rng), normal(rng)); };
  const LocalEnuFrame frame(testing::kTestOrigin);
  const Vec3 p_imu_antenna(0.45, 0.0, 1.0);
  std::vector<Measurement> stream;
  const double dt = 0.01;
  for (int k = 0; k * dt <= kEndS; ++k) {
    const double t = k * dt;
    ImuSample s;
    s.header.sensor_id = "imu";
    s.header.stamp_ns = FromSeconds(t);
    s.header.arrival_ns = s.header.stamp_ns + 2 * kNsPerMillisecond;
    s.gyro = white.gyro_noise_density / std::sqrt(dt) * r3();
    s.accel = Vec3(Motion(t).z(), 0.0, kGravity) + white.accel_noise_density / std::sqrt(dt) * r3();
    if (t >= outage.from_s && t < outage.to_s) s.accel.x() += outage.accel_step_mps2;
    tone.Add(t, &s);
    stream.push_back(s);
  }
  const double sigma_h = 2.0 / 1.1774, sigma_v = 1.5 * sigma_h;  // CEP 2 m
  for (int k = 0; k * 0.25 <= kEndS; ++k) {
    const double t = k * 0.25;
    if (t >= outage.from_s && t < outage.to_s) continue;
    const Vec3 m = Motion(t);
    const Vec3 p = Vec3(m.x(), 0.0, 0.0) + p_imu_antenna +
                   Vec3(sigma_h * normal(rng), sigma_h * normal(rng), sigma_v * normal(rng));
    const GeodeticPoint g = frame.ToGeodetic(p);
    GnssFix fix;
    fix.header.sensor_id = "gnss_front";
    fix.header.stamp_ns = FromSeconds(t);
    fix.header.arrival_ns = fix.header.stamp_ns + FromSeconds(0.1);
    fix.latitude_deg = g.latitude_deg;
    fix.longitude_deg = g.longitude_deg;
    fix.altitude_m = g.altitude_m;
    fix.covariance_enu.diagonal() << sigma_h * sigma_h, sigma_h * sigma_h, sigma_v * sigma_v;
    fix.status = GnssFixStatus::kSingle;
    GnssVelocity v;
    v.sigma_enu = Vec3(0.07, 0.07, 0.12);
    v.v_enu = Vec3(m.y(), 0.0, 0.0) + v.sigma_enu.cwiseProduct(r3());
    if (t >= kStopBeginS && t < kStopEndS) v.v_enu.y() += stop_doppler_north_mps;
    fix.velocity = v;
    stream.push_back(fix);
  }
  std::stable_sort(stream.begin(), stream.end(), [](const Measurement& a, const Measurement& b) {
    return HeaderOf(a).arrival_ns < HeaderOf(b).arrival_ns;
  });
  return stream;
}

struct StandstillCounts {
  int at_stop = 0;              // zero-velocity factors added during the stop
  int while_creeping = 0;       // added from kCreepSteadyS on
  double max_stop_speed = 0.0;  // estimated speed over the stop's second half
  double mean_stop_speed = 0.0;  // its mean there (the cheap-kit sweep's stop measure)
  // The gyro noise density in use (imu_noise_monitor.hpp) when the stop begins, and at the end.
  double gyro_noise_before_stop = 0.0, gyro_noise_after = 0.0;
};

// Feeds the stop-and-creep stream to `estimator`, counting its IMU event `event` (the factor
// graph's zero-velocity factors, the EKF's zero-velocity updates).
StandstillCounts FeedStopAndCreep(Estimator& estimator, const char* event, std::uint64_t seed,
                                  const OutageWithBiasStep& outage,
                                  double stop_doppler_north_mps) {
  const auto count = [&] {
    const auto& sensors = estimator.diagnostics().sensors;
    const auto imu = sensors.find("imu");
    if (imu == sensors.end()) return 0;
    const auto e = imu->second.events.find(event);
    return e == imu->second.events.end() ? 0 : static_cast<int>(e->second);
  };
  const auto gyro_noise = [&] {
    const auto n = estimator.diagnostics().imu_noise;
    return n ? n->gyro_used : 0.0;
  };
  StandstillCounts c;
  int at_stop_begin = 0, at_stop_end = 0, at_creep = 0, stop_samples = 0;
  testing::FeedOutputs(
      estimator,
      StopAndCreepStream(seed, ImuNoise{2.4e-4, 2e-3}, outage, stop_doppler_north_mps),
      [&](TimeNs t_ns, const std::optional<StateEstimate>& e) {
        const double t = ToSeconds(t_ns);
        if (t_ns == FromSeconds(kStopBeginS)) {
          at_stop_begin = count();
          c.gyro_noise_before_stop = gyro_noise();
        }
        if (t_ns == FromSeconds(kStopEndS)) at_stop_end = count();
        if (t_ns == FromSeconds(kCreepSteadyS)) at_creep = count();
        if (e && t > 0.5 * (kStopBeginS + kStopEndS) && t < kStopEndS) {
          c.max_stop_speed = std::max(c.max_stop_speed, e->state.v_world.norm());
          c.mean_stop_speed += e->state.v_world.norm();
          ++stop_samples;
        }
      });
  if (stop_samples > 0) c.mean_stop_speed /= stop_samples;
  c.gyro_noise_after = gyro_noise();
  c.at_stop = at_stop_end - at_stop_begin;
  c.while_creeping = count() - at_creep;
  return c;
}

StandstillCounts RunStopAndCreep(std::uint64_t seed, const ZeroVelocityOptions& zero_velocity,
                                 const OutageWithBiasStep& outage = {},
                                 double stop_doppler_north_mps = 0.0) {
  FactorGraphOptions options;
  options.origin = testing::kTestOrigin;
  options.zero_velocity = zero_velocity;
  FactorGraphEstimator estimator(testing::MakeSetup(testing::ScenarioOptions{}), options);
  return FeedStopAndCreep(estimator, "zero_velocity_factors", seed, outage,
                          stop_doppler_north_mps);
}

TEST(VibrationStandstill, DetectedAtTheStopNotWhileCreeping) {
  for (const std::uint64_t seed : {1u, 2u}) {
    const StandstillCounts c = RunStopAndCreep(seed, ZeroVelocityOptions{});
    std::printf("seed %d: %d zero-velocity factors in the 20 s stop, %d while creeping, "
                "max speed %.3f m/s over the stop's second half\n",
                static_cast<int>(seed), c.at_stop, c.while_creeping, c.max_stop_speed);
    // 10 per second once the Doppler window (1 s) and the IMU window are past the stop.
    EXPECT_GE(c.at_stop, 170) << seed;
    EXPECT_EQ(c.while_creeping, 0) << seed;
    EXPECT_LT(c.max_stop_speed, 0.05) << seed;
    // The noise is measured at the stop only: driving, the datasheet's stays in use (the
    // vibration is there, but so would be the motion); the stop's idle tone inflates it.
    const double configured = ImuNoise{}.gyro_noise_density;
    EXPECT_EQ(c.gyro_noise_before_stop, configured) << seed;
    EXPECT_GT(c.gyro_noise_after, 2.0 * configured) << seed;
  }
}

TEST(VibrationStandstill, TheRawTestAloneNeverFires) {
  ZeroVelocityOptions raw;
  raw.lowpass_s = 0.0;
  const StandstillCounts c = RunStopAndCreep(1, raw);
  EXPECT_EQ(c.at_stop, 0);
}

// A GNSS outage from 10 s to the end of the stop, and an accelerometer bias step the estimator
// has not seen: its speed has drifted by the stop. The stop is found when the estimated speed is
// tested against its own sigma too, and lost when tested against the 0.3 m/s bound alone.
TEST(VibrationStandstill, AStopInAnOutageIsFoundThoughTheSpeedDrifted) {
  const OutageWithBiasStep outage{10.0, kStopEndS, 0.08};
  ZeroVelocityOptions bound_only;
  bound_only.estimated_speed_sigmas = 0.0;
  for (const std::uint64_t seed : {3u, 4u}) {
    const StandstillCounts c = RunStopAndCreep(seed, ZeroVelocityOptions{}, outage);
    const StandstillCounts b = RunStopAndCreep(seed, bound_only, outage);
    std::printf("seed %d: with the sigmas %d zero-velocity factors at the stop (max speed "
                "%.3f m/s over its second half), with the bound only %d (%.3f m/s)\n",
                static_cast<int>(seed), c.at_stop, c.max_stop_speed, b.at_stop, b.max_stop_speed);
    EXPECT_GE(c.at_stop, 150) << seed;
    EXPECT_LT(c.max_stop_speed, 0.05) << seed;
    EXPECT_LT(b.at_stop, c.at_stop / 2) << seed;
    EXPECT_EQ(c.while_creeping, 0) << seed;
  }
}

// The Doppler reads 0.06 m/s north over the whole stop (within 3 sigmas of its mean's 0.035 m/s:
// a streak of its noise, as on the cheap kit's seed 26). A Doppler mean that agrees with zero
// makes the zero-velocity factor's sigma that mean's sigma and the stop reads nearer zero; with
// the creep bound's 0.1 m/s the estimate follows the Doppler further.
TEST(VibrationStandstill, ADopplerThatAgreesWithZeroTightensTheFactor) {
  ZeroVelocityOptions no_agreement;
  no_agreement.doppler_agreement_sigmas = 0.0;
  for (const std::uint64_t seed : {1u, 2u}) {
    const StandstillCounts c = RunStopAndCreep(seed, ZeroVelocityOptions{}, {}, 0.06);
    const StandstillCounts b = RunStopAndCreep(seed, no_agreement, {}, 0.06);
    std::printf("seed %d: max speed over the stop's second half %.3f m/s (Doppler agreement), "
                "%.3f m/s (sigma_without_encoder_mps)\n",
                static_cast<int>(seed), c.max_stop_speed, b.max_stop_speed);
    EXPECT_GE(c.at_stop, 170) << seed;
    EXPECT_EQ(c.while_creeping, 0) << seed;
    // Measured 0.027 / 0.043 and 0.034 / 0.048 m/s: the mean of 4 readings is 0.06 +- 0.035
    // north, so the agreement test (3 sigmas) fails now and then and 0.1 m/s is used there.
    EXPECT_LT(c.max_stop_speed, 0.8 * b.max_stop_speed) << seed;
  }
}

// The EKF without a speed input stands still by the same evidence (zero_velocity_evidence.hpp,
// its default ZeroVelocityOptions): updates through the stop, none while creeping, and the stop
// reads near zero on average (its samples spread more than the factor graph's: each IMU sample
// and Doppler reading moves the filter between two updates; measured max 0.072 / 0.061 m/s).
TEST(VibrationStandstill, TheEkfWithoutASpeedInputFindsTheStopToo) {
  for (const std::uint64_t seed : {1u, 2u}) {
    EkfSingleTrackEstimator ekf(testing::MakeSetup(testing::ScenarioOptions{}), EkfOptions{});
    const StandstillCounts c = FeedStopAndCreep(ekf, "zero_velocity_updates", seed, {}, 0.0);
    std::printf("ekf, seed %d: %d zero-velocity updates in the 20 s stop, %d while creeping, "
                "speed over the stop's second half mean %.3f max %.3f m/s\n",
                static_cast<int>(seed), c.at_stop, c.while_creeping, c.mean_stop_speed,
                c.max_stop_speed);
    EXPECT_GE(c.at_stop, 170) << seed;
    EXPECT_EQ(c.while_creeping, 0) << seed;
    EXPECT_LT(c.mean_stop_speed, 0.05) << seed;
  }
}

}  // namespace
}  // namespace statebench::est
