// Internal to EkfSingleTrackEstimator (not part of the estimator's API): the filter's members and
// the sensor roles it resolves from the setup. Measurement intake, reordering and the output are
// in ekf_single_track.cpp; propagation, the measurement updates and the initialisation in
// ekf_measurement_updates.cpp; the vehicle model in ekf_single_track_model.hpp.
#pragma once

#include <Eigen/Eigenvalues>
#include <deque>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/so3.hpp"
#include "estimator/ekf_single_track.hpp"
#include "estimator/ekf_single_track_model.hpp"
#include "estimator/gnss_enu.hpp"
#include "estimator/refused_fix_track.hpp"

namespace statebench::est {
namespace ekf {

inline constexpr double kMaxSubstepS = 0.0025;
inline constexpr double kMaxAbsSteeringRad = 1.2;  // beyond any road-wheel angle
inline constexpr double kMaxAbsSpeedMps = 100.0;

// A GNSS antenna, a speed encoder, or a steering encoder, resolved from the setup.
enum class Role { kImu, kGnss, kSpeed, kSteering, kHeading, kUnsupported };

struct SensorInfo {
  Role role = Role::kUnsupported;
  Vec3 p_body_sensor = Vec3::Zero();
  double covariance_scale = 1.0;
  double min_sigma_m = 0.0;
  double yaw_offset_rad = 0.0;  // heading: yaw of the antenna baseline in the body frame
};

// A measurement waiting for the IMU to pass its stamp.
struct Pending {
  TimeNs stamp_ns = 0;
  std::string sensor_id;
  Measurement measurement;
};

}  // namespace ekf

struct EkfSingleTrackEstimator::Impl {
  using VecN = ekf::VecN;
  using MatN = ekf::MatN;
  using Role = ekf::Role;
  using SensorInfo = ekf::SensorInfo;
  using Pending = ekf::Pending;
  using Snapshot = ekf::Snapshot;
  static constexpr int kN = ekf::kN;

  EstimatorSensorSetup setup;
  std::vector<std::string> position_sensors = setup.PositionSensorIds();
  EkfOptions options;
  Mat3 R_body_imu = Mat3::Identity();
  Vec3 p_body_imu = Vec3::Zero();
  std::map<std::string, SensorInfo> sensors;
  std::string course_antenna;
  bool has_steering = false;  // without a steering encoder r is a random walk, vy relaxes to 0
  std::optional<ekf::SingleTrackModel> model;  // once the setup is read

  EstimatorDiagnostics diag;
  std::optional<LocalEnuFrame> frame;
  TimeNs newest_arrival_ns = std::numeric_limits<TimeNs>::min();
  std::optional<TimeNs> last_imu_ns;
  std::map<std::string, TimeNs> last_stamp;

  // Inputs (held).
  double accel_x = 0.0;  // body x specific force at the IMU
  double steering = 0.0;
  std::optional<double> encoder_speed;

  // Initialisation: first fix of the course antenna.
  std::optional<std::pair<TimeNs, Vec3>> first_fix;
  Mat3 first_fix_covariance = Mat3::Identity();
  // How far the course antenna has moved from its first fix, and how far it must for a course
  // (WaitingFor()).
  double course_distance_m = 0.0;
  double course_needed_m = 0.0;

  // Filter.
  bool initialized = false;
  TimeNs initialized_ns = 0;  // the latest (re-)initialisation
  TimeNs t_ns = 0;
  VecN x = VecN::Zero();
  MatN P = MatN::Identity();
  double z = 0.0, Pz = 1.0;
  std::map<std::string, TimeNs> last_accepted_gnss_ns, last_accepted_speed_ns,
      last_accepted_heading_ns, last_accepted_velocity_ns;
  std::vector<Pending> pending;  // stamp-sorted
  std::deque<Snapshot> history;
  // Fixes each antenna's gate refused since its last accepted one: when they agree the filter
  // is lost and starts over from the fixes (refused_fix_track.hpp).
  std::map<std::string, RefusedFixTrack> refused_fixes;

  Impl(const EstimatorSensorSetup& s, const EkfOptions& o);

  VerdictObserver verdicts;  // optional (Estimator::SetVerdictObserver)
  void Reject(const std::string& id, TimeNs stamp_ns, RejectReason reason) {
    diag.Verdict(id, stamp_ns, reason, verdicts);
  }
  void Accept(const std::string& id, TimeNs stamp_ns) {
    diag.Verdict(id, stamp_ns, std::nullopt, verdicts);
  }

  // ---- process model -------------------------------------------------------------------------

  // Propagates the filter from t_ns to t_to_ns with the held inputs.
  void Propagate(TimeNs t_to_ns);

