#include "estimator/factor_graph_estimator.hpp"

#include <algorithm>
#include <chrono>
#include <deque>
#include <map>
#include <set>
#include <span>

#include "core/error.hpp"
#include "core/so3.hpp"
#include "estimator/encoder_scale_calibration.hpp"
#include "estimator/gnss_enu.hpp"
#include "estimator/gnss_stamp_group.hpp"
#include "estimator/imu_propagation.hpp"
#include "estimator/imu_rate_output.hpp"
#include "estimator/kinematic_odometry.hpp"
#include "estimator/lidar_odometry.hpp"
#include "estimator/lidar_scan_merger.hpp"
#include "estimator/measurement_checks.hpp"
#include "estimator/measurement_gate.hpp"
#include "estimator/reorder_buffer.hpp"
#include "estimator/sliding_window_smoother.hpp"
#include "estimator/state_initializer.hpp"

namespace statebench::est {
namespace {

constexpr TimeNs kMaxFutureNs = 2 * kNsPerSecond;  // stamp ahead of the newest IMU sample
// A measurement is taken before it arrives: a stamp later than the newest arrival stamp seen
// (plus a clock tolerance) is bogus. A bogus IMU stamp would otherwise make every later sample
// look like it goes backwards.
constexpr TimeNs kArrivalToleranceNs = 100 * kNsPerMillisecond;
constexpr std::size_t kStampsKeptPerSensor = 64;  // for repeated-stamp detection

SlidingWindowOptions SmootherOptions(const EstimatorSensorSetup& setup,
                                     const FactorGraphOptions& o) {
  SlidingWindowOptions s;
  s.window_s = o.window_s;
  s.imu_samples_per_state = o.imu_samples_per_state;
  s.imu_noise = setup.imu_noise.value_or(o.imu_noise);
  s.gnss_kernel = o.gnss.kernel;
  s.heading_kernel = o.heading.kernel;
  s.max_iterations = o.max_iterations;
  s.num_threads = o.num_threads;
  return s;
}

// Which factors the setup and the options give; InputError when an option requires a sensor
// the setup does not have.
struct FactorPlan {
  std::vector<const EstimatorSensor*> lidars;  // used lidars, setup order
  const EstimatorSensor* speed = nullptr;       // speed encoder (zero velocity, kinematic)
  const EstimatorSensor* steering = nullptr;
  bool kinematic = false;
  double wheelbase_m = 0.0;
  // Rear-axle frame (the speed encoder's mount, else the body frame) in the IMU frame: the
  // point and axes of the non-holonomic constraint.
  SE3 T_imu_axle;
};

FactorPlan PlanFactors(const EstimatorSensorSetup& setup, const FactorGraphOptions& o) {
  FactorPlan plan;
  for (const EstimatorSensor& s : setup.sensors) {
    if (s.kind == SensorKind::kLidar) plan.lidars.push_back(&s);
    if (s.kind == SensorKind::kSpeedEncoder && plan.speed == nullptr) plan.speed = &s;
    if (s.kind == SensorKind::kSteeringEncoder && plan.steering == nullptr) plan.steering = &s;
  }
  const std::string where = "factor graph options for sensor setup '" +
                            (setup.name.empty() ? setup.source : setup.name) + "': ";
  if (o.lidar.use == FactorUse::kOn && plan.lidars.empty()) {
    throw InputError(where + "lidar.enabled is true but the setup has no lidar");
  }
  if (o.lidar.use == FactorUse::kOff) plan.lidars.clear();
  const bool has_encoders = plan.speed != nullptr && plan.steering != nullptr;
  if (o.kinematic.use == FactorUse::kOn && !has_encoders) {
    throw InputError(where + "kinematic.enabled is true but the setup lacks a " +
                     (plan.speed == nullptr ? "speed_encoder" : "steering_encoder"));
  }
  plan.kinematic = has_encoders && o.kinematic.use != FactorUse::kOff;
  if (plan.kinematic) {
    plan.wheelbase_m =
        plan.steering->T_body_sensor.translation().x() - plan.speed->T_body_sensor.translation().x();
    if (plan.wheelbase_m < 0.1) {
      throw InputError(where + "the kinematic factor needs the steering encoder (front axle) at "
                       "least 0.1 m ahead of the speed encoder (rear axle) along body x; got " +
                       std::to_string(plan.wheelbase_m) + " m");
    }
  }
  plan.T_imu_axle = plan.speed != nullptr ? plan.speed->T_imu_sensor : setup.T_body_imu.Inverse();
  return plan;
}

// A measurement in the smoother, kept until it leaves the window to check its final residual
// against the robust kernel's scale.
struct Accepted {
  TimeNs stamp_ns = 0;
  std::string sensor_id;
  bool is_heading = false;
  GnssPositionEnu fix;
  Vec3 p_imu_antenna = Vec3::Zero();
  DualAntennaHeading heading;
  Vec3 baseline_imu = Vec3::Zero();
};

// Last time a measurement of a kind passed the gate, for the gate's reset.
struct GateState {
  TimeNs last_accepted_ns = INT64_MIN;
  bool rejected_since = false;
};

}  // namespace

struct FactorGraphEstimator::Impl {
  Impl(const EstimatorSensorSetup& s, const FactorGraphOptions& o)
      : setup(s),
        options(o),
        noise(s.imu_noise.value_or(o.imu_noise)),
        smoother(SmootherOptions(s, o)),
        initializer(o.initialization, noise,
                    setup.T_body_imu.rotation().conjugate() * Vec3::UnitX()),
        output(noise),
        latency_ns(FromSeconds(o.ReorderLatency(s))),
        plan(PlanFactors(setup, o)) {
    if (o.origin) frame.emplace(*o.origin);
    if (plan.kinematic) {
      kinematic.emplace(o.kinematic, plan.wheelbase_m);
      encoder_scale.emplace(plan.T_imu_axle);
    }
    if (!plan.lidars.empty()) lidar_odometry.emplace(o.lidar.odometry);
    if (plan.lidars.size() > 1) {
      // Several lidars: one merged scan per period in the first lidar's frame.
      std::vector<LidarMount> mounts;
      const SE3 T_ref_imu = plan.lidars.front()->T_imu_sensor.Inverse();
      for (const EstimatorSensor* l : plan.lidars) {
        mounts.push_back({l->id, T_ref_imu * l->T_imu_sensor});
      }
      LidarScanMergerOptions merge;
      merge.merged_id = plan.lidars.front()->id;
      lidar_merger.emplace(std::move(mounts), merge);
    }
  }

