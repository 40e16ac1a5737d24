#include "estimator/ekf_single_track.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <numbers>
#include <variant>
#include <vector>

#include "core/error.hpp"
#include "core/so3.hpp"
#include "estimator/gnss_enu.hpp"
#include "estimator/measurement_checks.hpp"

namespace statebench::est {

namespace {

constexpr int kN = 8;
enum : int { kX = 0, kY, kPsi, kVx, kVy, kR, kBg, kBa };
using VecN = Eigen::Matrix<double, kN, 1>;
using MatN = Eigen::Matrix<double, kN, kN>;

constexpr double kMaxSubstepS = 0.0025;
constexpr double kMaxAbsSteeringRad = 1.2;  // beyond any road-wheel angle
constexpr double kMaxAbsSpeedMps = 100.0;

Mat3 Rz(double psi) { return Eigen::AngleAxisd(psi, Vec3::UnitZ()).toRotationMatrix(); }

// A GNSS antenna, a speed encoder, or a steering encoder, resolved from the setup.
enum class Role { kImu, kGnss, kSpeed, kSteering, kHeading, kUnsupported };

struct SensorInfo {
  Role role = Role::kUnsupported;
  Vec3 p_body_sensor = Vec3::Zero();
  double covariance_scale = 1.0;
  double min_sigma_m = 0.0;
  double yaw_offset_rad = 0.0;  // heading: yaw of the antenna baseline in the body frame
};

struct Snapshot {
  TimeNs t_ns = 0;
  VecN x = VecN::Zero();
  MatN P = MatN::Zero();
  double z = 0.0, Pz = 0.0;
  double accel_x = 0.0, steering = 0.0;
};

// A measurement waiting for the IMU to pass its stamp.
struct Pending {
  TimeNs stamp_ns = 0;
  std::string sensor_id;
  Measurement measurement;
};

}  // namespace

struct EkfSingleTrackEstimator::Impl {
  EstimatorSensorSetup setup;
  EkfOptions options;
  Mat3 R_body_imu = Mat3::Identity();
  Vec3 p_body_imu = Vec3::Zero();
  std::map<std::string, SensorInfo> sensors;
  std::string course_antenna;
  bool has_steering = false;  // without a steering encoder r is a random walk, vy relaxes to 0

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

  // Filter.
  bool initialized = false;
  TimeNs t_ns = 0;
  VecN x = VecN::Zero();
  MatN P = MatN::Identity();
  double z = 0.0, Pz = 1.0;
  std::map<std::string, TimeNs> last_accepted_gnss_ns, last_accepted_speed_ns,
      last_accepted_heading_ns;
  std::vector<Pending> pending;  // stamp-sorted
  std::deque<Snapshot> history;

  Impl(const EstimatorSensorSetup& s, const EkfOptions& o) : setup(s), options(o) {
    std::string why;
    if (!options.IsValid(&why)) throw InputError(why);
    R_body_imu = setup.T_body_imu.rotation().toRotationMatrix();
    p_body_imu = setup.T_body_imu.translation();
    for (const EstimatorSensor& sensor : setup.sensors) {
      SensorInfo info;
      info.p_body_sensor = sensor.T_body_sensor.translation();
      switch (sensor.kind) {
        case SensorKind::kImu:
          info.role = sensor.id == setup.imu_id ? Role::kImu : Role::kUnsupported;
          break;
        case SensorKind::kGnss:
          info.role = Role::kGnss;
          if (const GnssAntenna* antenna = setup.FindAntenna(sensor.id)) {
            info.p_body_sensor = setup.T_body_imu.rotation() * antenna->p_imu_antenna +
                                 setup.T_body_imu.translation();
            info.covariance_scale = antenna->covariance_scale;
            info.min_sigma_m = antenna->min_sigma_m;
          }
          if (course_antenna.empty()) course_antenna = sensor.id;
          break;
        case SensorKind::kSpeedEncoder:
          info.role = Role::kSpeed;
          break;
        case SensorKind::kSteeringEncoder:
          info.role = Role::kSteering;
          has_steering = true;
          break;
        default:
          info.role = Role::kUnsupported;
      }
      sensors[sensor.id] = info;
    }
    for (const DualAntennaPair& pair : setup.dual_antennas) {
      if (pair.heading_id.empty()) continue;
      SensorInfo info;
      info.role = Role::kHeading;
      const Vec3 baseline_body = setup.T_body_imu.rotation() * (pair.p_imu_aux - pair.p_imu_main);
      info.yaw_offset_rad = std::atan2(baseline_body.y(), baseline_body.x());
      sensors[pair.heading_id] = info;
    }
    if (course_antenna.empty()) {
      throw InputError(setup.source + ": the ekf estimator needs a GNSS antenna in the setup");
    }
  }

