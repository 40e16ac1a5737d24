// The stage cache gives the same stream and truth, bit for bit, as a fresh simulation: the
// paper's setup 3 (two 16-beam lidars, RTK GNSS with an outage, IMU) run fresh, then through an
// empty cache (every stage computed and recorded), then again (every stage read back: no SUMO,
// no vehicle model, no raycast).
#include "simulator/cached_stages.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "simulator/sensor_run.hpp"
#include "simulator/sumo_result_io.hpp"
#include "tests/sensors/measurement_bytes.hpp"
#include "tests/simulator/sumo_test_support.hpp"

namespace statebench::sim {
namespace {

namespace fs = std::filesystem;

class CachedStagesTest : public ::testing::Test {
 protected:
  // One folder per test: ctest runs the tests of this file in parallel processes.
  void SetUp() override {
    dir_ = sim::testing::FreshWorkDir(
        "cached_stages", ::testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The whole stream as bytes, then every truth sample's fields and the truth summary's.
  std::string Stream(const std::string& name, StageCache* cache) {
    Scenario scenario = LoadScenario(sim::testing::SourceDir() / "scenarios/paper/setup3_shuttle.yaml");
    scenario.duration_s = 3.0;
    SensorRunOptions options;
    if (cache) options.cache = {cache, "test build"};
    SensorRun run(scenario, dir_ / name, options);
    std::string bytes, truth;
    run.SetTruthObserver([&truth](const TruthSample& s) { truth += TruthBytes(s); });
    while (const auto m = run.Next()) bytes += statebench::testing::MeasurementBytes(*m);
    EXPECT_GT(truth.size(), 2900u * sizeof(double));
    const TruthSummary& summary = run.truth().summary();
    for (const double v :
         {summary.duration_s, summary.distance_m, summary.max_speed_mps,
          summary.max_lateral_accel_mps2, summary.max_yaw_rate_radps, summary.rms_lateral_error_m,
          summary.max_lateral_error_m, summary.max_longitudinal_error_m}) {
      truth += Bytes(&v, 1);
    }
    return bytes + truth;
  }

  static std::string Bytes(const double* v, std::size_t n) {
    return std::string(reinterpret_cast<const char*>(v), n * sizeof(double));
  }

  // Every field of a truth sample, written out here (not by the cache's own writer).
  static std::string TruthBytes(const TruthSample& s) {
    const FrameKinematics& b = s.body;
    std::string bytes(reinterpret_cast<const char*>(&s.t_ns), sizeof(s.t_ns));
    bytes += Bytes(b.T_world_frame.rotation().coeffs().data(), 4);
    bytes += Bytes(b.T_world_frame.translation().data(), 3);
    for (const Vec3* v : {&b.v_world, &b.a_world, &b.omega_frame, &b.alpha_frame}) {
      bytes += Bytes(v->data(), 3);
    }
    bytes += Bytes(&s.steering_front_rad, 1) + Bytes(&s.steering_rear_rad, 1);
    bytes += Bytes(s.wheel_omega_radps.data(), 4);
    bytes += Bytes(&s.sideslip_rad, 1) + Bytes(&s.distance_m, 1);
    return bytes;
  }

  fs::path dir_;
};

TEST_F(CachedStagesTest, CachedStreamsAreTheFreshStreamBitForBit) {
  const std::string fresh = Stream("fresh", nullptr);
  ASSERT_GT(fresh.size(), 100000u);

  StageCache first(dir_ / "cache", 0);
  EXPECT_EQ(Stream("recorded", &first), fresh);
  EXPECT_EQ(first.counts().at("sumo").misses, 1);
  EXPECT_EQ(first.counts().at("vehicle").misses, 1);
  EXPECT_EQ(first.counts().at("sensors").misses, 4);  // imu, gnss, two lidars
  EXPECT_EQ(first.counts().at("sensors").hits, 0);

  StageCache second(dir_ / "cache", 0);
  EXPECT_EQ(Stream("replayed", &second), fresh);
  EXPECT_EQ(second.counts().at("sumo").hits, 1);
  EXPECT_EQ(second.counts().at("vehicle").hits, 1);
  EXPECT_EQ(second.counts().at("sensors").hits, 4);
  EXPECT_EQ(second.counts().at("sensors").misses, 0);
  // The run folder looks the same: the network file is there.
  EXPECT_TRUE(fs::exists(dir_ / "replayed" / "sumo" / "net.net.xml"));
}

TEST_F(CachedStagesTest, SumoResultRoundTripsExactly) {
  Scenario scenario = LoadScenario(sim::testing::SourceDir() / "scenarios/paper/setup3_shuttle.yaml");
  scenario.duration_s = 2.0;
  const SumoResult result = SimulateSumo(scenario, EgoVehicleType{}, dir_ / "sumo");
  WriteSumoResult(result, dir_ / "result.bin");
  EXPECT_TRUE(ReadSumoResult(dir_ / "result.bin") == result);
  // A truncated file is an error, not a shorter result.
  fs::resize_file(dir_ / "result.bin", fs::file_size(dir_ / "result.bin") / 2);
  EXPECT_THROW(ReadSumoResult(dir_ / "result.bin"), InputError);
}

TEST_F(CachedStagesTest, KeysFollowWhatTheStageDependsOn) {
  Scenario scenario = LoadScenario(sim::testing::SourceDir() / "scenarios/paper/setup3_shuttle.yaml");
  const std::string key = *TruthStageKey(scenario, {}, "build a");
  EXPECT_EQ(*TruthStageKey(scenario, {}, "build a"), key);
  EXPECT_NE(*TruthStageKey(scenario, {}, "build b"), key);
  Scenario other_seed = scenario;
  other_seed.seed += 1;
  EXPECT_NE(*TruthStageKey(other_seed, {}, "build a"), key);
  const ScenarioSensors sensors = LoadScenarioSensors(scenario);
  const auto keys = SensorStreamKeys(scenario, sensors, key, scenario.seed, "build a");
  const auto reseeded = SensorStreamKeys(scenario, sensors, key, scenario.seed + 1, "build a");
  ASSERT_EQ(keys.size(), 4u);
  for (const auto& [id, k] : keys) EXPECT_NE(reseeded.at(id), k) << id;
}

// The key of everything the estimators are fed (the shared lidar odometry's cache entries hang
// on it): it follows the build, the seeds, the faults and the mismatch, and not the estimators.
TEST_F(CachedStagesTest, EstimatorInputsKeyFollowsTheStreamsNotTheEstimators) {
  const Scenario scenario =
      LoadScenario(sim::testing::SourceDir() / "scenarios/paper/setup3_shuttle.yaml");
  ASSERT_TRUE(scenario.faults.has_value());
  ASSERT_TRUE(scenario.mismatch.has_value());
  const ScenarioSensors sensors = LoadScenarioSensors(scenario);
  const auto key = [&](const Scenario& s, std::uint64_t sensor_seed, const std::string& build) {
    return *EstimatorInputsKey(s, sensors, {}, sensor_seed, build);
  };
  const std::string base = key(scenario, scenario.seed, "build a");
  EXPECT_EQ(key(scenario, scenario.seed, "build a"), base);
  Scenario no_estimators = scenario;
  no_estimators.estimators.clear();
  EXPECT_EQ(key(no_estimators, scenario.seed, "build a"), base);

  EXPECT_NE(key(scenario, scenario.seed, "build b"), base);
  EXPECT_NE(key(scenario, scenario.seed + 1, "build a"), base);
  Scenario no_faults = scenario;
  no_faults.faults.reset();
  EXPECT_NE(key(no_faults, scenario.seed, "build a"), base);
  Scenario other_clocks = scenario;
  other_clocks.mismatch->clock_offset_sigma_s += 0.001;
  EXPECT_NE(key(other_clocks, scenario.seed, "build a"), base);
  Scenario longer = scenario;
  longer.duration_s += 1.0;
  EXPECT_NE(key(longer, scenario.seed, "build a"), base);
}

}  // namespace
}  // namespace statebench::sim
