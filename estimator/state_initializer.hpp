// First state of an estimator from the first seconds of data (stamp-ordered).
//
// Attitude = tilt (gravity direction in the IMU frame) + yaw (a horizontal reference direction):
//  - Tilt, static: over a still period (per-axis std of gyro and accel below thresholds, |f|
//    near g, and the GNSS fixes since the IMU began to look so proving a standstill: a constant
//    velocity looks still to an IMU) the specific force is f = R^T (0, 0, g) + b_a, so the up axis
//    in the IMU frame is f_mean / |f_mean| (the accel bias tilts it by |b_a| / g) and the gyro bias
//    is the mean rate.
//  - Attitude, moving: three fixes a, m, b of one antenna and the IMU preintegrated from a give
//    an exact vector observation of R_a (mostly gravity plus whatever the vehicle accelerated,
//    independent of the dynamics; see MovingAnchor), and the yaw reference a second one: TRIAD.
//  - Attitude, moving with GNSS (Doppler) velocities: two fixes a, b at least 1 s apart with
//    velocities and the IMU preintegrated between them give the same vector observation from
//    velocities, R_a (dv + dR [w_b]x l - [w_a]x l) = v_b - v_a - g tau (see VelocityAnchor),
//    within seconds where positions at CEP 2 m need a 10 s baseline.
//  - Yaw: a dual-antenna heading (yaw of the baseline main -> aux), the course of a GNSS velocity
//    (its horizontal speed above velocity_course_min_speed_mps and 10 sigma: the antenna's
//    velocity s f + w x l in the IMU frame, f the forward axis, s >= 0 solved from |v|) or the
//    GNSS course: the horizontal chord between two fixes at least course_min_distance_m apart
//    (more if the fixes are noisy) is parallel to the vehicle's forward axis at about the middle
//    of the chord.
// Static: the tilt and the yaw reference are taken at different stamps; the gyro (minus the gyro
// bias estimate) carries both to the initialisation stamp, and the yaw is fixed by a rotation
// about the world z axis, R = Rz(delta) R_tilt, which keeps the tilt.
// Position: the newest fix moved to the IMU through the lever arm; velocity: zero if the still
// period reaches the initialisation stamp, else the newest fix's velocity moved to the IMU
// (v_imu = v_antenna - R (w x l)) when it has one, else from two fixes and the IMU displacement
// between them (exact for any motion once the attitude is known; the accel bias is taken as
// zero). Doppler velocities also prove a standstill (mean horizontal velocity + 3 sigma below
// static_max_speed_mps) where noisy positions need many seconds.
// Covariance: diagonal in roll/pitch/yaw (world frame, mapped to the right perturbation
// R^T diag(...) R), position from the fix, velocity and biases from the options.
//
// Without an absolute-position sensor (no GNSS antenna: LocalStart::enabled), or with one whose
// fixes cannot start it yet while body-frame odometry is in the setup (LocalStart::enu_later)
// and no fix came or the fixes are too noisy for a course over course_min_distance_m, the first
// state is in a local frame: position 0 and the vehicle's forward axis along x (yaw 0) at
// the initialisation stamp, both known to kLocalPositionSigmaM / kLocalYawSigmaRad (the prior is
// what anchors them: neither is observable). Tilt and gyro bias from a still period (the
// odometry, when the setup has one, must read zero over it), or, while moving, tilt and
// velocity from the body-frame odometry (odometry_alignment.hpp) over kOdometryWindowS.
// WaitingFor() says what a start still lacks (the estimator's diagnostics carry it).
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
#include "estimator/odometry_alignment.hpp"