  void Reject(const std::string& id, RejectReason reason) { ++diag.sensors[id].rejected[reason]; }
  void Accept(const std::string& id, TimeNs stamp_ns) { diag.sensors[id].Accept(stamp_ns); }

  // ---- process model -------------------------------------------------------------------------

  VecN Derivative(const VecN& s, double ax, double delta) const {
    const SingleTrackParams& v = options.vehicle;
    const double c = std::cos(s[kPsi]), sn = std::sin(s[kPsi]);
    const double vx = s[kVx], vy = s[kVy], r = s[kR];
    VecN d = VecN::Zero();
    d[kX] = vx * c - vy * sn;
    d[kY] = vx * sn + vy * c;
    d[kPsi] = r;
    d[kVx] = ax - s[kBa] + r * vy + r * r * p_body_imu.x();
    const double lf = v.cg_to_front_axle_m, lr = v.cg_to_rear_axle_m, L = v.Wheelbase();
    const double delta_f = delta, delta_r = -v.rear_steering_ratio * delta;
    // Reversing: kinematic only (the dynamic model's lateral modes are unstable for vx < 0).
    const double w = std::clamp((vx - options.blend_low_speed_mps) /
                                    (options.blend_high_speed_mps - options.blend_low_speed_mps),
                                0.0, 1.0);
    double vy_dot = 0.0, r_dot = 0.0;
    if (!has_steering) {
      d[kVy] = -vy / options.kinematic_time_constant_s;
      d[kR] = 0.0;
      return d;
    }
    if (w > 0.0) {
      const double alpha_f = delta_f - (vy + lf * r) / vx;
      const double alpha_r = delta_r - (vy - lr * r) / vx;
      const double fy_f = v.cornering_stiffness_front_npr * alpha_f;
      const double fy_r = v.cornering_stiffness_rear_npr * alpha_r;
      vy_dot += w * ((fy_f + fy_r) / v.mass_kg - r * vx);
      r_dot += w * ((lf * fy_f - lr * fy_r) / v.yaw_inertia_kgm2);
    }
    if (w < 1.0) {
      const double tf = std::tan(delta_f), tr = std::tan(delta_r);
      const double vy_kin = vx * (lf * tr + lr * tf) / L;
      const double r_kin = vx * (tf - tr) / L;
      const double tau = options.kinematic_time_constant_s;
      vy_dot += (1.0 - w) * (vy_kin - vy) / tau;
      r_dot += (1.0 - w) * (r_kin - r) / tau;
    }
    d[kVy] = vy_dot;
    d[kR] = r_dot;
    return d;
  }

  MatN DerivativeJacobian(const VecN& s, double ax, double delta) const {
    MatN A;
    for (int i = 0; i < kN; ++i) {
      const double h = 1e-6 * std::max(1.0, std::abs(s[i]));
      VecN sp = s, sm = s;
      sp[i] += h;
      sm[i] -= h;
      A.col(i) = (Derivative(sp, ax, delta) - Derivative(sm, ax, delta)) / (2 * h);
    }
    return A;
  }