  EstimatorSensorSetup setup;
  FactorGraphOptions options;
  ImuNoise noise;
  SlidingWindowSmoother smoother;
  StateInitializer initializer;
  ImuRateOutput output;
  ReorderBuffer reorder;
  TimeNs latency_ns;
  std::optional<LocalEnuFrame> frame;
  EstimatorDiagnostics diag;

  TimeNs newest_imu_ns = INT64_MIN;
  TimeNs newest_arrival_ns = INT64_MIN;  // arrival stamps given (> 0) so far
  std::map<std::string, std::set<TimeNs>> seen_stamps;
  bool initialized = false;
  TimeNs lagged_ns = INT64_MIN;  // newest IMU stamp released to the smoother
  TimeNs next_solve_ns = 0;
  std::deque<Accepted> accepted;   // in the smoother, oldest first
  std::vector<NavState> smoothed;  // left the window, not taken yet
  GateState gnss_gate, heading_gate;

  FactorPlan plan;
  std::optional<KinematicOdometry> kinematic;
  std::optional<EncoderScaleCalibration> encoder_scale;
  TimeNs last_kinematic_ns = INT64_MIN;  // t2 of the newest kinematic factor
  std::optional<std::pair<TimeNs, double>> last_speed;
  std::deque<ImuSample> recent_imu;  // released samples over the zero-velocity window
  TimeNs next_nhc_ns = INT64_MIN;
  TimeNs next_zupt_ns = INT64_MIN;
  std::optional<LidarOdometry> lidar_odometry;
  std::optional<LidarScanMerger> lidar_merger;  // with more than one lidar
  std::deque<LidarScan> lidar_waiting;  // released scans whose sweep the IMU has not covered
  std::optional<TimeNs> last_scan_ns;    // stamp of the newest accepted scan

  SensorCounters& Counters(const std::string& id) { return diag.sensors[id]; }
  void Reject(const std::string& id, RejectReason reason) { ++Counters(id).rejected[reason]; }

  // ---- 1. Arrival -------------------------------------------------------------------------

  void AddImu(const ImuSample& s) {
    const std::string& id = s.header.sensor_id;
    if (id != setup.imu_id) return Reject(id, RejectReason::kUnknownSensor);
    if (const auto why = CheckImuSample(s)) return Reject(id, *why);
    if (s.header.stamp_ns <= newest_imu_ns) return Reject(id, RejectReason::kStampBackwards);
    if (AfterArrival(s.header)) return Reject(id, RejectReason::kStampInFuture);
    Accept(id, s.header.stamp_ns);
    newest_imu_ns = s.header.stamp_ns;
    output.AddImu(s);
    reorder.Push(s);
    ReleaseUpTo(s.header.stamp_ns - latency_ns);
  }

  // Only when the stream carries arrival stamps (a reader that has none leaves them 0).
  bool AfterArrival(const MeasurementHeader& h) const {
    return newest_arrival_ns > 0 && h.stamp_ns > newest_arrival_ns + kArrivalToleranceNs;
  }

  // Common arrival checks of GNSS fixes and headings; true if the measurement may go on.
  bool CheckStamp(const MeasurementHeader& h) {
    if (AfterArrival(h)) {
      Reject(h.sensor_id, RejectReason::kStampInFuture);
      return false;
    }
    if (newest_imu_ns != INT64_MIN && h.stamp_ns > newest_imu_ns + kMaxFutureNs) {
      Reject(h.sensor_id, RejectReason::kStampInFuture);
      return false;
    }
    std::set<TimeNs>& seen = seen_stamps[h.sensor_id];
    if (!seen.insert(h.stamp_ns).second) {
      Reject(h.sensor_id, RejectReason::kStampBackwards);  // a repeated stamp
      return false;
    }
    if (seen.size() > kStampsKeptPerSensor) seen.erase(seen.begin());
    return true;
  }

