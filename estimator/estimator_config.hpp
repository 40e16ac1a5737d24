// Estimator configuration: what the estimator reads from a sensor-setup YAML, and its own options
// YAML. Formats in docs/estimator-config.md.
//
// Sensor setup (docs/sensor-setup.md, the simulator's files): the estimator reads each sensor's
// type, id and T_body_sensor and ignores the simulation parameters. It works in the IMU frame:
//   T_imu_sensor = T_body_imu^-1 T_body_sensor.
// A sensor entry may carry an `estimator:` block overriding noise for that sensor (IMU noise
// densities; GNSS covariance scale and floor). Two GNSS antennas and no `dual_antenna_headings`
// entry: they are paired (first listed = main) and fixes of the same stamp give a heading.
//
// Options: smoother window, states per IMU sample, solve rate, reorder latency, gates, robust
// kernels, initialisation, priors; every field optional with defaults that serve every setup
// (scenarios/estimators/factor_graph.yaml lists them).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/geodetic.hpp"
#include "core/se3.hpp"
#include "core/yaml_node.hpp"
#include "estimator/imu_noise.hpp"
#include "estimator/imu_noise_monitor.hpp"
#include "estimator/measurement_checks.hpp"
#include "estimator/motion_factor_options.hpp"
#include "estimator/output_blend.hpp"
#include "estimator/robust_kernel.hpp"
#include "estimator/window_solver.hpp"

namespace statebench::est {

enum class SensorKind {
  kImu,
  kGnss,
  kWheelEncoders,
  kSpeedEncoder,
  kSteeringEncoder,
  kLidar,
  kBodyVelocity,  // generic velocity odometry (wheel odometry, radar...) of the sensor frame
};

struct EstimatorSensor {
  std::string id;
  SensorKind kind = SensorKind::kImu;
  SE3 T_body_sensor;
  SE3 T_imu_sensor;
  double latency_s = 0.0;  // arrival - stamp as the setup states it (0 if absent)
};

struct GnssAntenna {
  std::string id;
  Vec3 p_imu_antenna = Vec3::Zero();
  double covariance_scale = 1.0;  // reported covariance multiplied by this ...
  double min_sigma_m = 0.0;       // ... and its eigenvalues floored at min_sigma_m^2
  // The receiver's slowly varying error as its setup describes it (a datasheet or a static
  // recording; estimator-config.md, "Per-sensor estimator overrides"): stationary sigmas and
  // correlation time of the Gauss-Markov error states. 0: not described, the options'
  // gnss.correlated_error_* apply.
  double correlated_error_sigma_m = 0.0;           // east and north
  double correlated_error_vertical_sigma_m = 0.0;  // up
  double correlated_error_tau_s = 0.0;
  bool DescribesCorrelatedError() const { return correlated_error_sigma_m > 0.0; }
};

struct DualAntennaPair {
  std::string heading_id;  // sensor id of DualAntennaHeading measurements; empty: paired fixes
  std::string main;        // baseline main -> aux
  std::string aux;
  Vec3 p_imu_main = Vec3::Zero();
  Vec3 p_imu_aux = Vec3::Zero();
  double latency_s = 0.0;  // of the heading measurements (0 if absent)
};

struct EstimatorSensorSetup {
  std::string source;  // file the setup came from
  std::string name;
  std::string imu_id;
  SE3 T_body_imu;
  std::optional<ImuNoise> imu_noise;     // the IMU entry's estimator override, over the options'
  std::vector<EstimatorSensor> sensors;  // every sensor, file order
  std::vector<GnssAntenna> antennas;
  std::vector<DualAntennaPair> dual_antennas;

