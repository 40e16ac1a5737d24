// A differential-drive robot on the analytic drive of differential_drive_trajectory.hpp (test
// fixture for the local-frame and GNSS start tests): its mounts, its sensor setup and its
// measurement stream. IMU (consumer MEMS) at 100 Hz, wheel odometry (body_velocity) at 10 Hz,
// and optionally an SBAS-grade GNSS receiver: white noise plus an optional first-order
// Gauss-Markov part (shared/REFERENCE.md), its reported covariance a fraction of the true one.
// The drive is placed in ENU by a yaw and an offset (the IMU and odometry do not see it; the
// fixes and RobotTruth do), so a frame that starts with yaw 0 is not ENU by accident.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "core/geodetic.hpp"
#include "core/measurements.hpp"
#include "core/random.hpp"
#include "core/so3.hpp"
#include "differential_drive_trajectory.hpp"
#include "estimator/imu_noise.hpp"

namespace statebench::est::testing {

// A consumer MEMS IMU (BMI088 class, shared/REFERENCE.md), as the setup tells the estimator.
inline const ImuNoise kRobotImuNoise{2.4e-4, 2.0e-3, 2.0e-5, 3.0e-3};
inline const Vec3 kRobotPBodyImu(0.12, -0.05, 0.25);
inline const Vec3 kRobotImuRpyDeg(1.5, -2.0, 0.0);  // a slightly tilted mount
inline constexpr double kOdometrySigmaMps = 0.02;   // wheel odometry, per measured component
inline const Vec3 kRobotPBodyAntenna(-0.10, 0.05, 0.60);
inline const GeodeticPoint kRobotOrigin{48.7, 2.2, 120.0};  // where ENU (0, 0, 0) is
// The drive's start in ENU: heading (its x axis) and position.
inline constexpr double kRobotStartYawRad = 2.0;
inline const Vec3 kRobotStartEnu(35.0, -20.0, 0.0);

inline Quat RobotQBodyImu() {
  const double k = std::numbers::pi / 180.0;
  return so3::FromRollPitchYaw(k * kRobotImuRpyDeg.x(), k * kRobotImuRpyDeg.y(),
                               k * kRobotImuRpyDeg.z());
}

// Lawnmower drive: five 50 m legs joined by 10 m shifts, every corner a 90 deg turn on the spot
// between pauses; 300 m in total, ending about 70 m from the start. `pause_s` of standstill first.
inline DifferentialDriveTrajectory RobotDrive(double pause_s) {
  using Leg = DifferentialDriveTrajectory::Leg;
  std::vector<Leg> legs;
  if (pause_s > 0.0) legs.push_back({pause_s, 0.0, 0.0});
  const double half_pi = std::numbers::pi / 2.0;
  for (int k = 0; k < 5; ++k) {
    const double side = k % 2 == 0 ? 1.0 : -1.0;  // left turns, then right turns, ...
    legs.push_back({40.0, 50.0, 0.0});            // peak 2.5 m/s
    legs.push_back({1.0, 0.0, 0.0});
    legs.push_back({3.0, 0.0, side * half_pi});
    legs.push_back({10.0, 10.0, 0.0});
    legs.push_back({3.0, 0.0, side * half_pi});
    legs.push_back({1.0, 0.0, 0.0});
  }
  return DifferentialDriveTrajectory(legs, kRobotPBodyImu, RobotQBodyImu());
}

// The setup: IMU with its noise, optionally the wheel odometry and a GNSS antenna `gnss`.
inline std::string RobotSetupYaml(bool with_odometry, bool with_gnss = false) {
  char imu[512];
  std::snprintf(imu, sizeof(imu),
                "  - {type: imu, id: imu, rate_hz: 100, T_body_sensor: {translation: [%g, %g, %g],"
                " rpy_deg: [%g, %g, %g]}, estimator: {gyro_noise_density: %g, "
                "accel_noise_density: %g, gyro_random_walk: %g, accel_random_walk: %g}}\n",
                kRobotPBodyImu.x(), kRobotPBodyImu.y(), kRobotPBodyImu.z(), kRobotImuRpyDeg.x(),
                kRobotImuRpyDeg.y(), kRobotImuRpyDeg.z(), kRobotImuNoise.gyro_noise_density,
                kRobotImuNoise.accel_noise_density, kRobotImuNoise.gyro_random_walk,
                kRobotImuNoise.accel_random_walk);
  std::string yaml = std::string("name: robot\nsensors:\n") + imu;
  if (with_odometry) {
    yaml +=
        "  - {type: body_velocity, id: wheel_odom, rate_hz: 10, latency_s: 0.02,"
        " T_body_sensor: {translation: [0, 0, 0]}}\n";
  }
  if (with_gnss) {
    char gnss[256];
    std::snprintf(gnss, sizeof(gnss),
                  "  - {type: gnss, id: gnss, rate_hz: 2.5, latency_s: 0.1,"
                  " T_body_sensor: {translation: [%g, %g, %g]}}\n",
                  kRobotPBodyAntenna.x(), kRobotPBodyAntenna.y(), kRobotPBodyAntenna.z());
    yaml += gnss;
  }
  return yaml;
}

// An SBAS-grade receiver: white noise and a first-order Gauss-Markov part (per axis, sigma and
// time constant), reporting `reported_scale` times the white sigmas.
struct RobotGnssOptions {
  double rate_hz = 2.5;
  double sigma_h_m = 1.0, sigma_v_m = 2.0;  // white
  double correlated_sigma_h_m = 0.0, correlated_sigma_v_m = 0.0;
  double correlated_tau_s = 100.0;
  double reported_scale = 0.5;  // under-reported by 2x
  double latency_s = 0.1;
};

struct RobotStreamOptions {
  double start_s = 0.0;  // first sample (a later start: the robot is already moving)
  double end_s = 1e9;
  std::uint64_t seed = 1;
  double extra_gyro_sigma_radps = 0.0;  // white vibration on top of the datasheet noise
  bool odometry = true;
  bool gnss = false;  // fixes from their own random stream: the other bits do not change
  RobotGnssOptions gnss_options;
};

// The IMU's true state in ENU (the drive placed by kRobotStartYawRad and kRobotStartEnu).
inline NavState RobotTruth(const DifferentialDriveTrajectory& traj, TimeNs t_ns) {
  NavState x = traj.State(t_ns);
  const Quat q(Eigen::AngleAxisd(kRobotStartYawRad, Vec3::UnitZ()));
  x.q_world_imu = (q * x.q_world_imu).normalized();
  x.p_world = q * x.p_world + kRobotStartEnu;
  x.v_world = q * x.v_world;
  return x;
}

// The antenna's true position in ENU.
inline Vec3 RobotAntennaEnu(const DifferentialDriveTrajectory& traj, double t) {
  const DifferentialDriveTrajectory::Body b = traj.BodyAt(t);
  const Vec3 p_drive =
      Vec3(b.c.x(), b.c.y(), 0.0) + Eigen::AngleAxisd(b.yaw, Vec3::UnitZ()) * kRobotPBodyAntenna;
  return Eigen::AngleAxisd(kRobotStartYawRad, Vec3::UnitZ()) * p_drive + kRobotStartEnu;
}

// IMU at 100 Hz (datasheet noise and bias random walk, turn-on biases) and wheel odometry at
// 10 Hz (velocity of base_link in its frame: vx and vy with kOdometrySigmaMps white noise, vz
// reported unmeasured with a variance of 1e6 as ROS drivers do), and the GNSS fixes when asked
// for, in arrival order.
inline std::vector<Measurement> RobotStream(const DifferentialDriveTrajectory& traj,
                                            const RobotStreamOptions& o) {
  auto rng = MakeRng(o.seed, "robot_imu");
  auto odometry_rng = MakeRng(o.seed, "robot_odometry");
  NormalSampler normal;
  const auto r3 = [&] { return Vec3(normal(rng), normal(rng), normal(rng)); };
  const ImuNoise& n = kRobotImuNoise;
  const double dt = 0.01;
  Vec3 bg(1.5e-3, -2.0e-3, 2.5e-3), ba(0.04, -0.03, 0.05);  // turn-on biases
  std::vector<Measurement> stream;
  const double end_s = std::min(o.end_s, traj.duration_s() + 2.0);
  for (int k = 0; o.start_s + k * dt <= end_s; ++k) {
    const TimeNs t_ns = FromSeconds(o.start_s + k * dt);
    const double t = ToSeconds(t_ns);
    ImuSample s;
    s.header.sensor_id = "imu";
    s.header.stamp_ns = t_ns;
    s.header.arrival_ns = t_ns + 2 * kNsPerMillisecond;
    s.gyro = traj.Gyro(t) + bg + (n.gyro_noise_density / std::sqrt(dt)) * r3() +
             o.extra_gyro_sigma_radps * r3();
    s.accel = traj.Accel(t) + ba + (n.accel_noise_density / std::sqrt(dt)) * r3();
    bg += n.gyro_random_walk * std::sqrt(dt) * r3();
    ba += n.accel_random_walk * std::sqrt(dt) * r3();
    stream.push_back(s);
    if (o.odometry && k % 10 == 0) {
      BodyVelocity v;
      v.header.sensor_id = "wheel_odom";
      v.header.stamp_ns = t_ns;
      v.header.arrival_ns = t_ns + 20 * kNsPerMillisecond;
      const DifferentialDriveTrajectory::Body b = traj.BodyAt(t);
      // Standing wheels read exactly zero (no encoder tick); noise while they turn.
      const double noise = b.speed != 0.0 || b.yaw1 != 0.0 ? kOdometrySigmaMps : 0.0;
      v.velocity = Vec3(b.speed + noise * normal(odometry_rng), noise * normal(odometry_rng), 0.0);
      v.angular_velocity = Vec3(0.0, 0.0, b.yaw1);
      v.covariance = Mat6::Identity() * 1e6;
      v.covariance(0, 0) = v.covariance(1, 1) = kOdometrySigmaMps * kOdometrySigmaMps;
      stream.push_back(v);
    }
  }
  if (o.gnss) {
    const RobotGnssOptions& g = o.gnss_options;
    auto gnss_rng = MakeRng(o.seed, "robot_gnss");
    const LocalEnuFrame frame(kRobotOrigin);
    const Vec3 white(g.sigma_h_m, g.sigma_h_m, g.sigma_v_m);
    const Vec3 correlated_sigma(g.correlated_sigma_h_m, g.correlated_sigma_h_m,
                                g.correlated_sigma_v_m);
    const double period = 1.0 / g.rate_hz;
    const double phi = std::exp(-period / g.correlated_tau_s);
    Vec3 correlated = correlated_sigma.cwiseProduct(
        Vec3(normal(gnss_rng), normal(gnss_rng), normal(gnss_rng)));  // stationary start
    for (int k = static_cast<int>(std::ceil(o.start_s * g.rate_hz)); k * period <= end_s; ++k) {
      const TimeNs t_ns = FromSeconds(k * period);
      const Vec3 w(normal(gnss_rng), normal(gnss_rng), normal(gnss_rng));
      const Vec3 c(normal(gnss_rng), normal(gnss_rng), normal(gnss_rng));
      correlated = phi * correlated + std::sqrt(1.0 - phi * phi) * correlated_sigma.cwiseProduct(c);
      const Vec3 p = RobotAntennaEnu(traj, ToSeconds(t_ns)) + white.cwiseProduct(w) + correlated;
      const GeodeticPoint geo = frame.ToGeodetic(p);
      GnssFix fix;
      fix.header.sensor_id = "gnss";
      fix.header.stamp_ns = t_ns;
      fix.header.arrival_ns = t_ns + FromSeconds(g.latency_s);
      fix.latitude_deg = geo.latitude_deg;
      fix.longitude_deg = geo.longitude_deg;
      fix.altitude_m = geo.altitude_m;
      const Vec3 reported = g.reported_scale * white;
      fix.covariance_enu = reported.cwiseAbs2().asDiagonal();
      fix.status = GnssFixStatus::kSingle;
      stream.push_back(fix);
    }
  }
  std::stable_sort(stream.begin(), stream.end(), [](const Measurement& a, const Measurement& b) {
    return HeaderOf(a).arrival_ns < HeaderOf(b).arrival_ns;
  });
  return stream;
}

// Yaw of the body's forward axis for an IMU orientation.
inline double RobotHeading(const Quat& q_world_imu) {
  const Vec3 forward = q_world_imu * (RobotQBodyImu().conjugate() * Vec3::UnitX());
  return std::atan2(forward.y(), forward.x());
}

}  // namespace statebench::est::testing
