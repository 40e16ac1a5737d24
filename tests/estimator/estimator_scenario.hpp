// Measurement streams for the estimator tests (test fixture): IMU samples and GNSS fixes
// synthesised from VehicleTrajectory, fixes converted to WGS84 with core/geodetic.hpp, every
// measurement stamped and delivered in arrival order like the simulator does.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "core/geodetic.hpp"
#include "core/measurements.hpp"
#include "core/random.hpp"
#include "core/yaml_node.hpp"
#include "estimator/estimator.hpp"
#include "estimator/estimator_config.hpp"
#include "estimator/imu_noise.hpp"
#include "vehicle_trajectory.hpp"

namespace statebench::est::testing {

inline const GeodeticPoint kTestOrigin{48.7, 2.2, 120.0};

struct Antenna {
  std::string id;
  Vec3 p_imu;  // lever arm (the IMU frame is the body frame in these tests)
};

struct ScenarioOptions {
  double start_s = 0.0;  // first IMU sample
  double duration_s = 20.0;
  double motion_start_s = 2.0;  // still before
  double imu_rate_hz = 100.0;
  double gnss_rate_hz = 10.0;
  std::vector<Antenna> antennas = {{"gnss_front", Vec3(0.45, 0.0, 1.0)}};
  // IMU errors: white noise and bias random walk with these densities (off if imu_noisy is
  // false), plus a constant initial bias.
  bool imu_noisy = false;
  ImuNoise imu_noise;
  Vec3 gyro_bias = Vec3::Zero();
  Vec3 accel_bias = Vec3::Zero();
  // Triad errors: the IMU measures (I + K) u (scale factors on K's diagonal, cross-axis terms off
  // it); zero leaves the samples' bits as they are.
  Mat3 gyro_triad = Mat3::Zero();
  Mat3 accel_triad = Mat3::Zero();
  // GNSS: white noise (sigma per axis) and the covariance the receiver reports.
  double gnss_sigma_h = 0.0, gnss_sigma_v = 0.0;
  double reported_sigma_h = 0.01, reported_sigma_v = 0.015;
  double gnss_latency_s = 0.1;
  double gnss_extra_latency_s = 0.0;  // uniform in [0, this): out-of-order delivery
  double outage_begin_s = 1e9, outage_end_s = 1e9;
  // A slowly varying error on top (first-order Gauss-Markov per axis and antenna, stationary
  // sigmas and correlation time), not in the reported covariance; off at 0. Drawn from its own
  // stream, so turning it on leaves the other bits unchanged.
  double gnss_slow_sigma_h = 0.0, gnss_slow_sigma_v = 0.0;
  double gnss_slow_tau_s = 100.0;
  // Doppler velocity of the antenna (v + R (w x l)) with white noise of these sigmas, reported
  // as they are; drawn from its own stream, so turning it on leaves the other bits unchanged.
  bool gnss_velocity = false;
  double velocity_sigma_h = 0.07, velocity_sigma_v = 0.12;
  std::uint64_t seed = 1;
};

struct Scenario {
  ScenarioOptions options;
  VehicleTrajectory trajectory;
  std::vector<Measurement> stream;  // arrival order

