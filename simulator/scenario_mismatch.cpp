#include "simulator/scenario_mismatch.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>

#include "core/error.hpp"
#include "core/random.hpp"
#include "core/so3.hpp"

namespace statebench::sim {
namespace {

using sensors::SensorConfig;
using sensors::SensorType;

double NonNegative(const YamlNode& node, const char* key, double fallback) {
  const double v = node.Get<double>(key, fallback);
  if (!(v >= 0.0) || !std::isfinite(v)) node[key].Fail("must be a finite number >= 0");
  return v;
}

double Spread(const YamlNode& node, const char* key) {
  const double v = NonNegative(node, key, 0.0);
  if (v >= 1.0) node[key].Fail("must be below 1 (a factor 1 - s stays positive)");
  return v;
}

// `key: [min, max]` or `key: value` (min = max), 0 < min <= max; absent: both stay as they are.
void LogUniformRange(const YamlNode& node, const char* key, double* min, double* max) {
  const auto range = node.Find(key);
  if (!range) return;
  if (range->IsScalar()) {
    *min = *max = range->As<double>();
  } else {
    range->ExpectSequence();
    if (range->size() != 2) range->Fail("expected [min, max] or one number");
    *min = range->At(0).As<double>();
    *max = range->At(1).As<double>();
  }
  if (!(*min > 0.0) || !(*max >= *min) || !std::isfinite(*max)) {
    range->Fail("expected 0 < min <= max");
  }
}

// Every quantity takes its draws whatever its magnitude, so changing one magnitude (a sweep
// axis) leaves the others' draws as they were.
class Draws {
 public:
  explicit Draws(std::uint64_t seed, const char* stream) : rng_(MakeRng(seed, stream)) {}
  double Normal() { return normal_(rng_); }
  double Factor(double spread) { return 1.0 + spread * (2.0 * Uniform01(rng_) - 1.0); }
  double LogUniform(double lo, double hi) {
    const double u = Uniform01(rng_);
    return std::exp(std::log(lo) + u * (std::log(hi) - std::log(lo)));
  }

