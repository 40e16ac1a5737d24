#include "simulator/sensor_run.hpp"

#include <algorithm>
#include <map>
#include <utility>

#include "core/stage_profile.hpp"
#include "sensors/lidar_sensor_model.hpp"
#include "sensors/measurement_stream.hpp"
#include "sensors/sensor_suite.hpp"
#include "simulator/world_from_sumo.hpp"

namespace statebench::sim {
namespace {

using sensors::SensorType;

constexpr const char* kSensorStage = "sensors";
constexpr const char* kStreamFile = "stream.bin";

// `cached`: the sensors whose stream the cache holds (entry folder by id); their models are
// replayed, the lidars among them never built. `world` may be null when no model needs it.
std::unique_ptr<sensors::SensorSuite> MakeSuite(
    const Scenario& scenario, const sensors::SensorSetup& setup,
    const std::shared_ptr<sensors::LidarWorld>& world,
    const std::optional<sensors::SkyViewOptions>& urban_canyon, std::uint64_t sensor_seed,
    const std::map<std::string, std::filesystem::path>& cached) {
  auto suite =
      std::make_unique<sensors::SensorSuite>(setup, LocalEnuFrame(scenario.origin), sensor_seed);
  for (const sensors::SensorConfig* c : setup.OfType(SensorType::kLidar)) {
    if (const auto entry = cached.find(c->spec.id); entry != cached.end()) {
      suite->AddModel(
          std::make_unique<sensors::ReplayedSensorModel>(c->spec, entry->second / kStreamFile));
      continue;
    }
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
      sensor_seed_(options.sensor_seed.value_or(scenario.seed)),
      cache_(options.cache),
      faults_(sensors_.faults.StreamFaults()) {
  {
    const StageScope stage(Stage::kSumo);
    truth_ = std::make_unique<TruthSimulation>(scenario, work_dir, options.sumo, cache_);
  }

  const sensors::SensorSetup& setup = sensors_.setup;
  std::optional<sensors::SkyViewOptions> urban_canyon = sensors_.faults.urban_canyon;
  if (options.urban_canyon && !*options.urban_canyon) urban_canyon.reset();
  if (options.urban_canyon && *options.urban_canyon && !urban_canyon) urban_canyon.emplace();
  if (setup.OfType(SensorType::kGnss).empty()) urban_canyon.reset();

  // Streams the cache holds, and the keys of the others (recorded below).
  std::map<std::string, std::filesystem::path> cached;
  std::map<std::string, std::string> keys;
  const std::optional<std::string> truth_key =
      cache_.enabled() ? TruthStageKey(scenario, options.sumo, cache_.code_id) : std::nullopt;
  if (truth_key) {
    keys = SensorStreamKeys(scenario, sensors_, *truth_key, sensor_seed_, cache_.code_id);
    for (const auto& [id, key] : keys) {
      if (const auto entry = cache_.cache->Find(kSensorStage, key)) cached[id] = *entry;
    }
  }
  const auto needs_world = [&](SensorType type) {
    for (const sensors::SensorConfig* c : setup.OfType(type)) {
      if (!cached.count(c->spec.id)) return true;
    }
    return false;
  };
  if (needs_world(SensorType::kLidar) || (urban_canyon && needs_world(SensorType::kGnss))) {
    const StageScope stage(Stage::kWorld);
    WorldFromSumoOptions world_options;
    world_options.layout = options.layout;
    world_options.layout.seed = scenario.seed;
    world_options.world = options.world;
    world_ = BuildLidarWorld(truth_->sumo(), truth_->terrain(), world_options);
  }
  auto suite = MakeSuite(scenario, setup, world_, world_ ? urban_canyon : std::nullopt,
                         sensor_seed_, cached);
  if (truth_key) {
    suite->ReplaceModels(
        [&](std::unique_ptr<sensors::SensorModel> model) -> std::unique_ptr<sensors::SensorModel> {
          const std::string& id = model->spec().id;
          if (dynamic_cast<sensors::ReplayedSensorModel*>(model.get())) return model;
          if (const auto entry = cached.find(id); entry != cached.end()) {
            return std::make_unique<sensors::ReplayedSensorModel>(model->spec(),
                                                                  entry->second / kStreamFile);
          }
          const auto key = keys.find(id);
          if (key == keys.end()) return model;  // not an entry of the setup (none today)
          StageCache::PendingEntry entry = cache_.cache->Begin(kSensorStage, key->second);
          auto recorder = std::make_unique<sensors::RecordingSensorModel>(
              std::move(model), entry.folder() / kStreamFile);
          recordings_.push_back({recorder.get(), std::move(entry)});
          return recorder;
        });
  }
  source_ = std::make_unique<sensors::SimulatedMeasurementSource>(std::move(suite),
                                                                  [this] { return NextTruth(); });
}

void SensorRun::PublishRecordings() {
  for (Recording& r : recordings_) {
    r.model->Close();
    r.entry.Publish();
  }
  recordings_.clear();
}

std::optional<Measurement> SensorRun::Next() {
  const StageScope stage(Stage::kSensors);
  while (pending_.empty()) {
    std::optional<Measurement> m = lookahead_ ? std::move(lookahead_) : source_->Next();
    lookahead_.reset();
    if (!m || faults_.empty()) return m;
    // Everything that arrives at this instant, faults applied, in the stream's order again (a
    // fault may move a stamp, which orders measurements of equal arrival: ArrivesBefore), so a
    // recorded log reads back in the order it was delivered.
    const TimeNs arrival_ns = HeaderOf(*m).arrival_ns;
    std::vector<Measurement> group;
    faults_.Apply(*m, &group);
    while (std::optional<Measurement> n = source_->Next()) {
      if (HeaderOf(*n).arrival_ns != arrival_ns) {
        lookahead_ = std::move(n);
        break;
      }
      faults_.Apply(*n, &group);
    }
    std::stable_sort(group.begin(), group.end(), sensors::ArrivesBefore);
    for (Measurement& x : group) pending_.push_back(std::move(x));
  }
  Measurement m = std::move(pending_.front());
  pending_.pop_front();
  return m;
}

std::optional<TruthSample> SensorRun::NextTruth() {
  TruthSample sample;
  bool more = false;
  {
    const StageScope stage(Stage::kVehicle);
    more = truth_->Next(&sample);
  }
  if (!more) {
    PublishRecordings();
    return std::nullopt;
  }
  if (observer_) observer_(sample);
  return sample;
}

SE3 SensorRun::T_body_imu() const {
  const auto imus = sensors_.setup.OfType(SensorType::kImu);
  return imus.empty() ? truth_->vehicle().T_body_imu : imus.front()->spec.T_body_sensor;
}

}  // namespace statebench::sim