  template <typename M>
  void AddOther(const M& m, bool known, std::optional<RejectReason> (*check)(const M&)) {
    const std::string& id = m.header.sensor_id;
    if (!known) return Reject(id, RejectReason::kUnknownSensor);
    if (const auto why = check(m)) return Reject(id, *why);
    if (!CheckStamp(m.header)) return;
    if (m.header.stamp_ns <= reorder.watermark_ns()) {
      ProcessLate(Measurement(m));  // later than the reorder latency: no order guarantee
    } else {
      reorder.Push(m);
    }
  }

  void Add(const Measurement& m) {
    const MeasurementHeader& h = HeaderOf(m);
    ++Counters(h.sensor_id).received;
    if (h.arrival_ns > 0) newest_arrival_ns = std::max(newest_arrival_ns, h.arrival_ns);
    if (const auto* s = std::get_if<ImuSample>(&m)) return AddImu(*s);
    if (const auto* f = std::get_if<GnssFix>(&m)) {
      return AddOther(*f, setup.FindAntenna(h.sensor_id) != nullptr, &CheckGnssFix);
    }
    if (const auto* d = std::get_if<DualAntennaHeading>(&m)) {
      return AddOther(*d, setup.FindHeading(h.sensor_id) != nullptr, &CheckDualAntennaHeading);
    }
    if (const auto* v = std::get_if<VehicleSpeed>(&m)) {
      return AddOther(*v, IsSensor(h.sensor_id, SensorKind::kSpeedEncoder), &CheckVehicleSpeed);
    }
    if (const auto* a = std::get_if<SteeringAngle>(&m)) {
      return AddOther(*a, IsSensor(h.sensor_id, SensorKind::kSteeringEncoder),
                      &CheckSteeringAngle);
    }
    if (const auto* l = std::get_if<LidarScan>(&m)) {
      return AddOther(*l, IsSensor(h.sensor_id, SensorKind::kLidar), &CheckLidarScan);
    }
    Reject(h.sensor_id, setup.Find(h.sensor_id) != nullptr ? RejectReason::kUnsupportedSensor
                                                           : RejectReason::kUnknownSensor);
  }

  bool IsSensor(const std::string& id, SensorKind kind) const {
    const EstimatorSensor* s = setup.Find(id);
    return s != nullptr && s->kind == kind;
  }

  // ---- 2. Release in stamp order ----------------------------------------------------------

  void ReleaseUpTo(TimeNs watermark_ns) {
    std::vector<Measurement> released = reorder.Release(watermark_ns);
    std::vector<Measurement> group;  // non-IMU measurements of one stamp
    const auto flush = [&] {
      if (!group.empty()) ProcessGroup(group);
      group.clear();
    };
    for (Measurement& m : released) {
      if (const auto* s = std::get_if<ImuSample>(&m)) {
        flush();
        ProcessImu(*s);
      } else {
        if (!group.empty() && HeaderOf(group.front()).stamp_ns != HeaderOf(m).stamp_ns) flush();
        group.push_back(std::move(m));
      }
    }
    flush();
    ProcessWaitingScans();
    if (initialized && lagged_ns >= next_solve_ns) Solve();
  }

  void ProcessLate(const Measurement& m) {
    if (!initialized) return Reject(HeaderOf(m).sensor_id, RejectReason::kNotInitialized);
    ProcessGroup({m});
  }

  // ---- 3. Initialisation -------------------------------------------------------------------

  void ProcessImu(const ImuSample& s) {
    smoother.AddImu(s);
    lagged_ns = s.header.stamp_ns;
    recent_imu.push_back(s);
    while (s.header.stamp_ns - recent_imu.front().header.stamp_ns >
           FromSeconds(options.zero_velocity.window_s)) {
      recent_imu.pop_front();
    }
    if (initialized) return AddMotionConstraints(s);
    initializer.AddImu(s);
    std::optional<InitialState> init = initializer.TryInitialize();
    if (!init) return;
    VelocityFromEncoder(s, &*init);
    const NavState& x = init->state;
    if (!x.q_world_imu.coeffs().allFinite() || !x.p_world.allFinite() || !x.v_world.allFinite() ||
        !init->covariance.allFinite()) {
      return;  // a degenerate geometry (e.g. fixes on one spot): wait for more data
    }
    try {
      smoother.Initialize(init->state, init->covariance);
    } catch (const InputError&) {
      return;  // covariance not positive definite: same
    }
    initialized = true;
    diag.initialized = true;
    diag.initialized_at_ns = init->state.t_ns;
    diag.initialization = init->method;
    output.SetAnchor(PropagatedState{init->state, init->covariance});
    next_solve_ns = init->state.t_ns + FromSeconds(options.solve_interval_s);
    gnss_gate.last_accepted_ns = heading_gate.last_accepted_ns = init->state.t_ns;
  }