namespace statebench::est {

struct InitialState {
  NavState state;
  Mat15 covariance = Mat15::Identity();
  // "static (dual antenna)", "moving (gnss course)", "static (local frame)",
  // "moving (odometry, local frame)", ...
  std::string method;
  bool local_frame = false;  // position 0 and yaw 0 at the start (TryInitializeLocal)
  // The slow error (ENU covariance) the start's position shares with the fixes it was made of,
  // when the smoother estimates that error (GnssFrontEnd::RefineInitialState); zero otherwise.
  // The position is then the fixes' (position + slow error): the smoother gets it as a fix on
  // both (GnssFrontEnd::OnInitialized) instead of a prior on the position alone, and the
  // position's own covariance is `covariance`'s plus this.
  Mat3 position_slow_error = Mat3::Zero();

  // m^2 added to the position's variance of the smoother's prior with position_slow_error: 100
  // m, far more than any start's position error, far less than would upset the solver's scaling.
  static constexpr double kReleasedPositionVariance = 1e4;
  // The smoother's prior on the first state: `covariance`, the position released when
  // position_slow_error is set.
  Mat15 SmootherPrior() const {
    Mat15 p = covariance;
    if (!position_slow_error.isZero(0.0)) {
      p.block<3, 3>(kPositionIndex, kPositionIndex) += kReleasedPositionVariance * Mat3::Identity();
    }
    return p;
  }
  // The start's covariance with the position's own: the slow error added.
  Mat15 OutputCovariance() const {
    Mat15 p = covariance;
    p.block<3, 3>(kPositionIndex, kPositionIndex) += position_slow_error;
    return p;
  }
};

// How a setup starts in a local frame: without an absolute-position sensor always; with one
// (enu_later) only as long as the GNSS cannot start it in ENU, the estimator then moving the
// local frame into ENU once the fixes give the yaw (enu_alignment.hpp).
struct LocalStart {
  bool enabled = false;       // a start in a local frame is allowed
  bool has_odometry = false;  // body-frame velocity (body_velocity, speed encoder) in the setup
  bool enu_later = false;     // a GNSS antenna in the setup: a GNSS start first, else local
};

inline constexpr double kLocalPositionSigmaM = 1e-3;  // prior of the local frame's origin
inline constexpr double kLocalYawSigmaRad = 1e-3;     // and of its x axis
inline constexpr double kOdometryWindowS = 1.0;       // odometry fitted by a moving local start
inline constexpr double kMaxStillGravityError = 0.5;  // | |f| - g | in a still period, m/s^2

class StateInitializer {
 public:
  // forward_imu: the vehicle's forward axis (body +x) in the IMU frame.
  StateInitializer(const InitializationOptions& options, const ImuNoise& noise,
                   const Vec3& forward_imu, LocalStart local = {});

  // Stamp-ordered input. Samples must have increasing stamps (the caller checked them).
  void AddImu(const ImuSample& sample);
  void AddPosition(const GnssPositionEnu& fix, const Vec3& p_imu_antenna);
  void AddHeading(const DualAntennaHeading& heading, const Vec3& baseline_imu);
  // Body-frame odometry; kept for a local start only (ignored when local().enabled is false).
  void AddVelocity(const OdometryVelocity& velocity);

  const LocalStart& local() const { return local_; }

  // The first state at the newest IMU sample, once tilt, yaw and position are known.
  std::optional<InitialState> TryInitialize();

  // What the start is still waiting for, one line, e.g. "no still period of 1 s (quietest: gyro
  // std 0.04 rad/s > 0.01) and no GNSS course (2 fixes, longest chord 3.1 m of 5 m)".
  std::string WaitingFor() const;

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
  // A quiet IMU whose standstill the fixes or the odometry did not prove.
  enum class NotProven { kNo, kFixesMoved, kFixesNoProof, kOdometryMoving };
  // The quietest still-test window seen (the largest of its statistics over their thresholds),
  // for WaitingFor().
  struct StillRecord {
    bool tested = false;  // at least one window of static_duration_s
    double score = 0.0;
    double gyro_std = 0.0, accel_std = 0.0, gravity_error = 0.0, mean_rate = 0.0;
    NotProven not_proven = NotProven::kNo;  // the latest quiet window's
  };