 private:
  std::mt19937_64 rng_;
  NormalSampler normal_;
};

// Scales the triad's noise density and bias instability (random walk and Gauss-Markov sigma).
void Spread(double spread, Draws& draws, sensors::ImuTriadOptions* triad, double* noise,
            double* walk) {
  *noise = draws.Factor(spread);
  *walk = draws.Factor(spread);
  triad->noise_density *= *noise;
  triad->random_walk *= *walk;
  triad->gauss_markov_sigma *= *walk;
}

}  // namespace

MismatchOptions ParseMismatch(const YamlNode& node) {
  node.ExpectMap();
  node.ExpectOnlyKeys({"imu_spread", "gnss_covariance_scale", "gnss_slow_error_scale",
                       "mount_translation_sigma_m", "mount_rotation_sigma_deg",
                       "clock_offset_sigma_s", "vehicle_mass_spread",
                       "vehicle_cornering_stiffness_spread"});
  MismatchOptions o;
  o.imu_spread = Spread(node, "imu_spread");
  LogUniformRange(node, "gnss_covariance_scale", &o.gnss_covariance_scale_min,
                  &o.gnss_covariance_scale_max);
  LogUniformRange(node, "gnss_slow_error_scale", &o.gnss_slow_error_scale_min,
                  &o.gnss_slow_error_scale_max);
  o.mount_translation_sigma_m = NonNegative(node, "mount_translation_sigma_m", 0.0);
  o.mount_rotation_sigma_deg = NonNegative(node, "mount_rotation_sigma_deg", 0.0);
  o.clock_offset_sigma_s = NonNegative(node, "clock_offset_sigma_s", 0.0);
  o.vehicle_mass_spread = Spread(node, "vehicle_mass_spread");
  o.vehicle_cornering_stiffness_spread = Spread(node, "vehicle_cornering_stiffness_spread");
  return o;
}

std::vector<SensorMismatch> ApplyMismatch(const MismatchOptions& o, std::uint64_t seed,
                                          sensors::SensorSetup* setup, ScenarioFaults* faults) {
  Draws draws(seed, "mismatch");
  Draws slow_error_draws(seed, "mismatch_gnss_slow");  // its own stream: added after the others
  std::vector<SensorMismatch> out;
  for (SensorConfig& c : setup->sensors) {
    SensorMismatch m;
    m.id = c.spec.id;
    // The true mount: the setup's, moved in the body frame and turned in the sensor frame.
    Vec3 dr;
    for (int i = 0; i < 3; ++i) m.mount_translation_m[i] = o.mount_translation_sigma_m * draws.Normal();
    for (int i = 0; i < 3; ++i) m.mount_rotation_deg[i] = o.mount_rotation_sigma_deg * draws.Normal();
    dr = m.mount_rotation_deg * std::numbers::pi / 180.0;
    const SE3& T = c.spec.T_body_sensor;
    c.spec.T_body_sensor =
        SE3(T.rotation() * so3::Exp<double>(dr), T.translation() + m.mount_translation_m);
    const double clock = o.clock_offset_sigma_s * draws.Normal();
    if (c.type() == SensorType::kImu) {
      auto& imu = std::get<sensors::ImuOptions>(c.options);
      Spread(o.imu_spread, draws, &imu.gyro, &m.gyro_noise_factor, &m.gyro_walk_factor);
      Spread(o.imu_spread, draws, &imu.accel, &m.accel_noise_factor, &m.accel_walk_factor);
    } else if (clock != 0.0) {  // the IMU is the clock the others are measured against
      m.clock_offset_s = clock;
      MeasurementFault f;
      f.kind = MeasurementFaultKind::kClockJump;
      f.sensors = {c.spec.id};
      f.start_s = 0.0;
      f.end_s = std::numeric_limits<double>::infinity();
      f.shift_s = clock;
      faults->injected.push_back(f);
    }
    const double scale =
        draws.LogUniform(o.gnss_covariance_scale_min, o.gnss_covariance_scale_max);
    if (c.type() == SensorType::kGnss) {
      auto& gnss = std::get<sensors::GnssOptions>(c.options);
      gnss.covariance_scale *= scale;
      m.reported_covariance_scale = scale;
      m.slow_error_variance_factor =
          slow_error_draws.LogUniform(o.gnss_slow_error_scale_min, o.gnss_slow_error_scale_max);
      gnss.correlated_fraction =
          std::min(1.0, gnss.correlated_fraction * m.slow_error_variance_factor);
    }
    out.push_back(m);
  }
  return out;
}

VehicleMismatch WriteEstimatorVehicleFile(const MismatchOptions& o, std::uint64_t seed,
                                         const std::filesystem::path& vehicle_file,
                                         const std::filesystem::path& out) {
  YAML::Node v;
  try {
    v = YAML::LoadFile(vehicle_file.string());
  } catch (const YAML::Exception& e) {
    throw InputError(vehicle_file.string() + ": " + e.what());
  }
  Draws draws(seed, "mismatch_vehicle");
  const double mass = draws.Factor(o.vehicle_mass_spread);
  const double front = draws.Factor(o.vehicle_cornering_stiffness_spread);
  const double rear = draws.Factor(o.vehicle_cornering_stiffness_spread);
  const auto scale = [&v](const char* key, double factor) {
    if (v[key]) v[key] = v[key].as<double>() * factor;
  };
  scale("mass_kg", mass);
  scale("yaw_inertia_kgm2", mass);
  scale("cornering_stiffness_front_npr", front);
  scale("cornering_stiffness_rear_npr", rear);
  std::ofstream file(out);
  file << "# The vehicle file the estimators are given: " << vehicle_file.string()
       << "\n# with mass, yaw inertia and cornering stiffnesses as drawn by the scenario's "
          "`mismatch:` (docs/scenarios.md).\n"
       << YAML::Dump(v) << "\n";
  if (!file) throw InputError(out.string() + ": cannot write");
  return {out, mass, front, rear};
}

}  // namespace statebench::sim