  // A moving initialisation takes the velocity from GNSS fixes differenced over a second or
  // so (metres per second of error with single-point fixes). With a speed encoder the velocity
  // in the IMU frame is known to centimetres per second: v_imu = R_imu_axle (V, 0, 0) -
  // (w - b_g) x p_imu_axle, and v_world = R v_imu. Its world-frame covariance follows the
  // orientation's: dv = -R [v_imu]x dtheta (right perturbation) plus the encoder's own error.
  void VelocityFromEncoder(const ImuSample& s, InitialState* init) const {
    if (plan.speed == nullptr || !last_speed ||
        std::abs(ToSeconds(s.header.stamp_ns - last_speed->first)) > 0.1) {
      return;
    }
    constexpr double kEncoderSigmaMps = 0.1;  // before the radius is calibrated, and slip
    const NavState& x = init->state;
    const Vec3 omega = s.gyro - x.gyro_bias;
    const Vec3 v_imu = plan.T_imu_axle.rotation() * Vec3(last_speed->second, 0.0, 0.0) -
                       omega.cross(plan.T_imu_axle.translation());
    const Mat3 R = x.q_world_imu.toRotationMatrix();
    const Mat3 J = -R * so3::Hat<double>(v_imu);
    Mat15& P = init->covariance;
    const Mat3 P_rot = P.block<3, 3>(0, 0);
    P.block<3, 15>(6, 0).setZero();
    P.block<15, 3>(0, 6).setZero();
    P.block<3, 3>(6, 6) = J * P_rot * J.transpose() + kEncoderSigmaMps * kEncoderSigmaMps * Mat3::Identity();
    P.block<3, 3>(6, 0) = J * P_rot;
    P.block<3, 3>(0, 6) = P.block<3, 3>(6, 0).transpose();
    init->state.v_world = R * v_imu;
    init->method += " + encoder speed";
  }

  // ---- 4. GNSS and headings ----------------------------------------------------------------

  // The fix in ENU with the antenna's covariance overrides; nullopt (counted) if the covariance
  // threshold discards it. The first fix that passes sets the origin if the options give none.
  std::optional<GnssPositionEnu> ToEnu(const GnssFix& fix) {
    GnssFix adjusted = fix;
    adjusted.covariance_enu =
        AntennaCovariance(*setup.FindAntenna(fix.header.sensor_id), fix.covariance_enu);
    if (LargestSigma(adjusted.covariance_enu) > options.gnss.max_sigma) {
      Reject(fix.header.sensor_id, RejectReason::kCovarianceThreshold);
      return std::nullopt;
    }
    if (!frame) frame.emplace(GeodeticPoint{fix.latitude_deg, fix.longitude_deg, fix.altitude_m});
    std::optional<GnssPositionEnu> enu = GnssFixToEnu(adjusted, *frame);
    if (!enu) Reject(fix.header.sensor_id, RejectReason::kInvalidCovariance);
    return enu;
  }

  void ProcessGroup(const std::vector<Measurement>& group) {
    // Steering before speed: the speed sample closing an interval uses the steering of its stamp.
    for (const Measurement& m : group) {
      if (const auto* a = std::get_if<SteeringAngle>(&m)) ProcessSteering(*a);
    }
    for (const Measurement& m : group) {
      if (const auto* v = std::get_if<VehicleSpeed>(&m)) ProcessSpeed(*v);
      if (const auto* l = std::get_if<LidarScan>(&m)) ProcessLidar(*l);
    }
    std::map<std::string, GnssPositionEnu> fixes;        // by antenna id
    std::map<std::string, DualAntennaHeading> headings;  // by heading id
    for (const Measurement& m : group) {
      if (const auto* f = std::get_if<GnssFix>(&m)) {
        if (auto enu = ToEnu(*f)) fixes[f->header.sensor_id] = *enu;
      } else if (const auto* h = std::get_if<DualAntennaHeading>(&m)) {
        if (h->yaw_sigma_rad > options.heading.max_sigma) {
          Reject(h->header.sensor_id, RejectReason::kCovarianceThreshold);
        } else {
          headings[h->header.sensor_id] = *h;
        }
      }
    }
    const StampGroup inputs = GroupStamp(fixes, headings, setup);
    const TimeNs t_group = HeaderOf(group.front()).stamp_ns;
    for (const std::string& id : inputs.merged) Accept(id, t_group);  // via the heading
    for (const PositionInput& p : inputs.positions) AddPosition(p);
    for (const HeadingInput& h : inputs.headings) AddHeading(h);
  }

  bool PassesGate(const MeasurementGateOptions& gate, GateState& state, TimeNs t_ns,
                  double mahalanobis_squared) {
    if (mahalanobis_squared <= gate.gate_chi2) return true;
    const bool reset = state.rejected_since && state.last_accepted_ns != INT64_MIN &&
                       t_ns - state.last_accepted_ns > FromSeconds(gate.gate_reset_s);
    state.rejected_since = !reset;
    return reset;
  }

