// The robot of robot_drive.hpp with an SBAS-grade GNSS receiver (test fixture for
// local_frame_gnss_test.cpp): white noise plus an optional first-order Gauss-Markov part
// (shared/REFERENCE.md), its reported covariance a fraction of the true one. The drive is placed
// in ENU by a yaw and an offset (the IMU and odometry do not see it; the fixes and RobotTruth
// do), so a frame that starts with yaw 0 is not ENU by accident.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/geodetic.hpp"
#include "core/measurements.hpp"
#include "core/random.hpp"
#include "robot_drive.hpp"

namespace statebench::est::testing {

inline const Vec3 kRobotPBodyAntenna(-0.10, 0.05, 0.60);
inline const GeodeticPoint kRobotOrigin{48.7, 2.2, 120.0};  // where ENU (0, 0, 0) is
// The drive's start in ENU: heading (its x axis) and position.
inline constexpr double kRobotStartYawRad = 2.0;
inline const Vec3 kRobotStartEnu(35.0, -20.0, 0.0);

// The robot's setup (IMU, wheel odometry) with the antenna `gnss`.
inline EstimatorSensorSetup RobotGnssSetup() {
  char gnss[256];
  std::snprintf(gnss, sizeof(gnss),
                "  - {type: gnss, id: gnss, rate_hz: 2.5, latency_s: 0.1,"
                " T_body_sensor: {translation: [%g, %g, %g]}}\n",
                kRobotPBodyAntenna.x(), kRobotPBodyAntenna.y(), kRobotPBodyAntenna.z());
  return ParseEstimatorSensorSetup(
      YamlNode::LoadString(RobotSetupYaml(true) + gnss, "robot_gnss_setup.yaml"));
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

// RobotStream(traj, o) with the receiver's fixes over the same span (from their own random
// stream: the other bits do not change), in arrival order.
inline std::vector<Measurement> RobotStreamWithGnss(const DifferentialDriveTrajectory& traj,
                                                    const RobotStreamOptions& o,
                                                    const RobotGnssOptions& g) {
  std::vector<Measurement> stream = RobotStream(traj, o);
  const std::uint64_t seed = o.seed;
  const double start_s = o.start_s;
  const double end = std::min(o.end_s, traj.duration_s() + 2.0);
  NormalSampler normal;
  {
    auto gnss_rng = MakeRng(seed, "robot_gnss");
    const LocalEnuFrame frame(kRobotOrigin);
    const Vec3 white(g.sigma_h_m, g.sigma_h_m, g.sigma_v_m);
    const Vec3 correlated_sigma(g.correlated_sigma_h_m, g.correlated_sigma_h_m,
                                g.correlated_sigma_v_m);
    const double period = 1.0 / g.rate_hz;
    const double phi = std::exp(-period / g.correlated_tau_s);
    Vec3 correlated = correlated_sigma.cwiseProduct(
        Vec3(normal(gnss_rng), normal(gnss_rng), normal(gnss_rng)));  // stationary start
    for (int k = static_cast<int>(std::ceil(start_s * g.rate_hz)); k * period <= end; ++k) {
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

}  // namespace statebench::est::testing
