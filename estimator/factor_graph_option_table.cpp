#include "estimator/factor_graph_option_table.hpp"

#include <cmath>
#include <sstream>

#include "core/error.hpp"

namespace statebench::est {
namespace {

using Range = OptionRange;

std::string ShowNumber(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

void ReadUse(const YamlNode& n, FactorUse* use) {
  try {
    *use = ParseFactorUse(n.As<std::string>());
  } catch (const InputError& e) {
    n.Fail(e.what());
  }
}

OptionTable<RobustKernel> KernelTable() {
  OptionTable<RobustKernel> t("robust kernel");
  t.Custom(
       "type",
       [](const YamlNode& n, RobustKernel* k) {
         try {
           k->type = ParseRobustKernelType(n.As<std::string>());
         } catch (const InputError& e) {
           n.Fail(e.what());
         }
       },
       [](const RobustKernel& k) { return std::string(RobustKernelTypeName(k.type)); },
       "none, huber, cauchy", "robust loss on the whitened residual")
      .Number("scale", &RobustKernel::scale, Range::Positive(),
              "sigmas at which the kernel starts to down-weight");
  return t;
}

OptionTable<MeasurementGateOptions> GateTable(const char* sigma_key, const char* unit,
                                              bool adapt_covariance = false) {
  OptionTable<MeasurementGateOptions> t("gate");
  t.Number(sigma_key, &MeasurementGateOptions::max_sigma, Range::Positive(),
           std::string("discard above this reported sigma (") + unit +
               (adapt_covariance ? ", horizontal" : "") +
               ", sqrt of the largest covariance eigenvalue; paper)")
      .Number("gate_chi2", &MeasurementGateOptions::gate_chi2, Range::Positive(),
              "Mahalanobis gate on the innovation (chi-square)")
      .Number("gate_reset_s", &MeasurementGateOptions::gate_reset_s, Range::Positive(),
              "after this long with only rejections, the next one passes")
      .Section("robust_kernel", &MeasurementGateOptions::kernel, KernelTable(),
               "robust loss of the factor");
  if (adapt_covariance) {  // GNSS positions
    t.Flag("adapt_covariance", &MeasurementGateOptions::adapt_covariance,
           "scale the reported covariance up when the innovations say it is too small")
        .Number("max_vertical_sigma_m", &MeasurementGateOptions::max_vertical_sigma,
                Range::Positive(),
                "a fix with a larger (or no) vertical sigma is used horizontally only")
        .Flag("estimate_time_offset", &MeasurementGateOptions::estimate_time_offset,
              "estimate each receiver's time offset to the IMU in the smoother")
        .Number("time_offset_prior_sigma_s", &MeasurementGateOptions::time_offset_prior_sigma_s,
                Range::Positive(), "prior sigma of the time offset around 0 (s)")
        .Number("time_offset_max_s", &MeasurementGateOptions::time_offset_max_s, Range::Positive(),
                "the time offset is held within +- this (s)")
        .Custom(
            "estimate_correlated_error",
            [](const YamlNode& n, MeasurementGateOptions* o) {
              ReadUse(n, &o->estimate_correlated_error);
            },
            [](const MeasurementGateOptions& o) {
              return std::string(FactorUseName(o.estimate_correlated_error));
            },
            "auto, true, false",
            "each receiver's slowly varying error (Gauss-Markov, ENU) as smoother states "
            "(auto: the receivers whose setup describes it)")
        .Number("correlated_error_sigma_m", &MeasurementGateOptions::correlated_error_sigma_m,
                Range::Positive(), "its stationary sigma, east and north (m)")
        .Number("correlated_error_vertical_sigma_m",
                &MeasurementGateOptions::correlated_error_vertical_sigma_m, Range::Positive(),
                "its stationary sigma, up (m)")
        .Number("correlated_error_tau_s", &MeasurementGateOptions::correlated_error_tau_s,
                Range::Positive(), "its correlation time (s)");
  }
  return t;
}

OptionTable<GnssCalibrationUncertainty> GnssCalibrationTable() {
  using G = GnssCalibrationUncertainty;
  OptionTable<G> t("gnss calibration");
  t.Number("mount_translation_sigma_m", &G::mount_translation_sigma_m, Range::NonNegative(),
           "per axis, each sensor's mount (m)")
      .Number("mount_rotation_sigma_deg", &G::mount_rotation_sigma_deg, Range::NonNegative(),
              "per axis, the IMU's mount (deg)")
      .Number("clock_offset_sigma_s", &G::clock_offset_sigma_s, Range::NonNegative(),
              "a receiver's clock against the IMU's (s)")
      .Flag("estimate_heading_baseline", &G::estimate_heading_baseline,
            "a heading pair's baseline yaw and pitch as two window globals (prior from the "
            "mount sigmas) instead of widening its headings");
  return t;
}

OptionTable<InitializationOptions> InitializationTable() {
  using I = InitializationOptions;
  OptionTable<I> t("initialization");
  t.Choice("mode", &I::mode,
           {{"auto", InitializationMode::kAuto},
            {"static", InitializationMode::kStatic},
            {"moving", InitializationMode::kMoving}},
           "wait for a still period, or start while moving, or either");
  const Range p = Range::Positive();
  t.Number("static_duration_s", &I::static_duration_s, p, "still period averaged")
      .Number("static_max_gyro_std_radps", &I::static_max_gyro_std_radps, p,
              "still if the gyro std per axis is below")
      .Number("static_max_accel_std_mps2", &I::static_max_accel_std_mps2, p,
              "still if the accel std per axis is below")
      .Number("static_lowpass_s", &I::static_lowpass_s, Range::NonNegative(),
              "or if the std below ~3 Hz is: two moving averages of this (0: raw only)")
      .Number("static_max_speed_mps", &I::static_max_speed_mps, p,
              "still if the fixes bound the speed below")
      .Number("course_min_distance_m", &I::course_min_distance_m, p,
              "GNSS displacement that defines the course")
      .Number("velocity_course_min_speed_mps", &I::velocity_course_min_speed_mps, p,
              "course from a GNSS velocity faster than this (and 10 sigma)")
      .Number("roll_pitch_sigma_rad", &I::roll_pitch_sigma_rad, p, "prior, static alignment")
      .Number("moving_roll_pitch_sigma_rad", &I::moving_roll_pitch_sigma_rad, p,
              "prior, moving start")
      .Number("course_yaw_sigma_rad", &I::course_yaw_sigma_rad, p, "prior of a course yaw")
      .Number("static_velocity_sigma_mps", &I::static_velocity_sigma_mps, p, "prior, still")
      .Number("moving_velocity_sigma_mps", &I::moving_velocity_sigma_mps, p, "prior, moving")
      .Number("gyro_bias_sigma_radps", &I::gyro_bias_sigma_radps, p,
              "prior when no still period measured it")
      .Number("accel_bias_sigma_mps2", &I::accel_bias_sigma_mps2, p, "prior");
  return t;
}

OptionTable<OutputBlendOptions> OutputBlendTable() {
  using B = OutputBlendOptions;
  OptionTable<B> t("output blend");
  t.Number("max_s", &B::max_s, Range::NonNegative(),
           "the longest a correction takes to come in, unless max_position_rate_mps "
           "bounds it (0: the output jumps to each solve)")
      .Number("position_rate_mps", &B::position_rate_mps, Range::Positive(),
              "position correction rate (m/s; x dt is the largest step it adds)")
      .Number("rotation_rate_radps", &B::rotation_rate_radps, Range::Positive(),
              "rotation correction rate (rad/s)")
      .Number("max_position_rate_mps", &B::max_position_rate_mps, Range::NonNegative(),
              "a position correction never comes in faster, even beyond max_s (0: no bound)")
      .Number("after_start_s", &B::after_start_s, Range::NonNegative(),
              "for this long after a (re)start (the estimate converges) ...")
      .Number("start_max_s", &B::start_max_s, Range::NonNegative(),
              "... a correction takes at most this (0: it jumps in)");
  return t;
}

OptionTable<LidarFactorOptions> LidarTable() {
  using L = LidarFactorOptions;
  const auto odometry = [](auto member) {
    return [member](L & o) -> auto& { return o.odometry.*member; };
  };
  OptionTable<L> t("lidar");
  t.Custom(
       "enabled", [](const YamlNode& n, L* o) { ReadUse(n, &o->use); },
       [](const L& o) { return std::string(FactorUseName(o.use)); }, "auto, true, false",
       "lidar odometry factors (auto: when the setup has a lidar)")
      .Number("min_range_m", odometry(&LidarOdometryOptions::min_range_m), Range::NonNegative(),
              "points closer are dropped")
      .Number("max_range_m", odometry(&LidarOdometryOptions::max_range_m), Range::Positive(),
              "points farther are dropped")
      .Number("voxel_size_m", odometry(&LidarOdometryOptions::voxel_size_m), Range::Positive(),
              "map voxel")
      .Integer("max_points_per_voxel", odometry(&LidarOdometryOptions::max_points_per_voxel), 1,
               "map points kept per voxel")
      .Number("covariance_scale", &L::covariance_scale, Range::Positive(),
              "factor covariance = ICP covariance x this")
      .Number("min_sigma_translation_m", &L::min_sigma_translation_m, Range::Positive(),
              "floor per axis, per scan period")
      .Number("min_sigma_rotation_rad", &L::min_sigma_rotation_rad, Range::Positive(),
              "floor per axis, per scan period")
      .Section("robust_kernel", &L::kernel, KernelTable(), "robust loss of the factor")
      .Number("max_prior_deviation_m", &L::max_prior_deviation_m, Range::Positive(),
              "reject a registration this far from the IMU prediction")
      .Custom(
          "motion_prior",
          [](const YamlNode& n, L* o) {
            try {
              o->motion_prior = ParseLidarPriorSource(n.As<std::string>());
            } catch (const InputError& e) {
              n.Fail(e.what());
            }
          },
          [](const L& o) { return std::string(LidarPriorSourceName(o.motion_prior)); },
          "imu, constant_velocity, gyro",
          "guess and deskew: the estimator's IMU prediction; or, shared between estimators, the "
          "odometry's constant velocity, or that with the raw gyro's rotation")
      .Flag("estimate_mount", &L::estimate_mount,
            "estimate the lidar mount's roll, pitch and yaw against the IMU (three window "
            "globals)")
      .Number("mount_prior_sigma_deg", &L::mount_prior_sigma_deg, Range::Positive(),
              "prior sigma of each mount angle")
      .Number("mount_max_deg", &L::mount_max_deg, Range::Positive(),
              "each mount angle held within +-this")
      .Flag("merge_scans", &L::merge_scans,
            "several lidars: register their scans merged into one per period through the "
            "setup's mounts (false: each lidar on its own, with its own odometry and mount "
            "globals)")
      .AddRule([](const L& o) -> std::optional<std::pair<std::string, std::string>> {
        if (o.odometry.max_range_m > o.odometry.min_range_m) return std::nullopt;
        return std::make_pair(std::string("max_range_m"), std::string("must exceed min_range_m"));
      });
  return t;
}

OptionTable<KinematicFactorOptions> KinematicTable() {
  using K = KinematicFactorOptions;
  const Range p = Range::Positive(), nn = Range::NonNegative();
  OptionTable<K> t("kinematic");
  t.Custom(
       "enabled", [](const YamlNode& n, K* o) { ReadUse(n, &o->use); },
       [](const K& o) { return std::string(FactorUseName(o.use)); }, "auto, true, false",
       "kinematic factor from the speed and steering encoders")
      .Number("period_s", &K::period_s, p, "one factor per period")
      .Number("speed_sigma_mps", &K::speed_sigma_mps, p, "white error of one speed sample")
      .Number("speed_scale_sigma", &K::speed_scale_sigma, nn, "relative scale error per period")
      .Number("steering_sigma_rad", &K::steering_sigma_rad, p, "steering offset and noise")
      .Number("lateral_sigma_mps", &K::lateral_sigma_mps, p, "side slip the model ignores")
      .Number("slip_per_lateral_accel", &K::slip_per_lateral_accel, nn,
              "rad of slip per m/s^2 of lateral acceleration")
      .Number("vertical_sigma_mps", &K::vertical_sigma_mps, p, "motion off the axle plane")
      .Number("rear_steering_ratio", &K::rear_steering_ratio, nn,
              "4-wheel steering: rear angle = -ratio x front")
      .Number("max_gap_s", &K::max_gap_s, p, "encoder gap that breaks the integration");
  return t;
}

OptionTable<NonHolonomicOptions> NonHolonomicTable() {
  using N = NonHolonomicOptions;
  OptionTable<N> t("non_holonomic");
  t.Flag("enabled", &N::enabled, "no sideways or vertical velocity of the rear axle")
      .Number("rate_hz", &N::rate_hz, Range::Positive(), "factors per second")
      .Number("slip_per_lateral_accel", &N::slip_per_lateral_accel, Range::NonNegative(),
              "lateral sigma grows by |v| x this x |v omega_z|")
      .Number("lateral_sigma_mps", &N::lateral_sigma_mps, Range::Positive(), "lateral sigma")
      .Number("vertical_sigma_mps", &N::vertical_sigma_mps, Range::Positive(), "vertical sigma")
      .Flag("estimate_mount", &N::estimate_mount,
            "estimate the IMU mount's pitch and yaw against the vehicle (two window globals)")
      .Number("mount_prior_sigma_deg", &N::mount_prior_sigma_deg, Range::Positive(),
              "prior sigma of each mount angle")
      .Number("mount_max_deg", &N::mount_max_deg, Range::Positive(),
              "each mount angle held within +-this");
  return t;
}

OptionTable<ImuTriadOptions> ImuTriadTable() {
  using T = ImuTriadOptions;
  const Range p = Range::Positive();
  OptionTable<T> t("imu_triad");
  t.Flag("estimate_gyro", &T::estimate_gyro,
         "the gyro's scale factors and cross-axis terms as nine window globals")
      .Flag("estimate_accel", &T::estimate_accel, "the accelerometer's, likewise")
      .Number("gyro_scale_sigma", &T::gyro_scale_sigma, p, "prior sigma of a scale factor (1)")
      .Number("gyro_misalignment_sigma_rad", &T::gyro_misalignment_sigma_rad, p,
              "prior sigma of a cross-axis term")
      .Number("accel_scale_sigma", &T::accel_scale_sigma, p, "prior sigma of a scale factor (1)")
      .Number("accel_misalignment_sigma_rad", &T::accel_misalignment_sigma_rad, p,
              "prior sigma of a cross-axis term")
      .Number("max_sigmas", &T::max_sigmas, p, "each held within this many prior sigmas");
  return t;
}

OptionTable<ZeroVelocityOptions> ZeroVelocityTable() {
  using Z = ZeroVelocityOptions;
  const Range p = Range::Positive();
  OptionTable<Z> t("zero_velocity");
  t.Flag("enabled", &Z::enabled, "zero-velocity factor at standstill")
      .Number("rate_hz", &Z::rate_hz, p, "factors per second")
      .Number("window_s", &Z::window_s, p, "IMU window of the standstill test")
      .Number("max_gyro_std_radps", &Z::max_gyro_std_radps, p, "quiet gyro, per axis")
      .Number("max_accel_std_mps2", &Z::max_accel_std_mps2, p, "quiet accelerometer, per axis")
      .Number("lowpass_s", &Z::lowpass_s, Range::NonNegative(),
              "or quiet below ~3 Hz: two moving averages of this (0: raw samples only)")
      .Number("max_encoder_speed_mps", &Z::max_encoder_speed_mps, p,
              "the speed encoder reads below this over the whole window")
      .Number("doppler_window_s", &Z::doppler_window_s, p,
              "without an encoder: GNSS Doppler velocities averaged over this")
      .Number("max_doppler_speed_mps", &Z::max_doppler_speed_mps, p,
              "without an encoder: their mean's horizontal speed below")
      .Number("doppler_agreement_sigmas", &Z::doppler_agreement_sigmas, Range::NonNegative(),
              "their mean within this many of its sigmas of zero: the factor's sigma is that "
              "sigma")
      .Number("max_estimated_speed_mps", &Z::max_estimated_speed_mps, p,
              "without an encoder or Doppler: estimated speed below")
      .Number("estimated_speed_sigmas", &Z::estimated_speed_sigmas, Range::NonNegative(),
              "plus this many of its sigmas (a GNSS outage's drifted speed)")
      .Number("max_acceleration_mps2", &Z::max_acceleration_mps2, p,
              "without an encoder: measured acceleration below")
      .Number("sigma_mps", &Z::sigma_mps, p, "velocity sigma of the factor")
      .Number("sigma_without_encoder_mps", &Z::sigma_without_encoder_mps, p,
              "its sigma without a speed encoder");
  return t;
}

OptionTable<ImuNoiseEstimationOptions> ImuNoiseEstimationTable() {
  using E = ImuNoiseEstimationOptions;
  const Range p = Range::Positive();
  OptionTable<E> t("imu_noise_estimation");
  t.Flag("enabled", &E::enabled, "measure the IMU noise and inflate imu_noise to it")
      .Number("block_s", &E::block_s, p, "one measurement per block of this")
      .Number("scale_s", &E::scale_s, p, "the noise of means over this (Hadamard variance)")
      .Number("time_constant_s", &E::time_constant_s, p, "running mean of the blocks")
      .Number("inflate_above", &E::inflate_above, Range::AtLeast(1.0),
              "used when above this x the configured density")
      .Number("max_inflation", &E::max_inflation, Range::AtLeast(1.0),
              "at most this x the configured density");
  return t;
}

OptionTable<FactorGraphOptions> MakeFactorGraphTable() {
  using F = FactorGraphOptions;
  OptionTable<F> t("factor graph options");
  t.Ignored("name").Ignored("description");
  t.Number("window_s", &F::window_s, Range::Positive(), "fixed-lag window")
      .Integer("imu_samples_per_state", &F::imu_samples_per_state, 1,
               "1: a state per IMU sample (paper); N: keyframes")
      .Number("solve_interval_s", &F::solve_interval_s, Range::Positive(), "time between solves")
      .Section("output_blend", &F::output_blend, OutputBlendTable(),
               "how the IMU-rate output takes in each solve's correction")
      .Custom(
          "reorder_latency_s",
          [](const YamlNode& n, F* o) {
            if (n.IsScalar() && n.raw().as<std::string>() == "auto") {
              o->reorder_latency_s.reset();
              return;
            }
            const double v = n.As<double>();
            if (!Range::NonNegative().Contains(v)) n.Fail("must be >= 0 or auto");
            o->reorder_latency_s = v;
          },
          [](const F& o) {
            return o.reorder_latency_s ? ShowNumber(*o.reorder_latency_s) : std::string("auto");
          },
          "auto or >= 0", "hold measurements this long to feed them in stamp order")
      .Integer("max_iterations", &F::max_iterations, 1, "Ceres iterations per solve")
      .Integer("num_threads", &F::num_threads, 1, "Ceres threads")
      .Choice("solver", &F::solver,
              {{"ceres", WindowSolver::kCeres}, {"chain", WindowSolver::kChain}},
              "ceres::Solve, or the same Levenberg-Marquardt on the window's chain structure")
      .Flag("batch", &F::batch,
            "full-batch smoother: every state solved at the end of the log, no marginalisation")
      .Integer("batch_max_iterations", &F::batch_max_iterations, 1,
               "Levenberg-Marquardt iterations of the batch solve")
      .Flag("lagged_output", &F::lagged_output,
            "the smoothed output: each state as it leaves the window, read at the end of the log")
      .Custom(
          "origin",
          [](const YamlNode& n, F* o) {
            n.ExpectMap();
            n.ExpectOnlyKeys({"latitude_deg", "longitude_deg", "altitude_m"});
            GeodeticPoint p;
            p.latitude_deg = n.Get<double>("latitude_deg");
            p.longitude_deg = n.Get<double>("longitude_deg");
            p.altitude_m = n.Get<double>("altitude_m", 0.0);
            if (!(std::abs(p.latitude_deg) <= 90.0)) n["latitude_deg"].Fail("must be in [-90, 90]");
            if (!(std::abs(p.longitude_deg) <= 180.0)) {
              n["longitude_deg"].Fail("must be in [-180, 180]");
            }
            o->origin = p;
          },
          [](const F& o) { return std::string(o.origin ? "given" : "first fix"); },
          "{latitude_deg, longitude_deg, altitude_m}", "ENU origin")
      .Section("imu_noise", &F::imu_noise, ImuNoiseOptionTable(),
               "IMU noise (Kalibr units); a setup's imu entry may override it")
      .Section("imu_noise_estimation", &F::imu_noise_estimation, ImuNoiseEstimationTable(),
               "the IMU noise measured online; inflates imu_noise, never deflates it")
      .Section("imu_triad", &F::imu_triad, ImuTriadTable(),
               "the IMU's scale factors and cross-axis terms as states")
      .Section("initialization", &F::initialization, InitializationTable(), "first state")
      .Section("gnss", &F::gnss, GateTable("max_sigma_m", "m", true), "GNSS position factors")
      .Section("heading", &F::heading, GateTable("max_sigma_rad", "rad"),
               "dual-antenna heading factors")
      .Section("gnss_velocity", &F::gnss_velocity, GateTable("max_sigma_mps", "m/s"),
               "GNSS (Doppler) velocity factors")
      .Section("gnss_calibration", &F::gnss_calibration, GnssCalibrationTable(),
               "how far the setup's mounts and clocks may be off: widens GNSS fixes and headings")
      .Section("lidar", &F::lidar, LidarTable(), "lidar odometry factors")
      .Section("kinematic", &F::kinematic, KinematicTable(), "encoder kinematic factor")
      .Section("non_holonomic", &F::non_holonomic, NonHolonomicTable(), "non-holonomic constraint")
      .Section("zero_velocity", &F::zero_velocity, ZeroVelocityTable(), "zero-velocity factor")
      .Section("imu_limits", &F::imu_limits, ImuLimitsOptionTable(),
               "saturated or implausible IMU samples, and IMU gaps");
  return t;
}

}  // namespace

const OptionTable<ImuNoise>& ImuNoiseOptionTable() {
  static const OptionTable<ImuNoise> table = [] {
    OptionTable<ImuNoise> t("imu noise");
    t.Number("gyro_noise_density", &ImuNoise::gyro_noise_density, Range::Positive(),
             "rad/s/sqrt(Hz)")
        .Number("accel_noise_density", &ImuNoise::accel_noise_density, Range::Positive(),
                "m/s^2/sqrt(Hz)")
        .Number("gyro_random_walk", &ImuNoise::gyro_random_walk, Range::Positive(),
                "rad/s^2/sqrt(Hz)")
        .Number("accel_random_walk", &ImuNoise::accel_random_walk, Range::Positive(),
                "m/s^3/sqrt(Hz)")
        .Number("integration_density", &ImuNoise::integration_density, Range::NonNegative(),
                "m/sqrt(s), position integration error");
    return t;
  }();
  return table;
}

const OptionTable<GnssAntenna>& GnssAntennaOptionTable() {
  static const OptionTable<GnssAntenna> table = [] {
    OptionTable<GnssAntenna> t("gnss antenna");
    t.Number("covariance_scale", &GnssAntenna::covariance_scale, Range::Positive(),
             "reported covariance x this")
        .Number("min_sigma_m", &GnssAntenna::min_sigma_m, Range::NonNegative(),
                "eigenvalues floored at this sigma")
        .Number("correlated_error_sigma_m", &GnssAntenna::correlated_error_sigma_m,
                Range::NonNegative(),
                "the receiver's slow error: stationary sigma, east and north (m; 0: not given)")
        .Number("correlated_error_vertical_sigma_m",
                &GnssAntenna::correlated_error_vertical_sigma_m, Range::NonNegative(),
                "its stationary sigma, up (m)")
        .Number("correlated_error_tau_s", &GnssAntenna::correlated_error_tau_s,
                Range::NonNegative(), "its correlation time (s)");
    return t;
  }();
  return table;
}

const OptionTable<FactorGraphOptions>& FactorGraphOptionTable() {
  static const OptionTable<FactorGraphOptions> table = MakeFactorGraphTable();
  return table;
}

}  // namespace statebench::est