  void AddPosition(const PositionInput& in) {
    const GnssPositionEnu& fix = in.fix;
    const std::string& id = fix.header.sensor_id;
    const Vec3& lever = in.p_imu_antenna;
    if (!initialized) {
      Accept(id, fix.header.stamp_ns);
      return initializer.AddPosition(fix, lever);
    }
    if (const auto predicted = PredictAt(fix.header.stamp_ns)) {
      const double d2 = GnssMahalanobisSquared(*predicted, lever, fix.p_enu, fix.covariance);
      if (!PassesGate(options.gnss, gnss_gate, fix.header.stamp_ns, d2)) {
        return Reject(id, RejectReason::kMahalanobisGate);
      }
    }
    if (smoother.AddGnss(fix, lever) == AddResult::kTooOld) {
      return Reject(id, RejectReason::kTooOld);
    }
    gnss_gate = {std::max(gnss_gate.last_accepted_ns, fix.header.stamp_ns), false};
    Accept(id, fix.header.stamp_ns);
    Accepted a;
    a.stamp_ns = fix.header.stamp_ns;
    a.sensor_id = id;
    a.fix = fix;
    a.p_imu_antenna = lever;
    accepted.push_back(a);
  }

  void AddHeading(const HeadingInput& in) {
    const std::string& id = in.counter_id;
    const TimeNs t = in.heading.header.stamp_ns;
    // A heading paired from fixes on one spot has no direction (NaN).
    if (const auto why = CheckDualAntennaHeading(in.heading)) return Reject(id, *why);
    if (!initialized) {
      Accept(id, t);
      return initializer.AddHeading(in.heading, in.baseline_imu);
    }
    if (const auto predicted = PredictAt(t)) {
      const double d2 = HeadingMahalanobisSquared(*predicted, in.baseline_imu, in.heading);
      if (!PassesGate(options.heading, heading_gate, t, d2)) {
        return Reject(id, RejectReason::kMahalanobisGate);
      }
    }
    const Vec3 main = Vec3::Zero();  // the factor only uses the baseline direction
    try {
      if (smoother.AddDualAntenna(in.heading, main, in.baseline_imu) == AddResult::kTooOld) {
        return Reject(id, RejectReason::kTooOld);
      }
    } catch (const InputError&) {
      return Reject(id, RejectReason::kAbsurdValue);  // e.g. a vertical baseline
    }
    heading_gate = {std::max(heading_gate.last_accepted_ns, t), false};
    Accept(id, t);
    Accepted a;
    a.stamp_ns = t;
    a.sensor_id = id;
    a.is_heading = true;
    a.heading = in.heading;
    a.baseline_imu = in.baseline_imu;
    accepted.push_back(a);
  }

  // ---- 4b. Encoders: kinematic factor ----------------------------------------------------

  void ProcessSteering(const SteeringAngle& a) {
    const std::string& id = a.header.sensor_id;
    if (!kinematic || plan.steering == nullptr || id != plan.steering->id) {
      return Reject(id, RejectReason::kDisabled);
    }
    kinematic->AddSteering(a.header.stamp_ns, a.angle_rad);
    Accept(id, a.header.stamp_ns);
  }

  void ProcessSpeed(const VehicleSpeed& v) {
    const std::string& id = v.header.sensor_id;
    if (plan.speed == nullptr || id != plan.speed->id) return Reject(id, RejectReason::kDisabled);
    last_speed = {v.header.stamp_ns, v.speed_mps};
    if (encoder_scale) encoder_scale->AddSpeed(v.header.stamp_ns, v.speed_mps);
    if (!kinematic) {
      // Still used to detect standstill for the zero-velocity factor.
      if (options.zero_velocity.enabled) return Accept(id, v.header.stamp_ns);
      return Reject(id, RejectReason::kDisabled);
    }
    if (!initialized) {
      kinematic->AddSpeed(v.header.stamp_ns, v.speed_mps);  // keeps the integration going
      return Reject(id, RejectReason::kNotInitialized);
    }
    const std::optional<KinematicMotion> motion = kinematic->AddSpeed(v.header.stamp_ns,
                                                                      v.speed_mps);
    Accept(id, v.header.stamp_ns);
    if (!motion) return;
    RelativePoseMeasurement m;
    m.T_s1_s2 = motion->T_r1_r2;
    m.T_imu_sensor = plan.T_imu_axle;
    m.sqrt_information = motion->sqrt_information;
    RobustKernel kernel;  // Huber at 3 sigma: wheel slip
    if (smoother.AddRelativePose(motion->t1_ns, motion->t2_ns, m, kernel) == AddResult::kTooOld) {
      ++Counters(id).events["kinematic_factor_too_old"];
      return;
    }
    last_kinematic_ns = motion->t2_ns;
    ++Counters(id).events["kinematic_factors"];
  }

  void Accept(const std::string& id, TimeNs t_ns) { Counters(id).Accept(t_ns); }

  // ---- 4c. Motion constraints ---------------------------------------------------------------

  bool KinematicActive(TimeNs t_ns) const {
    return kinematic && last_kinematic_ns != INT64_MIN &&
           t_ns - last_kinematic_ns < FromSeconds(0.5);
  }

