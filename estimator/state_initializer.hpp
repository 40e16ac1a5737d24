// First state of an estimator from the first seconds of data (stamp-ordered).
//
// Attitude = tilt (gravity direction in the IMU frame) + yaw (a horizontal reference direction):
//  - Tilt, static: over a still period (per-axis std of gyro and accel below thresholds, |f|
//    near g, and the GNSS fixes since the IMU began to look so proving a standstill: a constant
//    velocity looks still to an IMU) the specific force is f = R^T (0, 0, g) + b_a, so the up axis in the IMU frame is
//    f_mean / |f_mean| (the accel bias tilts it by |b_a| / g) and the gyro bias is the mean rate.
//  - Attitude, moving: three fixes a, m, b of one antenna and the IMU preintegrated from a give
//    an exact vector observation of R_a (mostly gravity plus whatever the vehicle accelerated,
//    independent of the dynamics; see MovingAnchor), and the yaw reference a second one: TRIAD.
//  - Yaw: a dual-antenna heading (yaw of the baseline main -> aux) or the GNSS course: the
//    horizontal chord between two fixes at least course_min_distance_m apart (more if the fixes
//    are noisy) is parallel to the vehicle's forward axis at about the middle of the chord.
// Static: the tilt and the yaw reference are taken at different stamps; the gyro (minus the gyro
// bias estimate) carries both to the initialisation stamp, and the yaw is fixed by a rotation
// about the world z axis, R = Rz(delta) R_tilt, which keeps the tilt.
// Position: the newest fix moved to the IMU through the lever arm; velocity: zero if the still
// period reaches the initialisation stamp, else from two fixes and the IMU displacement between
// them (exact for any motion once the attitude is known; the accel bias is taken as zero).
// Covariance: diagonal in roll/pitch/yaw (world frame, mapped to the right perturbation
// R^T diag(...) R), position from the fix, velocity and biases from the options.
#pragma once

#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/measurements.hpp"
#include "core/state.hpp"
#include "estimator/estimator_config.hpp"
#include "estimator/gnss_enu.hpp"
#include "estimator/imu_noise.hpp"
#include "estimator/imu_preintegration.hpp"

namespace statebench::est {

struct InitialState {
  NavState state;
  Mat15 covariance = Mat15::Identity();
  std::string method;  // "static", "moving (dual antenna)", "moving (gnss course)", ...
};

class StateInitializer {
 public:
  // forward_imu: the vehicle's forward axis (body +x) in the IMU frame.
  StateInitializer(const InitializationOptions& options, const ImuNoise& noise,
                   const Vec3& forward_imu);

  // Stamp-ordered input. Samples must have increasing stamps (the caller checked them).
  void AddImu(const ImuSample& sample);
  void AddPosition(const GnssPositionEnu& fix, const Vec3& p_imu_antenna);
  void AddHeading(const DualAntennaHeading& heading, const Vec3& baseline_imu);

  // The first state at the newest IMU sample, once tilt, yaw and position are known.
  std::optional<InitialState> TryInitialize();

 private:
  struct Tilt {  // of a still period
    TimeNs t_ns = 0;
    Vec3 up_imu = Vec3::UnitZ();
    Vec3 gyro_bias = Vec3::Zero();
  };
  struct YawReference {
    TimeNs t_ns = 0;
    Vec3 direction_imu = Vec3::UnitX();
    double yaw_rad = 0.0;
    double pitch_rad = 0.0;  // of the reference direction (0 if unknown)
    double sigma_rad = 0.0;
    std::string method;
  };
  struct Fix {
    GnssPositionEnu fix;
    Vec3 p_imu_antenna;
  };

  // A state before or at the initialisation stamp (carried to it with the IMU).
  struct Anchor {
    NavState state;
    double sigma_tilt = 0.0;
    double sigma_v_fix = 0.0;  // velocity error from the fix noise
    bool still_now = false;
  };

  void UpdateStill();
  // Whether the fixes stamped in [from_ns, to_ns] bound the horizontal speed below
  // static_max_speed_mps (least-squares speed + 3 sigma; at least 3 fixes).
  bool FixesProveStandstill(TimeNs from_ns, TimeNs to_ns) const;
  std::optional<YawReference> CourseReference() const;
  std::optional<Anchor> StaticAnchor(const YawReference& yaw, TimeNs t0_ns) const;
  std::optional<Anchor> MovingAnchor(const YawReference& yaw) const;
  ImuPreintegration Preintegrate(TimeNs from_ns, TimeNs to_ns, const Vec3& gyro_bias) const;
  // Rotation from the IMU frame at to_ns to the one at from_ns (either order).
  Quat GyroDelta(TimeNs from_ns, TimeNs to_ns, const Vec3& gyro_bias) const;
  // The latest fix at least a velocity baseline (min_baseline_ns or more if the fixes are noisy)
  // before the newest one, not before t_min_ns.
  const Fix* EarlierFix(TimeNs min_baseline_ns, TimeNs t_min_ns) const;

  InitializationOptions options_;
  ImuNoise noise_;
  Vec3 forward_imu_;
  std::vector<ImuSample> imu_;
  std::deque<Fix> fixes_;
  std::optional<Tilt> still_;            // latest still period
  std::optional<TimeNs> still_since_ns_;  // the IMU has looked still since then
  std::optional<YawReference> heading_;  // latest dual-antenna heading
};

}  // namespace statebench::est