  // Joseph-form update of a D-dimensional measurement with innovation y.
  template <int D>
  void Update(const Eigen::Matrix<double, D, 1>& y, const Eigen::Matrix<double, D, kN>& H,
              const Eigen::Matrix<double, D, D>& R) {
    const Eigen::Matrix<double, D, D> S = H * P * H.transpose() + R;
    const Eigen::Matrix<double, kN, D> K = P * H.transpose() * S.inverse();
    const VecN dx = K * y;
    if (!dx.allFinite()) return;
    x += dx;
    x[ekf::kPsi] = so3::WrapAngle(x[ekf::kPsi]);
    const MatN IKH = MatN::Identity() - K * H;
    P = IKH * P * IKH.transpose() + K * R * K.transpose();
    P = 0.5 * (P + P.transpose());
  }

  template <int D>
  double Mahalanobis(const Eigen::Matrix<double, D, 1>& y, const Eigen::Matrix<double, D, kN>& H,
                     const Eigen::Matrix<double, D, D>& R) const {
    const Eigen::Matrix<double, D, D> S = H * P * H.transpose() + R;
    return y.dot(S.ldlt().solve(y));
  }

  // Gate with reopening: true if the measurement passes, or if none of its sensor has been
  // accepted for gate_reset_s (since last_accepted_ns: the last one, or the initialisation).
  bool Gate(double d2, double threshold, TimeNs stamp_ns, TimeNs last_accepted_ns) const {
    if (d2 <= threshold) return true;
    return ToSeconds(stamp_ns - last_accepted_ns) > options.gate_reset_s;
  }

  // ---- measurement updates -------------------------------------------------------------------

  void UpdateGyro(double gz_body);

  void UpdateSpeed(const std::string& id, const SensorInfo& info, const VehicleSpeed& m);

  // Dual-antenna heading: yaw of the baseline = psi + its yaw in the body frame (the
  // vehicle is planar, the baseline's pitch is not used).
  void UpdateHeading(const std::string& id, const SensorInfo& info, const DualAntennaHeading& m);

  // Receiver covariance with the setup's scale and eigenvalue floor.
  static Mat3 AdjustedCovariance(const Mat3& cov, const SensorInfo& info) {
    Eigen::SelfAdjointEigenSolver<Mat3> eig(cov * info.covariance_scale);
    const Vec3 values = eig.eigenvalues().cwiseMax(info.min_sigma_m * info.min_sigma_m);
    return eig.eigenvectors() * values.asDiagonal() * eig.eigenvectors().transpose();
  }

  void UpdateGnss(const std::string& id, const SensorInfo& info, const GnssPositionEnu& fix);
  // The fix's horizontal Doppler velocity of the antenna, R(psi) (vx - r l_y, vy + r l_x), with
  // the reported sigmas; gated like the position (gnss_gate_chi2, own reset clock), counted as
  // the antenna's velocity_updates / velocity_gated events.
  void UpdateGnssVelocity(const std::string& id, const SensorInfo& info,
                          const GnssPositionEnu& fix);

  // The filter no longer matches a consistent track of fixes ("lost"), or the IMU paused too
  // long ("imu_gap"): says so in the diagnostics (the event counted on sensor `id`) and
  // initialises again from the next fixes (no estimate meanwhile).
  void StartOver(const std::string& id, TimeNs stamp_ns, const char* event);

  // ---- initialisation ------------------------------------------------------------------------

  void TryInitialize(const std::string& id, const SensorInfo& info, const GnssPositionEnu& fix);
  // What the initialisation is waiting for, one line (EstimatorDiagnostics::waiting_for).
  std::string WaitingFor() const;

  // ---- bookkeeping ---------------------------------------------------------------------------

  void PushHistory() {
    history.push_back(Snapshot{t_ns, x, P, z, Pz, accel_x, steering});
    const TimeNs keep_from = t_ns - FromSeconds(options.history_s);
    while (history.size() > 1 && history.front().t_ns < keep_from) history.pop_front();
  }

  // Applies a measurement whose stamp is at or before the filter time.
  void Apply(const std::string& id, const SensorInfo& info, const Measurement& m);

  void ReleasePending(TimeNs up_to_ns);

  void AddImu(const std::string& id, const ImuSample& sample);

  std::optional<RejectReason> CheckOther(const Measurement& m) const;

  static bool TypeFits(Role role, const Measurement& m);

  void Add(const Measurement& m);

  // ---- output --------------------------------------------------------------------------------

  std::optional<StateEstimate> StateAt(TimeNs t_out_ns) const;
};

}  // namespace statebench::est