  void AddMotionConstraints(const ImuSample& s) {
    const TimeNs t = s.header.stamp_ns;
    const NonHolonomicOptions& nhc = options.non_holonomic;
    if (nhc.enabled && t >= next_nhc_ns && !KinematicActive(t)) {
      next_nhc_ns = t + FromSeconds(1.0 / nhc.rate_hz);
      BodyVelocityMeasurement m;
      m.p_imu_point = plan.T_imu_axle.translation();
      m.q_imu_frame = plan.T_imu_axle.rotation();
      // Side slip grows with the lateral acceleration v * omega.
      double speed = 0.0;
      if (const auto p = PredictAt(t)) speed = p->state.v_world.norm();
      const double yaw_rate = (plan.T_imu_axle.rotation().conjugate() * s.gyro).z();
      const double lateral_sigma =
          nhc.lateral_sigma_mps + nhc.slip_per_lateral_accel * speed * speed * std::abs(yaw_rate);
      m.sqrt_information =
          Vec3(0.0, 1.0 / lateral_sigma, 1.0 / nhc.vertical_sigma_mps).asDiagonal();
      if (smoother.AddBodyVelocity(t, m, RobustKernel{}) != AddResult::kTooOld) {
        ++Counters(setup.imu_id).events["non_holonomic_factors"];
      }
    }
    const ZeroVelocityOptions& z = options.zero_velocity;
    if (z.enabled && t >= next_zupt_ns && StandingStill(t)) {
      next_zupt_ns = t + FromSeconds(1.0 / z.rate_hz);
      BodyVelocityMeasurement m;
      m.sqrt_information = Mat3::Identity() / z.sigma_mps;
      if (smoother.AddBodyVelocity(t, m, RobustKernel{}) != AddResult::kTooOld) {
        ++Counters(setup.imu_id).events["zero_velocity_factors"];
      }
    }
  }

  // The IMU is quiet over the window and the speed encoder reads zero (or, without one, the
  // estimated speed is low).
  bool StandingStill(TimeNs t_ns) const {
    const ZeroVelocityOptions& z = options.zero_velocity;
    if (recent_imu.size() < 3 ||
        t_ns - recent_imu.front().header.stamp_ns < FromSeconds(0.9 * z.window_s)) {
      return false;
    }
    Vec3 mean_g = Vec3::Zero(), mean_a = Vec3::Zero();
    for (const ImuSample& s : recent_imu) {
      mean_g += s.gyro;
      mean_a += s.accel;
    }
    const double n = static_cast<double>(recent_imu.size());
    mean_g /= n;
    mean_a /= n;
    Vec3 var_g = Vec3::Zero(), var_a = Vec3::Zero();
    for (const ImuSample& s : recent_imu) {
      var_g += (s.gyro - mean_g).cwiseAbs2();
      var_a += (s.accel - mean_a).cwiseAbs2();
    }
    if ((var_g / (n - 1)).cwiseSqrt().maxCoeff() > z.max_gyro_std_radps) return false;
    if ((var_a / (n - 1)).cwiseSqrt().maxCoeff() > z.max_accel_std_mps2) return false;
    if (plan.speed != nullptr) {
      return last_speed && t_ns - last_speed->first < FromSeconds(0.5) &&
             std::abs(last_speed->second) <= z.max_encoder_speed_mps;
    }
    const auto predicted = PredictAt(t_ns);
    return predicted && predicted->state.v_world.norm() < z.max_estimated_speed_mps;
  }

  // ---- 4d. Lidar odometry ------------------------------------------------------------------

  const EstimatorSensor* UsedLidar(const std::string& id) const {
    for (const EstimatorSensor* l : plan.lidars) {
      if (l->id == id) return l;
    }
    return nullptr;
  }

  static TimeNs SweepEnd(const LidarScan& scan) {
    float t_max = 0.f;
    for (const LidarPoint& p : *scan.points) {
      if (std::isfinite(p.t)) t_max = std::max(t_max, p.t);
    }
    return scan.header.stamp_ns + FromSeconds(std::min(0.5, static_cast<double>(t_max)));
  }

  void ProcessLidar(const LidarScan& scan) {
    const std::string& id = scan.header.sensor_id;
    if (UsedLidar(id) == nullptr) return Reject(id, RejectReason::kDisabled);
    if (!initialized) return Reject(id, RejectReason::kNotInitialized);
    if (!lidar_merger) {
      lidar_waiting.push_back(scan);
    } else {
      // Several lidars: counted here, registered as one merged scan (under the first id).
      Accept(id, scan.header.stamp_ns);
      for (LidarScan& merged : lidar_merger->Add(scan)) lidar_waiting.push_back(std::move(merged));
    }
    ProcessWaitingScans();
  }

  void ProcessWaitingScans() {
    while (!lidar_waiting.empty()) {
      const TimeNs sweep_end_ns = SweepEnd(lidar_waiting.front());
      if (sweep_end_ns > newest_imu_ns) return;
      const LidarScan scan = lidar_waiting.front();
      lidar_waiting.pop_front();
      RegisterScan(scan, sweep_end_ns);
    }
  }

