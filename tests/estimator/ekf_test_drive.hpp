// Test fixture for the single-track EKF: a planar drive integrated with the same linear
// single-track model the filter uses (RK4 at 1 ms, steering held between 100 Hz encoder
// samples), constant longitudinal speed, and its measurements: IMU at 100 Hz (at the CG, 0.5 m
// up), GNSS at 10 Hz with 50 ms latency (antenna 0.8 m ahead, 1.4 m up), speed encoder at the
// rear axle and steering encoder at 100 Hz. Noise (optional) from core/random.hpp with a seed.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/geodetic.hpp"
#include "core/measurements.hpp"
#include "core/random.hpp"
#include "core/so3.hpp"
#include "core/state.hpp"
#include "core/time.hpp"
#include "core/yaml_node.hpp"
#include "estimator/ekf_options.hpp"
#include "estimator/estimator_config.hpp"

namespace statebench::est::testing {

struct PlanarTruth {
  TimeNs t_ns = 0;
  double x = 0, y = 0, psi = 0, vx = 0, vy = 0, r = 0;  // body origin, CG velocities
};

struct DriveOptions {
  double duration_s = 60.0;
  double speed_mps = 8.0;
  // Optional longitudinal profile: (vx, dvx/dt) of time; replaces speed_mps. Below 1 m/s the
  // truth has no lateral dynamics (use zero steering there: vy = r = 0).
  std::function<Vec2(double)> speed_profile;
  std::function<double(double)> steering = [](double) { return 0.1; };  // rad, of time
  double initial_yaw_rad = 0.0;
  bool start_steady = true;   // start in the steady state of steering(0) (a circle)
  double gnss_sigma_m = 0.0;  // horizontal noise per axis (vertical 2x)
  double reported_gnss_sigma_m = 0.02;
  double speed_sigma_mps = 0.0;
  double gyro_sigma_radps = 0.0;
  double accel_sigma_mps2 = 0.0;
  double heading_sigma_rad = -1.0;  // > 0: dual-antenna headings at 10 Hz with this sigma
  std::uint64_t seed = 1;
};

inline const Vec3 kDriveImu(0.0, 0.0, 0.5);
inline const Vec3 kDriveAntenna(0.8, 0.0, 1.4);
inline const Vec3 kDriveSpeedEncoder(-0.76, 0.0, 0.27);
inline const GeodeticPoint kDriveOrigin{45.478, 9.227, 120.0};  // Milan

// with_heading: a second antenna 1.6 m behind the first and a dual-antenna heading message
// (baseline rear -> front, along body +x).
// IMU and GNSS antenna only (no encoders).
inline EstimatorSensorSetup MakeMinimalDriveSetup() {
  const std::string yaml =
      "name: ekf_test_minimal\nsensors:\n"
      "  - {type: imu, id: imu, T_body_sensor: {translation: [0, 0, 0.5]}}\n"
      "  - {type: gnss, id: gnss, T_body_sensor: {translation: [0.8, 0, 1.4]}}\n";
  return ParseEstimatorSensorSetup(YamlNode::LoadString(yaml, "ekf_test_minimal.yaml"));
}

inline EstimatorSensorSetup MakeDriveSetup(bool with_heading = false) {
  const std::string yaml =
      "name: ekf_test\nsensors:\n"
      "  - {type: imu, id: imu, T_body_sensor: {translation: [0, 0, 0.5]}}\n"
      "  - {type: gnss, id: gnss, T_body_sensor: {translation: [0.8, 0, 1.4]}}\n"
      "  - {type: speed_encoder, id: speed, T_body_sensor: {translation: [-0.76, 0, 0.27]}}\n"
      "  - {type: steering_encoder, id: steering, T_body_sensor: {translation: [0.93, 0, 0]}}\n"
      "  - {type: wheel_encoders, id: wheels, T_body_sensor: {translation: [0, 0, 0]}}\n";
  const std::string heading =
      "  - {type: gnss, id: gnss_rear, T_body_sensor: {translation: [-0.8, 0, 1.4]}}\n"
      "dual_antenna_headings:\n  - {id: heading, main: gnss_rear, aux: gnss}\n";
  return ParseEstimatorSensorSetup(
      YamlNode::LoadString(yaml + (with_heading ? heading : ""), "ekf_test_setup.yaml"));
}

// d/dt (vy, r) of the linear single-track model at constant vx.
inline Vec2 LateralDerivative(const SingleTrackParams& p, double vx, double vy, double r,
                              double delta) {
  const double lf = p.cg_to_front_axle_m, lr = p.cg_to_rear_axle_m;
  const double fy_f = p.cornering_stiffness_front_npr * (delta - (vy + lf * r) / vx);
  const double fy_r =
      p.cornering_stiffness_rear_npr * (-p.rear_steering_ratio * delta - (vy - lr * r) / vx);
  return Vec2((fy_f + fy_r) / p.mass_kg - r * vx, (lf * fy_f - lr * fy_r) / p.yaw_inertia_kgm2);
}

struct Drive {
  std::vector<PlanarTruth> truth;   // at every IMU stamp (100 Hz)
  std::vector<Measurement> stream;  // arrival order
  LocalEnuFrame frame{kDriveOrigin};
};

inline Drive MakeDrive(const SingleTrackParams& p, const DriveOptions& o) {
  Drive d;
  auto rng = MakeRng(o.seed, "ekf_test_drive");
  NormalSampler normal;
  const auto profile = [&](double t) {
    return o.speed_profile ? o.speed_profile(t) : Vec2(o.speed_mps, 0.0);
  };
  double vx = profile(0.0).x();
  PlanarTruth s;
  s.psi = o.initial_yaw_rad;
  s.vx = vx;
  if (o.start_steady) {  // 0 = A (vy, r) + b: solve by the 2x2 Jacobian (linear model).
    const double delta = o.steering(0.0);
    const Vec2 b = LateralDerivative(p, vx, 0, 0, delta);
    Mat2 A;
    A.col(0) = LateralDerivative(p, vx, 1, 0, delta) - b;
    A.col(1) = LateralDerivative(p, vx, 0, 1, delta) - b;
    const Vec2 vr = A.lu().solve(-b);
    s.vy = vr.x();
    s.r = vr.y();
  }
  const TimeNs step_ns = 1'000'000;  // 1 ms
  const int steps = static_cast<int>(o.duration_s * 1000.0);
  double delta = o.steering(0.0);
  using State = Eigen::Matrix<double, 5, 1>;  // x, y, psi, vy, r
  const auto f = [&](const State& q, double t) {
    const double v = profile(t).x();
    State dq;
    dq << v * std::cos(q[2]) - q[3] * std::sin(q[2]), v * std::sin(q[2]) + q[3] * std::cos(q[2]),
        q[4], v < 1.0 ? Vec2::Zero() : LateralDerivative(p, v, q[3], q[4], delta);
    return dq;
  };
  State q;
  q << s.x, s.y, s.psi, s.vy, s.r;
  for (int k = 0; k <= steps; ++k) {
    const TimeNs t_ns = k * step_ns;
    const double t = ToSeconds(t_ns);
    vx = profile(t).x();
    if (k % 10 == 0) {
      delta = o.steering(t);  // held until the next encoder sample
      PlanarTruth truth{t_ns, q[0], q[1], so3::WrapAngle(q[2]), vx, q[3], q[4]};
      d.truth.push_back(truth);
      const State dq = f(q, t);
      ImuSample imu;
      imu.header = {"imu", t_ns, t_ns};
      // Specific force at the CG (IMU above it, no roll/pitch): a - g, body frame.
      imu.gyro = Vec3(0, 0, q[4] + o.gyro_sigma_radps * normal(rng));
      imu.accel = Vec3(profile(t).y() - q[4] * q[3] + o.accel_sigma_mps2 * normal(rng),
                       dq[3] + q[4] * vx + o.accel_sigma_mps2 * normal(rng), kGravity);
      if (k > 0) d.stream.push_back(imu);
      SteeringAngle steer;
      steer.header = {"steering", t_ns, t_ns};
      steer.angle_rad = delta;
      d.stream.push_back(steer);
      if (k % 20 == 0) {
        VehicleSpeed speed;
        speed.header = {"speed", t_ns, t_ns + 5'000'000};
        speed.speed_mps = vx - q[4] * kDriveSpeedEncoder.y() + o.speed_sigma_mps * normal(rng);
        d.stream.push_back(speed);
      }
      if (k % 100 == 0) {
        const Mat2 R = Eigen::Rotation2Dd(q[2]).toRotationMatrix();
        const Vec2 p_ant = Vec2(q[0], q[1]) + R * kDriveAntenna.head<2>();
        const Vec3 p_enu(p_ant.x() + o.gnss_sigma_m * normal(rng),
                         p_ant.y() + o.gnss_sigma_m * normal(rng),
                         kDriveAntenna.z() + 2 * o.gnss_sigma_m * normal(rng));
        const GeodeticPoint g = d.frame.ToGeodetic(p_enu);
        GnssFix fix;
        fix.header = {"gnss", t_ns, t_ns + 50'000'000};
        fix.latitude_deg = g.latitude_deg;
        fix.longitude_deg = g.longitude_deg;
        fix.altitude_m = g.altitude_m;
        const double sh = o.reported_gnss_sigma_m;
        fix.covariance_enu.diagonal() << sh * sh, sh * sh, 4 * sh * sh;
        fix.status = GnssFixStatus::kRtkFixed;
        d.stream.push_back(fix);
        if (o.heading_sigma_rad > 0.0) {
          DualAntennaHeading h;
          h.header = {"heading", t_ns, t_ns + 50'000'000};
          h.yaw_rad = so3::WrapAngle(q[2] + o.heading_sigma_rad * normal(rng));
          h.yaw_sigma_rad = o.heading_sigma_rad;
          d.stream.push_back(h);
        }
      }
    }
    // RK4 step.
    const double h = 1e-3;
    const State k1 = f(q, t), k2 = f(q + 0.5 * h * k1, t + 0.5 * h),
                k3 = f(q + 0.5 * h * k2, t + 0.5 * h), k4 = f(q + h * k3, t + h);
    q += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  std::stable_sort(d.stream.begin(), d.stream.end(),
                   [](const Measurement& a, const Measurement& b) {
                     return HeaderOf(a).arrival_ns < HeaderOf(b).arrival_ns;
                   });
  return d;
}

// IMU pose/velocity of a planar truth sample (for comparison with StateEstimate).
inline Vec3 TruthImuPosition(const PlanarTruth& s) {
  const Mat3 R = Eigen::AngleAxisd(s.psi, Vec3::UnitZ()).toRotationMatrix();
  return Vec3(s.x, s.y, 0.0) + R * kDriveImu;
}
inline Vec3 TruthImuVelocity(const PlanarTruth& s) {
  const Mat3 R = Eigen::AngleAxisd(s.psi, Vec3::UnitZ()).toRotationMatrix();
  return R * Vec3(s.vx, s.vy, 0.0);  // the IMU is above the CG: same horizontal velocity
}

}  // namespace statebench::est::testing
