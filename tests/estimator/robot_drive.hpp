// The differential-drive robot of issue 14 (test fixture): a lawnmower drive of 300 m with turns
// on the spot (differential_drive_trajectory.hpp), its sensor setup (a consumer MEMS IMU on a
// slightly tilted mount, wheel odometry as body_velocity), the seeded measurement stream and a
// run of any estimator on it scored against the truth in the local frame. Used by the factor
// graph's (local_frame_start_test.cpp) and the EKF's (ekf_local_start_test.cpp) local starts.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "core/measurements.hpp"
#include "core/random.hpp"
#include "core/so3.hpp"
#include "core/state.hpp"
#include "core/yaml_node.hpp"
#include "differential_drive_trajectory.hpp"
#include "idle_tone.hpp"
#include "estimator/estimator.hpp"
#include "estimator/estimator_config.hpp"
#include "estimator/imu_noise.hpp"

namespace statebench::est::testing {

// A consumer MEMS IMU (BMI088 class, shared/REFERENCE.md), as the setup tells the estimator.
inline const ImuNoise kRobotImuNoise{2.4e-4, 2.0e-3, 2.0e-5, 3.0e-3};
inline const Vec3 kRobotPBodyImu(0.12, -0.05, 0.25);
inline const Vec3 kRobotImuRpyDeg(1.5, -2.0, 0.0);  // a slightly tilted mount
inline constexpr double kOdometrySigmaMps = 0.02;   // wheel odometry, per measured component

inline Quat RobotQBodyImu() {
  const double k = std::numbers::pi / 180.0;
  return so3::FromRollPitchYaw(k * kRobotImuRpyDeg.x(), k * kRobotImuRpyDeg.y(),
                               k * kRobotImuRpyDeg.z());
}

// Lawnmower drive: five 50 m legs joined by 10 m shifts, every corner a 90 deg turn on the spot
// between pauses; 300 m in total, ending about 70 m from the start. `pause_s` of standstill first.
inline DifferentialDriveTrajectory RobotDrive(double pause_s) {
  std::vector<DifferentialDriveTrajectory::Leg> legs;
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

inline std::string RobotSetupYaml(bool with_odometry) {
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
  return yaml;
}

struct RobotStreamOptions {
  double start_s = 0.0;  // first sample (a later start: the robot is already moving)
  double end_s = 1e9;
  std::uint64_t seed = 1;
  double extra_gyro_sigma_radps = 0.0;  // white vibration on top of the datasheet noise
  bool odometry = true;
  bool idle_tone = false;  // an idle engine's vibration on every IMU sample (idle_tone.hpp)
};

// IMU at 100 Hz (datasheet noise and bias random walk, turn-on biases) and wheel odometry at
// 10 Hz (velocity of base_link in its frame: vx and vy with kOdometrySigmaMps white noise, vz
// reported unmeasured with a variance of 1e6 as ROS drivers do), in arrival order.
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
  const IdleTone tone(o.seed);
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
    if (o.idle_tone) tone.Add(t, &s);
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

struct RobotRun {
  EstimatorDiagnostics diagnostics;
  std::optional<StateEstimate> first;  // the first estimate
  double first_tilt_error_rad = 0.0;
  double first_speed_error_mps = 0.0;
  double end_error_m = 0.0;  // horizontal, aligned by the initial pose
  double max_error_m = 0.0;
  double end_yaw_error_rad = 0.0;
  double end_yaw_sigma_rad = 0.0;
  double distance_m = 0.0;  // driven from the first estimate on
  int estimates = 0;
  int not_local = 0;  // estimates whose status is not `local`
};

// The robot's sensor setup through the YAML parser.
inline EstimatorSensorSetup RobotSetup(bool with_odometry) {
  return ParseEstimatorSensorSetup(
      YamlNode::LoadString(RobotSetupYaml(with_odometry), "robot_setup.yaml"));
}

// Feeds `stream` to `estimator` and scores its estimate at every IMU stamp against the truth
// after aligning the first estimate's position and heading with the truth's (the local frame
// starts at 0 with yaw 0; tilt is not aligned: it is observable).
inline RobotRun RunRobot(Estimator& estimator, const DifferentialDriveTrajectory& traj,
                         const std::vector<Measurement>& stream) {
  RobotRun run;
  Quat q_align = Quat::Identity();
  Vec3 p_est0 = Vec3::Zero(), p_truth0 = Vec3::Zero(), p_truth_previous = Vec3::Zero();
  for (const Measurement& m : stream) {
    estimator.Add(m);
    const auto* imu = std::get_if<ImuSample>(&m);
    if (imu == nullptr) continue;
    const TimeNs t = imu->header.stamp_ns;
    const std::optional<StateEstimate> e = estimator.StateAt(t);
    if (!e) continue;
    const NavState truth = traj.State(t);
    ++run.estimates;
    run.not_local += e->status != EstimateStatus::kLocal;
    if (!run.first) {
      run.first = e;
      q_align = Eigen::AngleAxisd(
          RobotHeading(truth.q_world_imu) - RobotHeading(e->state.q_world_imu), Vec3::UnitZ());
      p_est0 = e->state.p_world;
      p_truth0 = truth.p_world;
      const Vec3 up_est = e->state.q_world_imu.conjugate() * Vec3::UnitZ();
      const Vec3 up_truth = truth.q_world_imu.conjugate() * Vec3::UnitZ();
      run.first_tilt_error_rad = std::acos(std::clamp(up_est.dot(up_truth), -1.0, 1.0));
      run.first_speed_error_mps = (e->state.v_world.norm() - truth.v_world.norm());
    }
    if (run.estimates > 1) run.distance_m += (truth.p_world - p_truth_previous).head<2>().norm();
    p_truth_previous = truth.p_world;
    const Vec3 p = q_align * (e->state.p_world - p_est0) + p_truth0;
    const double error = (p - truth.p_world).head<2>().norm();
    run.max_error_m = std::max(run.max_error_m, error);
    run.end_error_m = error;
    run.end_yaw_error_rad = so3::WrapAngle(RobotHeading(q_align * e->state.q_world_imu) -
                                           RobotHeading(truth.q_world_imu));
    // Yaw sigma: the world-z component of the rotation covariance (right perturbation).
    const Mat3 R = e->state.q_world_imu.toRotationMatrix();
    const Mat3 P_world =
        R * e->covariance.block<3, 3>(kRotationIndex, kRotationIndex) * R.transpose();
    run.end_yaw_sigma_rad = std::sqrt(P_world(2, 2));
  }
  run.diagnostics = estimator.diagnostics();
  return run;
}

}  // namespace statebench::est::testing