  // The IMU pose at t (window or IMU prediction, mean only); nullopt if no longer held.
  std::optional<SE3> ImuPoseAt(TimeNs t_ns, std::span<const NavState> window) const {
    const auto x = output.MeanAt(t_ns, window);
    if (!x) return std::nullopt;
    return SE3(x->q_world_imu, x->p_world);
  }

  void RegisterScan(const LidarScan& scan, TimeNs sweep_end_ns) {
    const EstimatorSensor& lidar = *plan.lidars.front();
    const std::string& id = lidar.id;
    const SE3& X = lidar.T_imu_sensor;
    const TimeNs t = scan.header.stamp_ns;
    // IMU prior: the lidar's motion since the previous accepted scan and within the sweep
    // (poses every 5 ms, interpolated on SE3).
    std::optional<LidarMotionPrior> prior;
    const std::vector<NavState> window = smoother.WindowStates();
    const std::optional<SE3> T_w_i = ImuPoseAt(t, window);
    std::optional<SE3> T_w_prev;
    if (last_scan_ns) T_w_prev = ImuPoseAt(*last_scan_ns, window);
    if (T_w_i) {
      const TimeNs end = sweep_end_ns;
      constexpr TimeNs kStep = 5 * kNsPerMillisecond;
      std::vector<std::pair<double, SE3>> table;
      const SE3 T_l_w = (*T_w_i * X).Inverse();
      for (TimeNs tk = t;; tk = std::min(end, tk + kStep)) {
        const std::optional<SE3> T = ImuPoseAt(tk, window);
        if (!T) break;
        table.emplace_back(ToSeconds(tk - t), T_l_w * *T * X);
        if (tk == end) break;
      }
      if (!table.empty()) {
        LidarMotionPrior p;
        p.T_prev_curr = T_w_prev ? (*T_w_prev * X).Inverse() * (*T_w_i * X) : SE3::Identity();
        p.sweep = [table](double ts) {
          if (ts <= table.front().first) return table.front().second;
          for (std::size_t k = 1; k < table.size(); ++k) {
            if (ts <= table[k].first) {
              const double a = (ts - table[k - 1].first) / (table[k].first - table[k - 1].first);
              return SE3::Interpolate(table[k - 1].second, table[k].second, a);
            }
          }
          return table.back().second;
        };
        if (T_w_prev || !last_scan_ns) prior = p;
      }
    }
    const LidarOdometryResult r = lidar_odometry->RegisterScan(scan, prior);
    if (!r.accepted) {
      // The category of the reason (its text before the details in parentheses).
      const std::string reason = r.reject_reason.substr(0, r.reject_reason.find(" ("));
      ++Counters(id).events[reason.empty() ? "registration failed" : reason];
      return Reject(id, RejectReason::kRegistrationFailed);
    }
    if (r.diagnostics.degenerate) ++Counters(id).events["degenerate"];
    last_scan_ns = t;
    const bool merged = lidar_merger.has_value();  // the input scans were counted already
    if (r.first_scan) {
      ++Counters(id).events["registered"];
      return merged ? void() : Accept(id, t);
    }
    if (prior && T_w_prev) {
      const SE3 deviation = prior->T_prev_curr.Inverse() * r.T_prev_curr;
      if (deviation.translation().norm() > options.lidar.max_prior_deviation_m) {
        ++Counters(id).events["deviates_from_imu_prior"];
        return Reject(id, RejectReason::kMahalanobisGate);
      }
    }
    Mat6 covariance = options.lidar.covariance_scale * r.covariance;
    covariance.diagonal().head<3>().array() +=
        options.lidar.min_sigma_translation_m * options.lidar.min_sigma_translation_m;
    covariance.diagonal().tail<3>().array() +=
        options.lidar.min_sigma_rotation_rad * options.lidar.min_sigma_rotation_rad;
    RelativePoseMeasurement m;
    m.T_s1_s2 = r.T_prev_curr;
    m.T_imu_sensor = X;
    try {
      m.sqrt_information = SqrtInformationOfCovariance(covariance, "lidar relative pose");
    } catch (const InputError&) {
      return Reject(id, RejectReason::kInvalidCovariance);
    }
    if (smoother.AddRelativePose(r.prev_stamp_ns, t, m, options.lidar.kernel) ==
        AddResult::kTooOld) {
      return Reject(id, RejectReason::kTooOld);
    }
    ++Counters(id).events["registered"];
    if (!merged) Accept(id, t);
  }

  // ---- 5. Solve ------------------------------------------------------------------------------