  // A state before or at the initialisation stamp (carried to it with the IMU).
  struct Anchor {
    NavState state;
    double sigma_tilt = 0.0;
    double sigma_v_fix = 0.0;  // velocity error from the fix noise
    bool still_now = false;
    // A moving start fitted over its chord (FitMovingAnchor): the covariance of (p, v, rotation
    // as the right perturbation) at state.t_ns, from the fit; the start's position covariance
    // is this one carried to the start instead of the newest fix's.
    std::optional<Eigen::Matrix<double, 9, 9>> fit_covariance;
  };

  void UpdateStill();
  // Whether the fixes stamped in [from_ns, to_ns] bound the horizontal speed below
  // static_max_speed_mps (least-squares speed + 3 sigma; at least 3 fixes).
  bool FixesProveStandstill(TimeNs from_ns, TimeNs to_ns) const;
  // Whether the odometry stamped in [from_ns, to_ns] reads zero (each measured component's mean
  // within static_max_speed_mps, 3 sigma); true without odometry in the setup.
  bool OdometryProvesStandstill(TimeNs from_ns, TimeNs to_ns) const;
  // The start in ENU from the GNSS (state_initializer.cpp) and in a local frame
  // (state_initializer_local.cpp).
  std::optional<InitialState> TryInitializeEnu();
  std::optional<InitialState> TryInitializeLocal();
  // The newest fix is precise enough for a GNSS course over course_min_distance_m.
  bool PreciseFixes() const;
  std::optional<OdometryAlignment> AlignOverOdometryWindow() const;
  std::string StillWaitingFor() const;
  std::string LocalWaitingFor() const;
  std::optional<YawReference> CourseReference() const;
  std::optional<YawReference> VelocityCourseReference() const;
  std::optional<Anchor> VelocityAnchor(const YawReference& yaw) const;
  // Whether the Doppler velocities stamped in [from_ns, to_ns] bound the horizontal speed below
  // static_max_speed_mps; nullopt when fewer than two fixes there have one.
  std::optional<bool> VelocitiesProveStandstill(TimeNs from_ns, TimeNs to_ns) const;
  // Raw gyro of the IMU sample nearest t_ns.
  Vec3 GyroNear(TimeNs t_ns) const;
  // Velocity of the IMU from a fix's antenna velocity, attitude and gyro bias.
  Vec3 ImuVelocityFromFix(const Fix& f, const Quat& q_world_imu, const Vec3& gyro_bias) const;
  std::optional<Anchor> StaticAnchor(const YawReference& yaw, TimeNs t0_ns) const;
  std::optional<Anchor> MovingAnchor(const YawReference& yaw) const;
  // The moving anchor at fix a refined over every fix since a (state_initializer_moving_fit.cpp).
  void FitMovingAnchor(const Fix& a, const YawReference& yaw, Anchor* anchor) const;
  ImuPreintegration Preintegrate(TimeNs from_ns, TimeNs to_ns, const Vec3& gyro_bias) const;
  // Rotation from the IMU frame at to_ns to the one at from_ns (either order).
  Quat GyroDelta(TimeNs from_ns, TimeNs to_ns, const Vec3& gyro_bias) const;
  // The latest fix at least a velocity baseline (min_baseline_ns or more if the fixes are noisy)
  // before the newest one, not before t_min_ns.
  const Fix* EarlierFix(TimeNs min_baseline_ns, TimeNs t_min_ns) const;

  InitializationOptions options_;
  ImuNoise noise_;
  Vec3 forward_imu_;
  LocalStart local_;
  std::vector<ImuSample> imu_;
  std::deque<Fix> fixes_;
  std::deque<OdometryVelocity> odometry_;  // local start only
  bool odometry_since_fit_ = false;        // a sample arrived since the last odometry fit
  std::optional<double> fit_gravity_;      // |G| of the last odometry fit that was refused
  StillRecord still_record_;
  std::optional<Tilt> still_;            // latest still period
  std::optional<TimeNs> still_since_ns_;  // the IMU has looked still since then
  std::optional<YawReference> heading_;  // latest dual-antenna heading
};

}  // namespace statebench::est