  // Propagates the filter from t_ns to t_to_ns with the held inputs.
  void Propagate(TimeNs t_to_ns) {
    if (t_to_ns <= t_ns) return;
    const double total = ToSeconds(t_to_ns - t_ns);
    const int steps = std::max(1, static_cast<int>(std::ceil(total / kMaxSubstepS)));
    const double dt = total / steps;
    VecN qc = VecN::Zero();
    qc[kX] = qc[kY] = options.position_density * options.position_density;
    qc[kVx] = options.accel_noise_density * options.accel_noise_density;
    qc[kVy] = options.lateral_model_density * options.lateral_model_density;
    qc[kR] = options.yaw_accel_density * options.yaw_accel_density;
    qc[kBg] = options.gyro_bias_walk * options.gyro_bias_walk;
    qc[kBa] = options.accel_bias_walk * options.accel_bias_walk;
    for (int k = 0; k < steps; ++k) {
      const MatN F = MatN::Identity() + DerivativeJacobian(x, accel_x, steering) * dt;
      const VecN mid = x + 0.5 * dt * Derivative(x, accel_x, steering);
      x += dt * Derivative(mid, accel_x, steering);
      x[kPsi] = so3::WrapAngle(x[kPsi]);
      P = F * P * F.transpose();
      P.diagonal() += qc * dt;
    }
    Pz += options.altitude_density * options.altitude_density * total;
    t_ns = t_to_ns;
  }