  void Solve() {
    const auto start = std::chrono::steady_clock::now();
    const SmootherSolveSummary summary = smoother.Solve();
    std::vector<NavState> left = smoother.TakeMarginalizedStates();
    const NavState newest = smoother.NewestState();
    const Mat15 covariance = smoother.NewestCovariance();
    const auto stop = std::chrono::steady_clock::now();

    UpdateDiagnostics u;
    u.t_ns = newest.t_ns;
    u.solve_time_s = std::chrono::duration<double>(stop - start).count();
    u.iterations = summary.iterations;
    u.usable = summary.usable;
    u.num_states = summary.num_states;
    u.num_marginalized = summary.num_marginalized;
    u.factors = {{"prior", 1},
                 {"imu", summary.num_imu_factors},
                 {"bias", summary.num_imu_factors},
                 {"gnss", summary.num_gnss_factors},
                 {"heading", summary.num_heading_factors},
                 {"relative_pose", summary.num_relative_pose_factors},
                 {"velocity", summary.num_velocity_factors}};
    diag.updates.push_back(u);

    CountDownweighted(left);
    if (encoder_scale && kinematic) {
      encoder_scale->AddSmoothedStates(left);
      if (const auto scale = encoder_scale->scale()) kinematic->set_speed_scale(*scale);
    }
    smoothed.insert(smoothed.end(), left.begin(), left.end());
    if (newest.q_world_imu.coeffs().allFinite() && newest.p_world.allFinite() &&
        newest.v_world.allFinite() && covariance.allFinite()) {
      output.SetAnchor(PropagatedState{newest, covariance});
    }
    const TimeNs interval = FromSeconds(options.solve_interval_s);
    while (next_solve_ns <= lagged_ns) next_solve_ns += interval;
    TrimHistory();
  }

  // Measurements anchored at states that left the window are final: compare their whitened
  // residual at the final estimate with the robust kernel's scale.
  void CountDownweighted(const std::vector<NavState>& left) {
    if (left.empty()) return;
    const TimeNs t_window = smoother.WindowStates().front().t_ns;
    while (!accepted.empty() && accepted.front().stamp_ns < t_window) {
      const Accepted& a = accepted.front();
      auto it = std::upper_bound(left.begin(), left.end(), a.stamp_ns,
                                 [](TimeNs t, const NavState& s) { return t < s.t_ns; });
      if (it != left.begin()) {
        const PropagatedState at{output.Carry(*std::prev(it), a.stamp_ns), Mat15::Zero()};
        const double d2 = a.is_heading ? HeadingMahalanobisSquared(at, a.baseline_imu, a.heading)
                                       : GnssMahalanobisSquared(at, a.p_imu_antenna, a.fix.p_enu,
                                                                a.fix.covariance);
        const RobustKernel& k = a.is_heading ? options.heading.kernel : options.gnss.kernel;
        if (k.type != RobustKernelType::kNone && d2 > k.scale * k.scale) {
          ++Counters(a.sensor_id).downweighted;
        }
      }
      accepted.pop_front();
    }
  }

  void TrimHistory() {
    TimeNs keep = smoother.WindowStates().front().t_ns;
    if (!accepted.empty()) keep = std::min(keep, accepted.front().stamp_ns);
    output.Forget(keep);
  }

  // ---- 6. Output ---------------------------------------------------------------------------

  std::optional<PropagatedState> PredictAt(TimeNs t_ns) const {
    if (const auto p = output.AfterAnchor(t_ns)) return p;
    if (!output.has_anchor() || t_ns > newest_imu_ns) return std::nullopt;
    const std::vector<NavState> window = smoother.WindowStates();
    return output.InWindow(t_ns, window);
  }
};

FactorGraphEstimator::FactorGraphEstimator(const EstimatorSensorSetup& setup,
                                           const FactorGraphOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw InputError(why);
  impl_ = std::make_unique<Impl>(setup, options);
}

FactorGraphEstimator::~FactorGraphEstimator() = default;

void FactorGraphEstimator::Add(const Measurement& measurement) { impl_->Add(measurement); }

std::optional<StateEstimate> FactorGraphEstimator::StateAt(TimeNs t_ns) const {
  const std::optional<PropagatedState> p = impl_->PredictAt(t_ns);
  if (!p || !impl_->frame) return std::nullopt;
  StateEstimate out;
  out.state = p->state;
  out.covariance = p->covariance;
  const GeodeticPoint g = impl_->frame->ToGeodetic(out.state.p_world);
  out.latitude_deg = g.latitude_deg;
  out.longitude_deg = g.longitude_deg;
  out.altitude_m = g.altitude_m;
  const NavState& s = out.state;
  if (!s.q_world_imu.coeffs().allFinite() || !s.p_world.allFinite() || !s.v_world.allFinite() ||
      !s.gyro_bias.allFinite() || !s.accel_bias.allFinite() || !out.covariance.allFinite() ||
      !std::isfinite(out.latitude_deg) || !std::isfinite(out.longitude_deg)) {
    return std::nullopt;
  }
  return out;
}

EstimatorDiagnostics FactorGraphEstimator::diagnostics() const { return impl_->diag; }

std::vector<NavState> FactorGraphEstimator::TakeSmoothedStates() {
  std::vector<NavState> out;
  out.swap(impl_->smoothed);
  return out;
}

std::optional<GeodeticPoint> FactorGraphEstimator::origin() const {
  if (!impl_->frame) return std::nullopt;
  return impl_->frame->origin();
}

}  // namespace statebench::est
