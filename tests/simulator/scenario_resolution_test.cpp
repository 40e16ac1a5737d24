#include "simulator/scenario_resolution.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/yaml_merge.hpp"
#include "simulator/scenario.hpp"
#include "simulator/scenario_sensors.hpp"

namespace statebench::sim {
namespace {

namespace fs = std::filesystem;

// ctest runs the tests in the source folder.
const fs::path kSetup2 = fs::absolute("scenarios/paper/setup2_quadricycle.yaml");
const fs::path kSetup3 = fs::absolute("scenarios/paper/setup3_shuttle.yaml");

class ScenarioResolutionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("scenario_resolution_test_" + std::to_string(getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path Write(const YAML::Node& node, const std::string& name) {
    const fs::path file = dir_ / name;
    std::ofstream(file) << ToYamlText(node);
    return file;
  }
  fs::path dir_;
};

TEST_F(ScenarioResolutionTest, ResolvedScenarioRunsTheSameFromAnotherFolder) {
  const YAML::Node resolved = ResolveScenario(kSetup3);
  const Scenario original = LoadScenario(kSetup3);
  const Scenario moved = LoadScenario(Write(resolved, "moved.yaml"));
  EXPECT_EQ(moved.seed, original.seed);
  EXPECT_EQ(moved.vehicle_file, original.vehicle_file);
  ASSERT_TRUE(moved.network.xml.has_value());
  EXPECT_EQ(fs::canonical(moved.network.xml->edges), fs::canonical(original.network.xml->edges));
  const ScenarioSensors a = LoadScenarioSensors(original);
  const ScenarioSensors b = LoadScenarioSensors(moved);
  ASSERT_EQ(a.setup.sensors.size(), b.setup.sensors.size());
  ASSERT_EQ(ScenarioEstimators(moved).size(), ScenarioEstimators(original).size());
  EXPECT_EQ(ScenarioEstimators(moved)[0].label, "factor_graph");
  // Every option of the estimator is in the document, so a sweep can set any of them.
  EXPECT_TRUE(ScenarioValue(resolved, "estimators.factor_graph.window_s").IsDefined());
}

TEST_F(ScenarioResolutionTest, PathsNameSensorsAndEstimatorsById) {
  YAML::Node resolved = ResolveScenario(kSetup2);
  SetScenarioValue(resolved, "sensors.gnss_front.cep_m", YAML::Node(4.0));
  SetScenarioValue(resolved, "estimators.fg_paper_inputs.window_s", YAML::Node(0.5));
  SetScenarioValue(resolved, "sensors.imu.preset", YAML::Node("consumer"));
  SetScenarioValue(resolved, "ego.route[0]", YAML::Node("A1B1"));
  EXPECT_EQ(ScenarioValue(resolved, "sensors.gnss_front.cep_m").as<double>(), 4.0);
  const Scenario scenario = LoadScenario(Write(resolved, "changed.yaml"));
  const ScenarioSensors sensors = LoadScenarioSensors(scenario);
  EXPECT_EQ(ScenarioEstimators(scenario)[0].overrides->raw()["window_s"].as<double>(), 0.5);
  // The estimators' inputs (the paper's protocol) survive the resolution.
  EXPECT_EQ(ScenarioEstimators(scenario)[0].inputs,
            (std::vector<std::string>{"imu", "gnss_front", "lidar_roof"}));
  EXPECT_TRUE(ScenarioEstimators(scenario)[2].inputs.empty());
  EXPECT_EQ(scenario.ego.route[0].edge_id, "A1B1");
}

TEST_F(ScenarioResolutionTest, MissingPathsSayWhatExists) {
  YAML::Node resolved = ResolveScenario(kSetup2);
  const auto message = [&](const std::string& path) {
    try {
      SetScenarioValue(resolved, path, YAML::Node(1.0));
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("sensors.gnss_rear.cep_m").find("gnss_front"), std::string::npos);
  EXPECT_NE(message("estimators.kalman.window_s").find("fg_paper_inputs"), std::string::npos);
  EXPECT_NE(message("faults.gnss_outages[0].start_s").find("faults"), std::string::npos);
  EXPECT_NE(message("ego.route[99]").find("elements"), std::string::npos);
  EXPECT_NE(message("ego..loops").find("empty key"), std::string::npos);
  // Only inside an estimator's options is a missing section created (its loader checks it).
  EXPECT_NE(message("sensors.gnss_front.noise.sigma").find("noise"), std::string::npos);
  EXPECT_EQ(message("estimators.fg_paper_inputs.output_blend.max_s"), "no error");
  EXPECT_EQ(ScenarioValue(resolved, "estimators.fg_paper_inputs.output_blend.max_s").as<double>(),
            1.0);
  EXPECT_NE(message("estimators.fg_paper_inputs.gnss[0].x").find("gnss"), std::string::npos);
}

TEST_F(ScenarioResolutionTest, FingerprintFollowsContentNotLocation) {
  const YAML::Node resolved = ResolveScenario(kSetup3);
  const std::string print = ScenarioFingerprint(resolved);
  Write(resolved, "moved.yaml");
  EXPECT_EQ(ScenarioFingerprint(ResolveScenario(dir_ / "moved.yaml")), print);
  YAML::Node changed = YAML::Clone(resolved);
  SetScenarioValue(changed, "seed", YAML::Node(7));
  EXPECT_NE(ScenarioFingerprint(changed), print);
  EXPECT_EQ(print.find(fs::current_path().string() + "/scenarios"), std::string::npos);
}

}  // namespace
}  // namespace statebench::sim