  // Joseph-form update of a D-dimensional measurement with innovation y.
  template <int D>
  void Update(const Eigen::Matrix<double, D, 1>& y, const Eigen::Matrix<double, D, kN>& H,
              const Eigen::Matrix<double, D, D>& R) {
    const Eigen::Matrix<double, D, D> S = H * P * H.transpose() + R;
    const Eigen::Matrix<double, kN, D> K = P * H.transpose() * S.inverse();
    const VecN dx = K * y;
    if (!dx.allFinite()) return;
    x += dx;
    x[kPsi] = so3::WrapAngle(x[kPsi]);
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

  void UpdateGyro(double gz_body) {
    Eigen::Matrix<double, 1, kN> H = Eigen::Matrix<double, 1, kN>::Zero();
    H(0, kR) = 1.0;
    H(0, kBg) = 1.0;
    Eigen::Matrix<double, 1, 1> y(gz_body - x[kR] - x[kBg]);
    Eigen::Matrix<double, 1, 1> R(options.gyro_sigma_radps * options.gyro_sigma_radps);
    Update<1>(y, H, R);
  }

  void UpdateSpeed(const std::string& id, const SensorInfo& info, const VehicleSpeed& m) {
    Eigen::Matrix<double, 1, kN> H = Eigen::Matrix<double, 1, kN>::Zero();
    const double ly = info.p_body_sensor.y();
    H(0, kVx) = 1.0;
    H(0, kR) = -ly;
    Eigen::Matrix<double, 1, 1> y(m.speed_mps - (x[kVx] - x[kR] * ly));
    Eigen::Matrix<double, 1, 1> R(options.speed_sigma_mps * options.speed_sigma_mps);
    const auto last = last_accepted_speed_ns.find(id);
    if (!Gate(Mahalanobis<1>(y, H, R), options.speed_gate_chi2, m.header.stamp_ns,
              last == last_accepted_speed_ns.end() ? diag.initialized_at_ns : last->second)) {
      Reject(id, RejectReason::kMahalanobisGate);
      return;
    }
    Update<1>(y, H, R);
    last_accepted_speed_ns[id] = m.header.stamp_ns;
    Accept(id, m.header.stamp_ns);
  }

  // Dual-antenna heading: yaw of the baseline = psi + its yaw in the body frame (the
  // vehicle is planar, the baseline's pitch is not used).
  void UpdateHeading(const std::string& id, const SensorInfo& info, const DualAntennaHeading& m) {
    Eigen::Matrix<double, 1, kN> H = Eigen::Matrix<double, 1, kN>::Zero();
    H(0, kPsi) = 1.0;
    Eigen::Matrix<double, 1, 1> y(so3::WrapAngle(m.yaw_rad - (x[kPsi] + info.yaw_offset_rad) -
                                                 x[kR] * ToSeconds(m.header.stamp_ns - t_ns)));
    Eigen::Matrix<double, 1, 1> R(m.yaw_sigma_rad * m.yaw_sigma_rad);
    const auto last = last_accepted_heading_ns.find(id);
    if (!Gate(Mahalanobis<1>(y, H, R), options.heading_gate_chi2, m.header.stamp_ns,
              last == last_accepted_heading_ns.end() ? diag.initialized_at_ns : last->second)) {
      Reject(id, RejectReason::kMahalanobisGate);
      return;
    }
    Update<1>(y, H, R);
    last_accepted_heading_ns[id] = m.header.stamp_ns;
    Accept(id, m.header.stamp_ns);
  }

  // Receiver covariance with the setup's scale and eigenvalue floor.
  static Mat3 AdjustedCovariance(const Mat3& cov, const SensorInfo& info) {
    Eigen::SelfAdjointEigenSolver<Mat3> eig(cov * info.covariance_scale);
    const Vec3 values = eig.eigenvalues().cwiseMax(info.min_sigma_m * info.min_sigma_m);
    return eig.eigenvectors() * values.asDiagonal() * eig.eigenvectors().transpose();
  }

  void UpdateGnss(const std::string& id, const SensorInfo& info, const GnssPositionEnu& fix) {
    const auto start = std::chrono::steady_clock::now();
    const Mat3 cov = AdjustedCovariance(fix.covariance, info);
    // Lag: the fix is of stamp_ns <= t_ns; carry the prediction back by the current velocity.
    const double lag = ToSeconds(t_ns - fix.header.stamp_ns);
    const double c = std::cos(x[kPsi]), s = std::sin(x[kPsi]);
    const Vec2 l = info.p_body_sensor.head<2>();
    const Vec2 Rl(c * l.x() - s * l.y(), s * l.x() + c * l.y());
    const Vec2 v_world(c * x[kVx] - s * x[kVy] - x[kR] * Rl.y(),
                       s * x[kVx] + c * x[kVy] + x[kR] * Rl.x());
    const Vec2 predicted = Vec2(x[kX], x[kY]) + Rl - v_world * lag;
    Eigen::Matrix<double, 2, kN> H = Eigen::Matrix<double, 2, kN>::Zero();
    H(0, kX) = 1.0;
    H(1, kY) = 1.0;
    H(0, kPsi) = -Rl.y();
    H(1, kPsi) = Rl.x();
    const Vec2 y = fix.p_enu.head<2>() - predicted;
    const Mat2 R = cov.topLeftCorner<2, 2>();
    const auto last = last_accepted_gnss_ns.find(id);
    if (!Gate(Mahalanobis<2>(y, H, R), options.gnss_gate_chi2, fix.header.stamp_ns,
              last == last_accepted_gnss_ns.end() ? diag.initialized_at_ns : last->second)) {
      Reject(id, RejectReason::kMahalanobisGate);
      return;
    }
    Update<2>(y, H, R);
    // Altitude of the body origin (flat vehicle: the lever arm's z is a constant offset).
    const double z_meas = fix.p_enu.z() - info.p_body_sensor.z();
    const double k = Pz / (Pz + cov(2, 2));
    z += k * (z_meas - z);
    Pz *= 1.0 - k;
    last_accepted_gnss_ns[id] = fix.header.stamp_ns;
    Accept(id, fix.header.stamp_ns);
    UpdateDiagnostics u;
    u.t_ns = t_ns;
    u.solve_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    u.iterations = 1;
    u.usable = true;
    u.num_states = 1;
    u.factors["gnss"] = 1;
    diag.updates.push_back(u);
  }

  // ---- initialisation ------------------------------------------------------------------------

  void TryInitialize(const std::string& id, const SensorInfo& info, const GnssPositionEnu& fix) {
    if (id != course_antenna) return;
    if (!first_fix) {
      first_fix = {fix.header.stamp_ns, fix.p_enu};
      first_fix_covariance = fix.covariance;
      return;
    }
    const Vec3 d = fix.p_enu - first_fix->second;
    const double dt = ToSeconds(fix.header.stamp_ns - first_fix->first);
    // The course is the chord between two noisy fixes: its yaw sigma is about
    // sqrt(2) sigma_h / distance; wait until that is below course_max_yaw_sigma_rad.
    const Mat3 cov_first = AdjustedCovariance(first_fix_covariance, info);
    const Mat3 cov_now = AdjustedCovariance(fix.covariance, info);
    const double var_h = std::max(cov_first.topLeftCorner<2, 2>().eigenvalues().real().maxCoeff(),
                                  cov_now.topLeftCorner<2, 2>().eigenvalues().real().maxCoeff());
    const double distance = d.head<2>().norm();
    if (distance < options.course_min_distance_m || dt <= 0.0) return;
    const double course_var = 2.0 * var_h / (distance * distance);
    if (course_var > options.course_max_yaw_sigma_rad * options.course_max_yaw_sigma_rad) return;
    double yaw = std::atan2(d.y(), d.x());
    double speed = d.head<2>().norm() / dt;
    if (encoder_speed) {
      speed = *encoder_speed;
      if (speed < 0.0) yaw = so3::WrapAngle(yaw + std::numbers::pi);
    }
    const Mat3& cov = cov_now;
    const Vec2 Rl = (Rz(yaw) * info.p_body_sensor).head<2>();
    x = VecN::Zero();
    x[kX] = fix.p_enu.x() - Rl.x();
    x[kY] = fix.p_enu.y() - Rl.y();
    x[kPsi] = yaw;
    x[kVx] = speed;
    P = MatN::Zero();
    P.topLeftCorner<2, 2>() = cov.topLeftCorner<2, 2>();
    P(kPsi, kPsi) = options.init_yaw_sigma_rad * options.init_yaw_sigma_rad + course_var;
    // The lever arm moves the yaw uncertainty into the position.
    const Vec2 dpos_dpsi(-Rl.y(), Rl.x());
    P.block<2, 1>(0, kPsi) = -dpos_dpsi * P(kPsi, kPsi);
    P.block<1, 2>(kPsi, 0) = P.block<2, 1>(0, kPsi).transpose();
    P.topLeftCorner<2, 2>() += dpos_dpsi * dpos_dpsi.transpose() * P(kPsi, kPsi);
    P(kVx, kVx) = options.init_speed_sigma_mps * options.init_speed_sigma_mps;
    P(kVy, kVy) = options.init_speed_sigma_mps * options.init_speed_sigma_mps;
    P(kR, kR) = 0.1 * 0.1;
    P(kBg, kBg) = options.init_gyro_bias_sigma_radps * options.init_gyro_bias_sigma_radps;
    P(kBa, kBa) = options.init_accel_bias_sigma_mps2 * options.init_accel_bias_sigma_mps2;
    z = fix.p_enu.z() - info.p_body_sensor.z();
    Pz = cov(2, 2);
    t_ns = fix.header.stamp_ns;
    initialized = true;
    diag.initialized = true;
    diag.initialized_at_ns = t_ns;
    diag.initialization = "moving (gnss course)";
    if (last_imu_ns) {
      Propagate(*last_imu_ns);
      PushHistory();
    }
  }

  // ---- bookkeeping ---------------------------------------------------------------------------

  void PushHistory() {
    history.push_back(Snapshot{t_ns, x, P, z, Pz, accel_x, steering});
    const TimeNs keep_from = t_ns - FromSeconds(options.history_s);
    while (history.size() > 1 && history.front().t_ns < keep_from) history.pop_front();
  }

  // Applies a measurement whose stamp is at or before the filter time.
  void Apply(const std::string& id, const SensorInfo& info, const Measurement& m) {
    if (const auto* fix = std::get_if<GnssFix>(&m)) {
      if (!frame)
        frame.emplace(GeodeticPoint{fix->latitude_deg, fix->longitude_deg, fix->altitude_m});
      std::string why;
      const auto enu = GnssFixToEnu(*fix, *frame, &why);
      if (!enu) {
        Reject(id, RejectReason::kAbsurdValue);
        return;
      }
      const Mat3 cov = AdjustedCovariance(enu->covariance, info);
      if (std::sqrt(std::max(0.0, cov.eigenvalues().real().maxCoeff())) >
          options.gnss_max_sigma_m) {
        Reject(id, RejectReason::kCovarianceThreshold);
        return;
      }
      if (!initialized) {
        TryInitialize(id, info, *enu);
        Accept(id, HeaderOf(m).stamp_ns);
        return;
      }
      UpdateGnss(id, info, *enu);
    } else if (const auto* speed = std::get_if<VehicleSpeed>(&m)) {
      encoder_speed = speed->speed_mps;
      if (!initialized) {
        Accept(id, HeaderOf(m).stamp_ns);
        return;
      }
      UpdateSpeed(id, info, *speed);
    } else if (const auto* heading = std::get_if<DualAntennaHeading>(&m)) {
      if (!initialized) {
        Reject(id, RejectReason::kNotInitialized);
        return;
      }
      if (heading->yaw_sigma_rad > options.heading_max_sigma_rad) {
        Reject(id, RejectReason::kCovarianceThreshold);
        return;
      }
      UpdateHeading(id, info, *heading);
    } else if (const auto* angle = std::get_if<SteeringAngle>(&m)) {
      steering = angle->angle_rad;
      Accept(id, HeaderOf(m).stamp_ns);
    }
  }

  void ReleasePending(TimeNs up_to_ns) {
    std::size_t n = 0;
    while (n < pending.size() && pending[n].stamp_ns <= up_to_ns) {
      const Pending& p = pending[n];
      if (initialized) Propagate(p.stamp_ns);
      Apply(p.sensor_id, sensors[p.sensor_id], p.measurement);
      ++n;
    }
    pending.erase(pending.begin(), pending.begin() + static_cast<std::ptrdiff_t>(n));
  }

  void AddImu(const std::string& id, const ImuSample& sample) {
    if (last_imu_ns && sample.header.stamp_ns <= *last_imu_ns) {
      Reject(id, RejectReason::kStampBackwards);
      return;
    }
    if (const auto reason = CheckImuSample(sample)) {
      Reject(id, *reason);
      return;
    }
    Accept(id, sample.header.stamp_ns);
    const Vec3 gyro_body = R_body_imu * sample.gyro;
    const Vec3 accel_body = R_body_imu * sample.accel;
    accel_x = accel_body.x();
    ReleasePending(sample.header.stamp_ns);
    last_imu_ns = sample.header.stamp_ns;
    if (!initialized) return;
    Propagate(sample.header.stamp_ns);
    UpdateGyro(gyro_body.z());
    PushHistory();
  }

  std::optional<RejectReason> CheckOther(const Measurement& m) const {
    if (const auto* fix = std::get_if<GnssFix>(&m)) return CheckGnssFix(*fix);
    if (const auto* heading = std::get_if<DualAntennaHeading>(&m)) {
      return CheckDualAntennaHeading(*heading);
    }
    if (const auto* speed = std::get_if<VehicleSpeed>(&m)) {
      if (!std::isfinite(speed->speed_mps)) return RejectReason::kNonFinite;
      if (std::abs(speed->speed_mps) > kMaxAbsSpeedMps) return RejectReason::kAbsurdValue;
    }
    if (const auto* angle = std::get_if<SteeringAngle>(&m)) {
      if (!std::isfinite(angle->angle_rad)) return RejectReason::kNonFinite;
      if (std::abs(angle->angle_rad) > kMaxAbsSteeringRad) return RejectReason::kAbsurdValue;
    }
    return std::nullopt;
  }

  static bool TypeFits(Role role, const Measurement& m) {
    switch (role) {
      case Role::kImu:
        return std::holds_alternative<ImuSample>(m);
      case Role::kGnss:
        return std::holds_alternative<GnssFix>(m);
      case Role::kSpeed:
        return std::holds_alternative<VehicleSpeed>(m);
      case Role::kSteering:
        return std::holds_alternative<SteeringAngle>(m);
      case Role::kHeading:
        return std::holds_alternative<DualAntennaHeading>(m);
      case Role::kUnsupported:
        return true;
    }
    return false;
  }

  void Add(const Measurement& m) {
    const MeasurementHeader& header = HeaderOf(m);
    const std::string& id = header.sensor_id;
    ++diag.sensors[id].received;
    const auto it = sensors.find(id);
    if (it == sensors.end() || !TypeFits(it->second.role, m)) {
      Reject(id, RejectReason::kUnknownSensor);
      return;
    }
    const SensorInfo& info = it->second;
    if (info.role == Role::kUnsupported) {
      Reject(id, RejectReason::kUnsupportedSensor);
      return;
    }
    if (header.stamp_ns > header.arrival_ns) {
      Reject(id, RejectReason::kStampInFuture);
      return;
    }
    newest_arrival_ns = std::max(newest_arrival_ns, header.arrival_ns);
    if (info.role == Role::kImu) {
      AddImu(id, std::get<ImuSample>(m));
      return;
    }
    if (const auto reason = CheckOther(m)) {
      Reject(id, *reason);
      return;
    }
    if (const auto last = last_stamp.find(id);
        last != last_stamp.end() && header.stamp_ns <= last->second) {
      Reject(id, RejectReason::kStampBackwards);
      return;
    }
    if (initialized && header.stamp_ns < t_ns - FromSeconds(options.max_delay_s)) {
      Reject(id, RejectReason::kTooOld);
      return;
    }
    last_stamp[id] = header.stamp_ns;
    if (last_imu_ns && header.stamp_ns <= *last_imu_ns) {
      Apply(id, info, m);
      return;
    }
    Pending p{header.stamp_ns, id, m};
    const auto pos = std::upper_bound(pending.begin(), pending.end(), p.stamp_ns,
                                      [](TimeNs t, const Pending& q) { return t < q.stamp_ns; });
    pending.insert(pos, std::move(p));
  }

  // ---- output --------------------------------------------------------------------------------

  StateEstimate Output(const Snapshot& snap, TimeNs t_out_ns) const {
    VecN s = snap.x;
    const double dt = ToSeconds(t_out_ns - snap.t_ns);
    if (dt > 0.0) {
      s += dt * Derivative(s, snap.accel_x, snap.steering);
      s[kPsi] = so3::WrapAngle(s[kPsi]);
    }
    const Mat3 R_world_body = Rz(s[kPsi]);
    const Mat3 R_world_imu = R_world_body * R_body_imu;
    const Vec3 omega_body(0.0, 0.0, s[kR]);
    const Vec3 v_body = Vec3(s[kVx], s[kVy], 0.0) + omega_body.cross(p_body_imu);
    StateEstimate out;
    NavState& n = out.state;
    n.t_ns = t_out_ns;
    n.q_world_imu = Quat(R_world_imu).normalized();
    const Vec3 lever_world = R_world_body * p_body_imu;
    n.p_world = Vec3(s[kX], s[kY], snap.z) + lever_world;
    n.v_world = R_world_body * v_body;
    const Mat3 R_imu_body = R_body_imu.transpose();
    n.gyro_bias = R_imu_body * Vec3(0.0, 0.0, s[kBg]);
    n.accel_bias = R_imu_body * Vec3(s[kBa], 0.0, 0.0);

    // Error vector e (16): [8 filter states, z, roll_w, pitch_w, vz, bg_x, bg_y, ba_y, ba_z]
    // (small world-frame tilts, body-frame bias components), mapped to the 15x15 ordering.
    constexpr int kE = 16;
    Eigen::Matrix<double, kE, 1> variances;
    const double rp = options.roll_pitch_sigma_rad * options.roll_pitch_sigma_rad;
    const double vz = options.vertical_velocity_sigma_mps * options.vertical_velocity_sigma_mps;
    const double bg = options.init_gyro_bias_sigma_radps * options.init_gyro_bias_sigma_radps;
    const double ba = options.init_accel_bias_sigma_mps2 * options.init_accel_bias_sigma_mps2;
    variances << VecN::Zero(), snap.Pz, rp, rp, vz, bg, bg, ba, ba;
    Eigen::Matrix<double, kE, kE> C = variances.asDiagonal();
    C.topLeftCorner<kN, kN>() = snap.P;
    Eigen::Matrix<double, 15, kE> J = Eigen::Matrix<double, 15, kE>::Zero();
    // World tilt columns (roll_w, pitch_w, psi) for rotation, position and velocity.
    const int tilt[3] = {9, 10, kPsi};
    const Mat3 R_imu_world = R_world_imu.transpose();
    const Mat3 dpos_dtilt = -so3::Hat<double>(lever_world);
    const Mat3 dvel_dtilt = -so3::Hat<double>(n.v_world);
    for (int i = 0; i < 3; ++i) {
      J.block<3, 1>(kRotationIndex, tilt[i]) = R_imu_world.col(i);
      J.block<3, 1>(kPositionIndex, tilt[i]) = dpos_dtilt.col(i);
      J.block<3, 1>(kVelocityIndex, tilt[i]) = dvel_dtilt.col(i);
    }
    J(kPositionIndex + 0, kX) = 1.0;
    J(kPositionIndex + 1, kY) = 1.0;
    J(kPositionIndex + 2, 8) = 1.0;
    J.block<3, 1>(kVelocityIndex, kVx) = R_world_body.col(0);
    J.block<3, 1>(kVelocityIndex, kVy) = R_world_body.col(1);
    J.block<3, 1>(kVelocityIndex, kR) = R_world_body * Vec3::UnitZ().cross(p_body_imu);
    J(kVelocityIndex + 2, 11) = 1.0;
    J.block<3, 1>(kGyroBiasIndex, 12) = R_imu_body.col(0);
    J.block<3, 1>(kGyroBiasIndex, 13) = R_imu_body.col(1);
    J.block<3, 1>(kGyroBiasIndex, kBg) = R_imu_body.col(2);
    J.block<3, 1>(kAccelBiasIndex, kBa) = R_imu_body.col(0);
    J.block<3, 1>(kAccelBiasIndex, 14) = R_imu_body.col(1);
    J.block<3, 1>(kAccelBiasIndex, 15) = R_imu_body.col(2);
    const Mat15 cov = J * C * J.transpose();
    out.covariance = 0.5 * (cov + cov.transpose());
    if (frame) {
      const GeodeticPoint g = frame->ToGeodetic(n.p_world);
      out.latitude_deg = g.latitude_deg;
      out.longitude_deg = g.longitude_deg;
      out.altitude_m = g.altitude_m;
    }
    return out;
  }

  std::optional<StateEstimate> StateAt(TimeNs t_out_ns) const {
    if (!initialized || history.empty() || !last_imu_ns || t_out_ns > *last_imu_ns) {
      return std::nullopt;
    }
    if (t_out_ns < history.front().t_ns) return std::nullopt;
    // Newest snapshot at or before t.
    auto it = std::upper_bound(history.begin(), history.end(), t_out_ns,
                               [](TimeNs t, const Snapshot& s) { return t < s.t_ns; });
    --it;
    StateEstimate out = Output(*it, t_out_ns);
    if (!out.state.p_world.allFinite() || !out.covariance.allFinite()) return std::nullopt;
    return out;
  }
};

EkfSingleTrackEstimator::EkfSingleTrackEstimator(const EstimatorSensorSetup& setup,
                                                 const EkfOptions& options)
    : impl_(std::make_unique<Impl>(setup, options)) {}

EkfSingleTrackEstimator::~EkfSingleTrackEstimator() = default;

void EkfSingleTrackEstimator::Add(const Measurement& measurement) { impl_->Add(measurement); }

std::optional<StateEstimate> EkfSingleTrackEstimator::StateAt(TimeNs t_ns) const {
  return impl_->StateAt(t_ns);
}

EstimatorDiagnostics EkfSingleTrackEstimator::diagnostics() const { return impl_->diag; }

std::optional<GeodeticPoint> EkfSingleTrackEstimator::origin() const {
  if (!impl_->frame) return std::nullopt;
  return impl_->frame->origin();
}

}  // namespace statebench::est
