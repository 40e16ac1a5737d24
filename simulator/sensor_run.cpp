#include "simulator/sensor_run.hpp"

#include <algorithm>
#include <utility>

#include "sensors/lidar_sensor_model.hpp"
#include "sensors/sensor_suite.hpp"
#include "simulator/world_from_sumo.hpp"

namespace statebench::sim {
namespace {

using sensors::SensorType;

std::unique_ptr<sensors::SensorSuite> MakeSuite(
    const Scenario& scenario, const sensors::SensorSetup& setup,
    const std::shared_ptr<sensors::LidarWorld>& world,
    const std::optional<sensors::SkyViewOptions>& urban_canyon, std::uint64_t sensor_seed) {
  auto suite =
      std::make_unique<sensors::SensorSuite>(setup, LocalEnuFrame(scenario.origin), sensor_seed);
  for (const sensors::SensorConfig* c : setup.OfType(SensorType::kLidar)) {
    suite->AddModel(std::make_unique<sensors::LidarSensorModel>(
        c->spec, std::get<sensors::LidarOptions>(c->options), *world, sensor_seed, c->where));
  }
  if (urban_canyon && !setup.OfType(SensorType::kGnss).empty()) {
    sensors::GnssConstellationOptions sky;
    sky.seed = scenario.seed;
    sky.site_latitude_deg = scenario.origin.latitude_deg;
    sky.site_longitude_deg = scenario.origin.longitude_deg;
    suite->SetSatelliteVisibility(
        std::make_shared<sensors::UrbanCanyonVisibility>(world, sky, *urban_canyon));
  }
  return suite;
}

}  // namespace

SensorRun::SensorRun(const Scenario& scenario, const std::filesystem::path& work_dir,
                     const SensorRunOptions& options)
    : sensors_(LoadScenarioSensors(scenario)),
      sensor_seed_(options.sensor_seed.value_or(scenario.seed)) {
  truth_ = std::make_unique<TruthSimulation>(scenario, work_dir, options.sumo);

  const sensors::SensorSetup& setup = sensors_.setup;
  std::optional<sensors::SkyViewOptions> urban_canyon = sensors_.faults.urban_canyon;
  if (options.urban_canyon && !*options.urban_canyon) urban_canyon.reset();
  if (options.urban_canyon && *options.urban_canyon && !urban_canyon) urban_canyon.emplace();
  if (setup.OfType(SensorType::kGnss).empty()) urban_canyon.reset();
  if (!setup.OfType(SensorType::kLidar).empty() || urban_canyon) {
    WorldFromSumoOptions world_options;
    world_options.layout = options.layout;
    world_options.layout.seed = scenario.seed;
    world_options.world = options.world;
    world_ = BuildLidarWorld(truth_->sumo(), truth_->terrain(), world_options);
  }
  source_ = std::make_unique<sensors::SimulatedMeasurementSource>(
      MakeSuite(scenario, setup, world_, urban_canyon, sensor_seed_),
      [this] { return NextTruth(); });
}

SensorRun::~SensorRun() = default;

std::optional<Measurement> SensorRun::Next() {
  const std::vector<SensorOutage>& outages = sensors_.faults.sensor_outages;
  while (true) {
    std::optional<Measurement> m = source_->Next();
    if (!m || outages.empty()) return m;
    const MeasurementHeader& h = HeaderOf(*m);
    const bool silent = std::any_of(outages.begin(), outages.end(), [&](const SensorOutage& o) {
      return o.Covers(h.sensor_id, h.stamp_ns);
    });
    if (!silent) return m;
  }
}

std::optional<TruthSample> SensorRun::NextTruth() {
  TruthSample sample;
  if (!truth_->Next(&sample)) return std::nullopt;
  if (observer_) observer_(sample);
  return sample;
}

SE3 SensorRun::T_body_imu() const {
  const auto imus = sensors_.setup.OfType(SensorType::kImu);
  return imus.empty() ? truth_->vehicle().T_body_imu : imus.front()->spec.T_body_sensor;
}

}  // namespace statebench::sim