  const EstimatorSensor* Find(const std::string& id) const;
  const GnssAntenna* FindAntenna(const std::string& id) const;
  const DualAntennaPair* FindHeading(const std::string& heading_id) const;
  // Largest latency of the sensors whose measurements the estimator places in the window at
  // their stamps (GNSS antennas and headings, body-velocity odometry).
  double MaxMeasurementLatency() const;
  // The ids of the sensors that give an absolute position (the GNSS antennas).
  std::vector<std::string> PositionSensorIds() const;
};

// The setup with only the sensors `ids` (the inputs an estimator is given; e.g. the paper's setup-2
// factor graph: IMU, front antenna and lidar): antennas, dual-antenna pairs (both antennas kept)
// and sensors of other ids are left out. Throws InputError when an id is not in the setup or the
// IMU is not among them.
EstimatorSensorSetup RestrictToSensors(const EstimatorSensorSetup& setup,
                                       const std::vector<std::string>& ids);

// InputError naming file:line:column and field on: unknown sensor type, missing or duplicate id,
// no IMU or more than one, bad transform, unknown key in an `estimator:` block, a dual-antenna
// entry naming a sensor that is not a GNSS antenna.
EstimatorSensorSetup LoadEstimatorSensorSetup(const std::filesystem::path& path);
EstimatorSensorSetup ParseEstimatorSensorSetup(const YamlNode& root);

enum class InitializationMode { kAuto, kStatic, kMoving };

struct InitializationOptions {
  // kStatic: wait for a still period; kMoving: do not wait for one; kAuto: whichever comes
  // first (static alignment if the vehicle is still, GNSS course or dual antenna if moving).
  InitializationMode mode = InitializationMode::kAuto;
  double static_duration_s = 1.0;           // still period averaged for gravity and gyro bias
  double static_max_gyro_std_radps = 0.01;  // per axis, over the still period
  double static_max_accel_std_mps2 = 0.1;   // per axis
  // With an engine running no raw window is quiet: the window counts as still when its low band
  // (below ~3 Hz, two moving averages of this; imu_band_split.hpp) is. 0: the raw test only.
  double static_lowpass_s = 0.1;
  // The IMU cannot tell a constant velocity from standstill: a still period counts only when the
  // GNSS fixes since the IMU began to look still bound the horizontal speed (least-squares
  // speed + 3 sigma) below this. Noisy fixes need a longer wait (CEP 2 m at 10 Hz: ~15 s).
  double static_max_speed_mps = 0.1;
  double course_min_distance_m = 5.0;  // GNSS displacement that defines the course
  // A GNSS (Doppler) velocity gives the course at once when its horizontal speed is above this
  // and 10 times its horizontal sigma (yaw sigma under 0.1 rad).
  double velocity_course_min_speed_mps = 1.0;
  // Prior sigmas of the first state where no measurement gives them.
  double roll_pitch_sigma_rad = 0.02;  // static alignment (accel bias / g ~ 0.01 rad)
  double moving_roll_pitch_sigma_rad = 0.05;
  double course_yaw_sigma_rad = 0.1;  // yaw from the GNSS course (slip, chord vs tangent)
  double static_velocity_sigma_mps = 0.02;
  double moving_velocity_sigma_mps = 0.5;
  double gyro_bias_sigma_radps = 0.01;  // when not measured in a still period
  double accel_bias_sigma_mps2 = 0.1;
};

struct MeasurementGateOptions {
  // Paper: discard measurements whose reported uncertainty exceeds a threshold (sqrt of the
  // largest covariance eigenvalue, m for GNSS, rad for headings).
  double max_sigma = 5.0;
  // Mahalanobis gate: squared innovation norm over (H P H^T + R) above this is rejected.
  double gate_chi2 = 16.27;  // chi-square(3) at p = 0.999
  // After this long without an accepted measurement of the kind (but with rejected ones), the
  // gate lets the next one through (recovery after a divergence); the kernel still applies.
  double gate_reset_s = 10.0;
  RobustKernel kernel;
  // Scale the reported covariance by what the innovations' consistency across measurements says
  // (estimator/innovation_scale.hpp; never below the reported one). GNSS positions only.
  bool adapt_covariance = false;
  // GNSS positions only: a fix whose vertical sigma is above this (or not given) is used
  // horizontally only (measurement_gate.hpp, FixUse); max_sigma then tests the horizontal part.
  double max_vertical_sigma = 5.0;
  // GNSS positions only: estimate each receiver's time offset to the IMU (how late its stamps
  // are) as a state of the smoother (gnss_time_offset_factor.hpp), with the prior N(0, sigma^2)
  // and held within +-time_offset_max_s.
  bool estimate_time_offset = false;
  double time_offset_prior_sigma_s = 0.2;
  double time_offset_max_s = 0.5;
  // GNSS positions only: each receiver's slowly varying error (multipath, atmosphere; what
  // averaging fixes does not remove) as three states of the smoother, east, north and up
  // (gnss_error_state_factor.hpp), each a first-order Gauss-Markov process of these stationary
  // sigmas and correlation time (shared/REFERENCE.md: tau 30-300 s), held within 5 sigmas.
  // kAuto: the receivers whose setup describes their slow error (GnssAntenna), with its figures;
  // kOn: every receiver, with the setup's figures where it gives them, else these; kOff: none.
  FactorUse estimate_correlated_error = FactorUse::kAuto;
  double correlated_error_sigma_m = 0.5;           // east and north
  double correlated_error_vertical_sigma_m = 1.0;  // up
  double correlated_error_tau_s = 100.0;
  // Whether `antenna` gets the error states under estimate_correlated_error.
  bool EstimatesCorrelatedErrorOf(const GnssAntenna& antenna) const {
    return estimate_correlated_error == FactorUse::kOn ||
           (estimate_correlated_error == FactorUse::kAuto && antenna.DescribesCorrelatedError());
  }
};

// How far the setup's mounts and clocks may be from the truth (estimator/gnss_calibration_
// covariance.hpp): GNSS fixes and dual-antenna headings are widened by what such errors do.
// Defaults: the low end of shared/REFERENCE.md's figures for mounts measured by hand (1-2 cm,
// 0.2-1 deg) and unsynchronised clocks (a few ms). Zero turns a term off.
struct GnssCalibrationUncertainty {
  double mount_translation_sigma_m = 0.01;  // per axis, each sensor's mount
  double mount_rotation_sigma_deg = 0.2;    // per axis, the IMU's mount
  double clock_offset_sigma_s = 0.003;      // the receiver's clock against the IMU's
  // A dual-antenna pair's baseline direction (yaw, pitch) as two globals of the window with the
  // priors these sigmas give it, instead of widening each heading and adding it to the output
  // covariance (gnss_front_end.hpp).
  bool estimate_heading_baseline = false;
};

// The IMU's scale factors and cross-axis terms (its triad errors) as globals of the window
// (estimator/imu_triad_factor.hpp): nine per triad, each with the prior N(0, sigma^2) and held
// within max_sigmas of it. Defaults: shared/REFERENCE.md's upper figures for a MEMS gyro (scale
// factor 0.1-1 %, cross-axis 0.1-0.5 %); the accelerometer is given the same (REFERENCE has no
// separate figure). diagnostics.json reports each under the IMU (gyro_scale_x, gyro_xz, ...).
// On by default: over 50 held-out seeds they bring setups 1 and 3 inside their ANEES bounds and
// halve setup 2's (docs/calibration-states.md); false / false is the estimator without them.
struct ImuTriadOptions {
  bool estimate_gyro = true;
  bool estimate_accel = true;
  double gyro_scale_sigma = 0.01;
  double gyro_misalignment_sigma_rad = 0.005;
  double accel_scale_sigma = 0.01;
  double accel_misalignment_sigma_rad = 0.005;
  double max_sigmas = 5.0;

