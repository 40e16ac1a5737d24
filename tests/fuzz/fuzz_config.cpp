// Fuzz target: the YAML inputs a user writes. The first byte picks the parser (scenario with its
// sensor setup and faults when the simulator is built, simulator sensor setup, estimator sensor setup, factor-graph options,
// EKF options, vehicle parameters); the rest is the YAML text. Bad input must end in an
// InputError naming file, line and field, never in a crash or another exception.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/error.hpp"
#include "core/yaml_node.hpp"
#include "estimator/ekf_options.hpp"
#include "estimator/estimator_config.hpp"
#include "fuzz_support.hpp"
#include "sensors/sensor_setup.hpp"
#if STATEBENCH_FUZZ_SCENARIOS
#include "simulator/scenario.hpp"
#include "simulator/scenario_sensors.hpp"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace statebench;
  if (size < 1) return 0;
  const int parser = data[0] % 6;
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  try {
    if (parser == 0) {
#if STATEBENCH_FUZZ_SCENARIOS
      // A scenario file beside the stock folders (setups and vehicles resolve through
      // STATEBENCH_SOURCE_DIR, which scripts/fuzz.sh sets).
      const auto file = fuzz::ScratchDir() / "scenario.yaml";
      fuzz::WriteFile(file, text);
      const sim::Scenario scenario = sim::LoadScenario(file);
      sim::LoadScenarioSensors(scenario);
#endif
      return 0;
    }
    const YamlNode root = YamlNode::LoadString(text, "fuzz.yaml");
    switch (parser) {
      case 1:
        sensors::ParseSensorSetup(root);
        break;
      case 2:
        est::ParseEstimatorSensorSetup(root);
        break;
      case 3:
        est::ParseFactorGraphOptions(root);
        break;
      case 4:
        est::ParseEkfOptions(root);
        break;
      default:
        est::ParseSingleTrackParams(root);
        break;
    }
  } catch (const InputError&) {
  } catch (const std::exception& e) {
    fuzz::Unexpected("fuzz_config", e);
  }
  return 0;
}