  NavState Truth(TimeNs t_ns) const { return trajectory.State(t_ns); }
};

// The outage tests' drive: a noisy IMU with constant gyro and accel biases that make it drift
// when GNSS goes, and RTK-grade fixes (2 cm / 3 cm, reported as they are).
inline ScenarioOptions DriftingImuRtkOptions(double duration_s) {
  ScenarioOptions so;
  so.duration_s = duration_s;
  so.imu_noisy = true;
  so.gyro_bias = Vec3(2e-4, -3e-4, 4e-4);
  so.accel_bias = Vec3(0.02, -0.015, 0.01);
  so.gnss_sigma_h = so.reported_sigma_h = 0.02;
  so.gnss_sigma_v = so.reported_sigma_v = 0.03;
  return so;
}

inline Scenario MakeScenario(const ScenarioOptions& o) {
  Scenario sc{o, VehicleTrajectory(o.motion_start_s), {}};
  auto rng = MakeRng(o.seed, "estimator_scenario");
  auto latency_rng = MakeRng(o.seed, "estimator_scenario_latency");
  auto velocity_rng = MakeRng(o.seed, "estimator_scenario_velocity");
  auto slow_rng = MakeRng(o.seed, "estimator_scenario_slow_error");
  NormalSampler velocity_normal;
  NormalSampler normal_slow;
  NormalSampler normal;
  const auto r3 = [&] { return Vec3(normal(rng), normal(rng), normal(rng)); };
  const LocalEnuFrame frame(kTestOrigin);
  const double dt = 1.0 / o.imu_rate_hz;
  const ImuNoise& n = o.imu_noise;
  Vec3 bg = o.gyro_bias, ba = o.accel_bias;
  const int num_imu = static_cast<int>(std::lround(o.duration_s * o.imu_rate_hz));
  for (int k = 0; k <= num_imu; ++k) {
    ImuSample s;
    s.header.sensor_id = "imu";
    s.header.stamp_ns = FromSeconds(o.start_s + k * dt);
    s.header.arrival_ns = s.header.stamp_ns + 2 * kNsPerMillisecond;
    const double t = ToSeconds(s.header.stamp_ns);
    s.gyro = sc.trajectory.Gyro(t) + bg;
    s.accel = sc.trajectory.Accel(t) + ba;
    if (!o.gyro_triad.isZero(0.0)) s.gyro += o.gyro_triad * sc.trajectory.Gyro(t);
    if (!o.accel_triad.isZero(0.0)) s.accel += o.accel_triad * sc.trajectory.Accel(t);
    if (o.imu_noisy) {
      s.gyro += n.gyro_noise_density / std::sqrt(dt) * r3();
      s.accel += n.accel_noise_density / std::sqrt(dt) * r3();
      bg += n.gyro_random_walk * std::sqrt(dt) * r3();
      ba += n.accel_random_walk * std::sqrt(dt) * r3();
    }
    sc.stream.push_back(s);
  }
  const int num_fix = static_cast<int>(std::floor(o.duration_s * o.gnss_rate_hz));
  const Vec3 slow_sigma(o.gnss_slow_sigma_h, o.gnss_slow_sigma_h, o.gnss_slow_sigma_v);
  const double slow_rho = std::exp(-1.0 / (o.gnss_rate_hz * o.gnss_slow_tau_s));
  std::vector<Vec3> slow(o.antennas.size());
  for (Vec3& e : slow) {
    for (int i = 0; i < 3; ++i) e[i] = slow_sigma[i] * normal_slow(slow_rng);
  }
  for (int k = 0; k <= num_fix; ++k) {
    const TimeNs t_ns = FromSeconds(o.start_s + k / o.gnss_rate_hz);
    const double t = ToSeconds(t_ns);
    const double extra = o.gnss_extra_latency_s * Uniform01(latency_rng);
    if (k > 0) {
      for (Vec3& e : slow) {
        for (int i = 0; i < 3; ++i) {
          e[i] = slow_rho * e[i] +
                 std::sqrt(1.0 - slow_rho * slow_rho) * slow_sigma[i] * normal_slow(slow_rng);
        }
      }
    }
    if (t >= o.outage_begin_s && t < o.outage_end_s) continue;
    for (std::size_t ai = 0; ai < o.antennas.size(); ++ai) {
      const Antenna& a = o.antennas[ai];
      const NavState truth = sc.trajectory.State(t_ns);
      Vec3 p = truth.p_world + truth.q_world_imu * a.p_imu;
      p += Vec3(o.gnss_sigma_h * normal(rng), o.gnss_sigma_h * normal(rng),
                o.gnss_sigma_v * normal(rng));
      if (o.gnss_slow_sigma_h > 0.0 || o.gnss_slow_sigma_v > 0.0) p += slow[ai];
      const GeodeticPoint g = frame.ToGeodetic(p);
      GnssFix fix;
      fix.header.sensor_id = a.id;
      fix.header.stamp_ns = t_ns;
      fix.header.arrival_ns = t_ns + FromSeconds(o.gnss_latency_s + extra);
      fix.latitude_deg = g.latitude_deg;
      fix.longitude_deg = g.longitude_deg;
      fix.altitude_m = g.altitude_m;
      fix.covariance_enu.diagonal() << o.reported_sigma_h * o.reported_sigma_h,
          o.reported_sigma_h * o.reported_sigma_h, o.reported_sigma_v * o.reported_sigma_v;
      fix.status = GnssFixStatus::kRtkFixed;
      if (o.gnss_velocity) {
        GnssVelocity v;
        v.sigma_enu = Vec3(o.velocity_sigma_h, o.velocity_sigma_h, o.velocity_sigma_v);
        v.v_enu = truth.v_world + truth.q_world_imu * sc.trajectory.Gyro(t).cross(a.p_imu);
        for (int i = 0; i < 3; ++i) v.v_enu[i] += v.sigma_enu[i] * velocity_normal(velocity_rng);
        fix.velocity = v;
      }
      sc.stream.push_back(fix);
    }
  }
  std::stable_sort(sc.stream.begin(), sc.stream.end(),
                   [](const Measurement& a, const Measurement& b) {
                     return HeaderOf(a).arrival_ns < HeaderOf(b).arrival_ns;
                   });
  return sc;
}

// The sensor setup of a scenario, through the YAML parser (IMU at the body origin).
inline EstimatorSensorSetup MakeSetup(const ScenarioOptions& o, const std::string& extra = "") {
  std::string yaml =
      "name: test\nsensors:\n  - {type: imu, id: imu, rate_hz: 100, latency_s: 0,"
      " T_body_sensor: {translation: [0, 0, 0]}}\n";
  for (const Antenna& a : o.antennas) {
    yaml += "  - {type: gnss, id: " + a.id +
            ", rate_hz: 10, latency_s: 0.1, T_body_sensor: " + "{translation: [" +
            std::to_string(a.p_imu.x()) + ", " + std::to_string(a.p_imu.y()) + ", " +
            std::to_string(a.p_imu.z()) + "]}}\n";
  }
  return ParseEstimatorSensorSetup(YamlNode::LoadString(yaml + extra, "test_setup.yaml"));
}

// Rotation error (rad, right perturbation), position error (m).
inline double RotationError(const NavState& est, const NavState& truth) {
  return so3::Log<double>(truth.q_world_imu.conjugate() * est.q_world_imu).norm();
}

// [rotation (right perturbation), position, velocity] of a minus b.
inline Vec9 StateDifference(const NavState& a, const NavState& b) {
  Vec9 d;
  d << so3::Log<double>(b.q_world_imu.conjugate() * a.q_world_imu), a.p_world - b.p_world,
      a.v_world - b.v_world;
  return d;
}

// |yaw error| (rad, wrapped), yaw as so3::ToRollPitchYaw gives it.
inline double YawError(const NavState& est, const NavState& truth) {
  return std::abs(so3::WrapAngle(so3::ToRollPitchYaw(est.q_world_imu).z() -
                                 so3::ToRollPitchYaw(truth.q_world_imu).z()));
}

// Feeds `stream` in its order and, after each IMU sample, hands on_output(t_ns, estimate) the
// estimator's output at the sample's stamp (nullopt while it has none).
template <typename OnOutput>
void FeedOutputs(Estimator& estimator, const std::vector<Measurement>& stream,
                 OnOutput&& on_output) {
  for (const Measurement& m : stream) {
    estimator.Add(m);
    if (!std::holds_alternative<ImuSample>(m)) continue;
    const TimeNs t = HeaderOf(m).stamp_ns;
    const std::optional<StateEstimate> e = estimator.StateAt(t);
    on_output(t, e);
  }
}

}  // namespace statebench::est::testing