  bool any() const { return estimate_gyro || estimate_accel; }
};

inline constexpr double kReorderMarginS = 0.05;  // jitter allowed on top of the stated latency

struct FactorGraphOptions {
  double window_s = 1.0;
  int imu_samples_per_state = 10;  // 1: a state per IMU sample (paper); N: keyframes
  double solve_interval_s = 0.1;
  // How the IMU-rate output takes in the correction each solve brings (output_blend.hpp): at a
  // bounded rate instead of a jump between two samples; its covariance covers the offset still
  // shown.
  OutputBlendOptions output_blend;
  // Every measurement is held until the IMU is this far past its stamp and then fed to the
  // smoother in stamp order, so delivery order does not change the result (delays up to this).
  // The IMU-rate output is an IMU prediction over this span. nullopt ("auto"): the setup's
  // largest GNSS/heading latency plus kReorderMarginS.
  std::optional<double> reorder_latency_s;
  int max_iterations = 10;
  int num_threads = 1;
  WindowSolver solver = WindowSolver::kChain;  // sliding_window_smoother.hpp
  // The full-batch smoother (the accuracy bound the fixed-lag smoother is judged against): the
  // fixed-lag smoother runs as usual but keeps every state and factor that leaves its window;
  // at the end of the log they are solved together (no marginalisation) with up to
  // batch_max_iterations iterations, and the estimate comes from the batch states
  // (Estimator::EstimatesAtEnd).
  bool batch = false;
  int batch_max_iterations = 50;
  // The fixed-lag smoother's smoothed output instead of its real-time one: the estimate at a
  // stamp comes from the latest state at or before it as estimated when it left the window
  // (window_s of lag; the window's last states at the end of the log), with its marginal
  // covariance then, carried through the IMU samples. The smoother runs exactly as without it;
  // the estimate is read at the end of the log (Estimator::EstimatesAtEnd). Not with batch.
  bool lagged_output = false;
  std::optional<GeodeticPoint> origin;  // ENU origin; default the first accepted GNSS fix
  ImuNoise imu_noise;
  ImuNoiseEstimationOptions imu_noise_estimation;  // imu_noise_monitor.hpp
  ImuTriadOptions imu_triad;
  InitializationOptions initialization;
  MeasurementGateOptions gnss{.adapt_covariance = true};                   // defaults above
  MeasurementGateOptions heading{0.2, 13.82, 10.0, RobustKernel{}};        // rad; chi-square(2)
  MeasurementGateOptions gnss_velocity{1.0, 16.27, 10.0, RobustKernel{}};  // m/s; chi-square(3)
  GnssCalibrationUncertainty gnss_calibration;
  LidarFactorOptions lidar;
  KinematicFactorOptions kinematic;
  NonHolonomicOptions non_holonomic;
  ZeroVelocityOptions zero_velocity;
  ImuLimits imu_limits;

  bool IsValid(std::string* why = nullptr) const;
  double ReorderLatency(const EstimatorSensorSetup& setup) const;
};

// Every key optional; unknown keys and invalid values are InputErrors naming file:line.
FactorGraphOptions LoadFactorGraphOptions(const std::filesystem::path& path);
FactorGraphOptions ParseFactorGraphOptions(const YamlNode& root);

}  // namespace statebench::est
