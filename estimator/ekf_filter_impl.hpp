// Internal to EkfSingleTrackEstimator (not part of the estimator's API): the filter's members and
// the sensor roles it resolves from the setup. Measurement intake, reordering and the output are
// in ekf_single_track.cpp; propagation, the measurement updates and the initialisation from GNSS
// in ekf_measurement_updates.cpp; the odometry updates in ekf_odometry_updates.cpp; the start in
// a local frame (no GNSS antenna) in ekf_local_start.cpp; the vehicle model in
// ekf_single_track_model.hpp.
#pragma once

#include <Eigen/Eigenvalues>
#include <deque>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/so3.hpp"
#include "estimator/doppler_window.hpp"
#include "estimator/ekf_course_start.hpp"
#include "estimator/ekf_single_track.hpp"
#include "estimator/ekf_single_track_model.hpp"
#include "estimator/gnss_enu.hpp"
#include "estimator/imu_still_window.hpp"
#include "estimator/refused_fix_track.hpp"
#include "estimator/state_initializer.hpp"

namespace statebench::est {
namespace ekf {

inline constexpr double kMaxSubstepS = 0.0025;
// IMU samples kept between two zero readings of the odometry (5 s at 100 Hz); more: the odometry
// stopped sending, the standstill test starts again.
inline constexpr std::size_t kMaxStandstillSamples = 500;

// A GNSS antenna, a speed encoder, a steering encoder, a heading or a body-velocity odometry,
// resolved from the setup.
enum class Role { kImu, kGnss, kSpeed, kSteering, kHeading, kBodyVelocity, kUnsupported };

struct SensorInfo {
  Role role = Role::kUnsupported;
  Vec3 p_body_sensor = Vec3::Zero();
  Mat3 R_body_sensor = Mat3::Identity();
  SE3 T_imu_sensor;  // for the local start's odometry
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
  bool has_speed_input = false;  // a speed encoder or a body_velocity sensor
  std::optional<ekf::SingleTrackModel> model;  // once the setup is read
  // Without a GNSS antenna the filter starts in a local frame (ekf_local_start.cpp) from this
  // initialiser (the factor graph's, state_initializer.hpp); its WGS84 output is local_frame,
  // placed at latitude, longitude and height 0 (meaningless: the status says `local`).
  std::optional<StateInitializer> local_start;
  LocalEnuFrame local_frame{GeodeticPoint{0.0, 0.0, 0.0}};
  EstimatorDiagnostics diag;
  std::optional<LocalEnuFrame> frame;
  TimeNs newest_arrival_ns = std::numeric_limits<TimeNs>::min();
  std::optional<TimeNs> last_imu_ns;
  std::map<std::string, TimeNs> last_stamp;

  // Inputs (held).
  double accel_x = 0.0;  // body x specific force at the IMU
  double gyro_z = 0.0;   // body z rate (raw) of the newest IMU sample
  double steering = 0.0;
  std::optional<double> encoder_speed;

  // Initialisation: the course antenna's recent fixes and the IMU's longitudinal force.
  EkfCourseStart course_start;

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

  // Odometry (ekf_odometry_updates.cpp): the measured components of the velocity of a point of
  // the vehicle in a frame fixed to it (ekf_point_velocity.hpp), each with its variance (one of
  // BodyVelocityFrontEnd::kUnmeasuredVariance or more: not measured). Each component is gated on
  // speed_gate_chi2 (1 dof; the sample is refused when one is outside, the gate reopening after
  // gate_reset_s), then the components update the filter one after the other (exact: the model
  // is linear and the components independent).
  void UpdatePointVelocity(const std::string& id, TimeNs stamp_ns, const Mat3& R_body_sensor,
                           const Vec3& p_body_point, const Vec3& measured, const Vec3& variance);
  // Speed encoder: the body-x velocity of its wheel, speed_sigma_mps.
  void UpdateSpeed(const std::string& id, const SensorInfo& info, const VehicleSpeed& m);
  // body_velocity: the measured components of the sensor origin's velocity in the sensor frame
  // with their reported variances (floored at BodyVelocityFrontEnd::kMinSigmaMps); the angular
  // velocity is not used (the gyro measures it), as in the factor graph.
  void UpdateBodyVelocity(const std::string& id, const SensorInfo& info, const BodyVelocity& m);
  // Standstill from the odometry, as the factor graph's zero-rate factor
  // (body_velocity_front_end.hpp): two consecutive samples of a body_velocity sensor reading
  // zero (BodyVelocityReadsZero, ZeroVelocityOptions' max_encoder_speed_mps), the IMU quiet
  // (the factor graph's default still test, low band included, over the rolling window ending
  // with the newer sample or over the span when longer: imu_still_window.hpp) and its mean
  // body-z rate over the span within
  // BodyVelocityFrontEnd::kMaxStillRateRadps of b_g: that mean measures b_g with the sigma
  // gyro_sigma_radps / sqrt(samples). Counted as the sensor's `zero_rate_updates` event.
  // Without an absolute heading it is what keeps b_g, hence the yaw, from drifting.
  void UpdateStandstill(const std::string& id, const BodyVelocity& m);
  std::optional<TimeNs> odometry_zero_since_ns;  // the previous sample read zero, at this stamp
  std::vector<ImuSample> standstill_imu;         // IMU samples after odometry_zero_since_ns
  ImuStillWindow still_imu{ZeroVelocityOptions{}.window_s};  // the newest, for the still test

  // Standstill without a speed input (no encoder, no odometry), as the factor graph's
  // zero-velocity factor with its default options (zero_velocity_evidence.hpp): the IMU quiet
  // over still_imu (low band included), the receiver's Doppler mean near zero (no update without
  // Doppler: the estimated speed's test is not used, ekf_zero_velocity.cpp), and the
  // longitudinal specific force less b_a below max_acceleration_mps2
  // (the planar model's own: a grade's gravity is not separated from b_a, so a stop on a steep
  // grade can fail it); then vx = vy = 0 with the sigma that evidence gives, at rate_hz.
  // Counted as the IMU's `zero_velocity_updates` event.
  void UpdateZeroVelocity(TimeNs t_ns);
  DopplerWindow doppler;  // every Doppler velocity, gated or not
  TimeNs next_zero_velocity_ns = INT64_MIN;

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
  // Local frame (ekf_local_start.cpp): odometry for the initialiser before the start; the IMU
  // sample (gyro_z_body: its body-z rate) that may start it, at its stamp.
  void ResetLocalStart();  // a fresh initialiser (at construction and after StartOver)
  void FeedLocalStart(const std::string& id, const SensorInfo& info, const Measurement& m);
  void TryStartLocal(const ImuSample& sample, double gyro_z_body);
  // The planar state from the initialiser's first state (yaw of the body x axis, the IMU's
  // position and velocity moved to the body origin, the body-z gyro bias).
  void InitializeFrom(const InitialState& first, double gyro_z_body);
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
