#include "simulator/cached_stages.hpp"

#include <yaml-cpp/yaml.h>


#include "core/content_hash.hpp"
#include "core/csv.hpp"
#include "core/yaml_merge.hpp"
#include "simulator/sumo_result_io.hpp"

namespace statebench::sim {
namespace {

namespace fs = std::filesystem;

constexpr const char* kTruthStage = "sumo";
constexpr const char* kResultFile = "sumo_result.bin";
constexpr const char* kNetFile = "net.net.xml";

}  // namespace

std::optional<std::string> TruthStageKey(const Scenario& scenario, const SumoRunOptions& options,
                                         const std::string& code_id) {
  std::error_code ec;
  if (!fs::is_regular_file(scenario.file, ec)) return std::nullopt;
  const YAML::Node root = YAML::LoadFile(scenario.file.string());
  Sha256 key;
  key.Field("truth v1").Field(code_id);
  for (const char* field : {"network", "ego", "traffic", "sumo"}) {
    key.Field(field).Field(ToYamlText(root[field]));
  }
  if (scenario.network.xml) {
    const XmlNetwork& xml = *scenario.network.xml;
    key.File(xml.nodes).File(xml.edges);
    if (xml.connections) key.File(*xml.connections);
    if (xml.traffic_lights) key.File(*xml.traffic_lights);
  }
  key.File(scenario.vehicle_file);
  key.Field(std::to_string(scenario.seed)).Field(NumberText(scenario.duration_s));
  key.Field(NumberText(scenario.origin.latitude_deg))
      .Field(NumberText(scenario.origin.longitude_deg))
      .Field(NumberText(scenario.origin.altitude_m));
  key.Field(NumberText(options.lookahead_m))
      .Field(NumberText(options.max_tail_s))
      .Field(options.record_traffic ? "traffic" : "no traffic");
  return key.Hex();
}

std::map<std::string, std::string> SensorStreamKeys(const Scenario& scenario,
                                                    const ScenarioSensors& sensors,
                                                    const std::string& truth_key,
                                                    std::uint64_t sensor_seed,
                                                    const std::string& code_id) {
  const YAML::Node setup = YAML::Load(sensors.setup_yaml);
  const std::string faults = scenario.faults ? ToYamlText(scenario.faults->raw()) : "";
  std::map<std::string, std::string> keys;
  for (const sensors::SensorConfig& c : sensors.setup.sensors) {
    std::string entry;
    for (const YAML::Node& e : setup["sensors"]) {
      if (e["id"] && e["id"].as<std::string>() == c.spec.id) entry = ToYamlText(e);
    }
    Sha256 key;
    key.Field("sensor v1").Field(code_id).Field(truth_key).Field(entry);
    key.Field(std::to_string(sensor_seed)).Field(std::to_string(scenario.seed));
    if (c.type() == sensors::SensorType::kGnss) key.Field(faults);
    if (scenario.mismatch) {  // the drawn unit (noise, mounts, reported covariance, slow error)
      const MismatchOptions& m = *scenario.mismatch;
      key.Field("mismatch v1");
      for (const double v : {m.imu_spread, m.gnss_covariance_scale_min, m.gnss_covariance_scale_max,
                             m.mount_translation_sigma_m, m.mount_rotation_sigma_deg,
                             m.gnss_slow_error_scale_min, m.gnss_slow_error_scale_max}) {
        key.Field(NumberText(v));
      }
    }
    keys[c.spec.id] = key.Hex();
  }
  return keys;
}

std::optional<std::string> EstimatorInputsKey(const Scenario& scenario,
                                              const ScenarioSensors& sensors,
                                              const SumoRunOptions& options,
                                              std::uint64_t sensor_seed,
                                              const std::string& code_id) {
  const std::optional<std::string> truth_key = TruthStageKey(scenario, options, code_id);
  if (!truth_key) return std::nullopt;
  Sha256 key;
  key.Field("estimator inputs v1").Field(code_id).Field(*truth_key);
  for (const auto& [id, k] : SensorStreamKeys(scenario, sensors, *truth_key, sensor_seed, code_id)) {
    key.Field(id).Field(k);
  }
  key.Field(scenario.faults ? ToYamlText(scenario.faults->raw()) : "");
  if (scenario.mismatch) {
    const MismatchOptions& m = *scenario.mismatch;
    key.Field("mismatch");
    for (const double v : {m.imu_spread, m.gnss_covariance_scale_min, m.gnss_covariance_scale_max,
                           m.mount_translation_sigma_m, m.mount_rotation_sigma_deg,
                           m.clock_offset_sigma_s, m.vehicle_mass_spread,
                           m.vehicle_cornering_stiffness_spread}) {
      key.Field(NumberText(v));
    }
  }
  return key.Hex();
}

SumoResult SimulateSumoCached(const Scenario& scenario, const EgoVehicleType& ego_type,
                              const fs::path& work_dir, const SumoRunOptions& options,
                              const StageCacheUse& use) {
  const std::optional<std::string> key =
      use.enabled() ? TruthStageKey(scenario, options, use.code_id) : std::nullopt;
  const fs::path sumo_dir = work_dir / "sumo";
  if (!key) return SimulateSumo(scenario, ego_type, sumo_dir, options);
  StageCache& cache = *use.cache;
  const StageCache::KeyLock lock = cache.Lock(kTruthStage, *key);
  if (const auto entry = cache.Find(kTruthStage, *key)) {
    std::error_code ec;
    fs::create_directories(sumo_dir, ec);
    fs::copy_file(*entry / kNetFile, sumo_dir / kNetFile, fs::copy_options::overwrite_existing,
                  ec);
    return ReadSumoResult(*entry / kResultFile);
  }
  SumoResult result = SimulateSumo(scenario, ego_type, sumo_dir, options);
  cache.Write(kTruthStage, *key, [&](const fs::path& written) {
    WriteSumoResult(result, written / kResultFile);
    fs::copy_file(sumo_dir / kNetFile, written / kNetFile);
  });
  return result;
}

}  // namespace statebench::sim
