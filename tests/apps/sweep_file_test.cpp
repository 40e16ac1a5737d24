// The sweep file and its expansion: file:line errors before anything runs, grid and zip
// expansion, deterministic ids and draws, shards that partition the runs.
#include "apps/sweep_file.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "apps/sweep_expansion.hpp"
#include "core/error.hpp"

namespace statebench::app {
namespace {

namespace fs = std::filesystem;

class SweepFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("sweep_file_test_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A sweep over the paper's setup 2 (ctest runs in the source folder) with `body` appended.
  fs::path Write(const std::string& body) {
    const fs::path file = dir_ / "sweep.yaml";
    std::ofstream(file) << "name: test\n"
                        << "scenarios: ["
                        << fs::absolute("scenarios/paper/setup2_quadricycle.yaml").string() << "]\n"
                        << body;
    return file;
  }

  // The message of the InputError that loading and expanding `body` throws.
  std::string Error(const std::string& body) {
    try {
      ExpandSweep(LoadSweepFile(Write(body)), "v1");
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  }

  fs::path dir_;
};

TEST_F(SweepFileTest, GridExpansionWithIdsAndParameters) {
  const SweepSpec spec =
      LoadSweepFile(Write("seeds: {count: 3, first: 10}\n"
                          "estimators: [fg_paper_inputs]\n"
                          "axes:\n"
                          "  cep_m: {path: sensors.gnss_front.cep_m, values: [1.0, 2.0]}\n"
                          "  window_s: {path: estimators.fg_paper_inputs.window_s, range: {start: "
                          "0.5, stop: 1.5, step: 0.5}}\n"));
  const std::vector<SweepRun> runs = ExpandSweep(spec, "v1");
  ASSERT_EQ(runs.size(), 2u * 3u * 3u);
  EXPECT_EQ(runs[0].parameters, (std::vector<std::pair<std::string, std::string>>{
                                    {"cep_m", "1.0"}, {"window_s", "0.5"}}));
  EXPECT_EQ(runs[0].seed, 10u);
  EXPECT_EQ(runs[1].seed, 11u);
  EXPECT_EQ(runs[3].parameters[1].second, "1");
  EXPECT_EQ(runs.back().parameters[0].second, "2.0");
  EXPECT_EQ(runs[0].estimators, std::vector<std::string>{"fg_paper_inputs"});
  std::set<std::string> ids;
  for (const SweepRun& r : runs) ids.insert(r.id);
  EXPECT_EQ(ids.size(), runs.size());
  EXPECT_EQ(ExpandSweep(spec, "v1")[5].id, runs[5].id);
  EXPECT_NE(ExpandSweep(spec, "v2")[5].id, runs[5].id);
  EXPECT_NE(runs[0].scenario_yaml.find("cep_m: 1.0"), std::string::npos);
}

// Every sweep the repository ships (scenarios/sweeps/, the commands of docs/ and the closing
// notes) loads and expands as `statebench sweep` would check it before running anything.
TEST_F(SweepFileTest, EveryShippedSweepExpands) {
  int files = 0;
  for (const auto& entry : fs::directory_iterator("scenarios/sweeps")) {
    if (entry.path().extension() != ".yaml") continue;
    ++files;
    SCOPED_TRACE(entry.path().string());
    std::vector<SweepRun> runs;
    EXPECT_NO_THROW(runs = ExpandSweep(LoadSweepFile(entry.path()), "v1"));
    EXPECT_FALSE(runs.empty());
  }
  EXPECT_GT(files, 0);
}

// An axis that changes nothing the runs use (an option of an estimator the sweep does not run)
// would repeat runs under one id: refused.
TEST_F(SweepFileTest, AnAxisThatChangesNothingIsRefused) {
  const std::string e = Error(
      "seeds: [1]\nestimators: [ekf]\naxes:\n"
      "  window_s: {path: estimators.fg_paper_inputs.window_s, values: [1.0, 2.0]}\n");
  EXPECT_NE(e.find("sweep.yaml:6:"), std::string::npos) << e;
  EXPECT_NE(e.find("same run"), std::string::npos) << e;
}

TEST_F(SweepFileTest, ZipModeAndRandomDrawsFromTheRunSeed) {
  const SweepSpec spec = LoadSweepFile(
      Write("seeds: [1, 2]\n"
            "mode: zip\n"
            "axes:\n"
            "  cep_m: {path: sensors.gnss_front.cep_m, values: [1.0, 4.0]}\n"
            "  vertical: {path: sensors.gnss_front.vertical_sigma_m, values: [1.3, 5.1]}\n"
            "  dropout: {path: sensors.lidar_roof.dropout_probability, uniform: {low: 0.0, high: "
            "0.2}}\n"));
  const std::vector<SweepRun> runs = ExpandSweep(spec, "v1");
  ASSERT_EQ(runs.size(), 4u);
  EXPECT_EQ(runs[2].parameters[0].second, "4.0");
  EXPECT_EQ(runs[2].parameters[1].second, "5.1");
  // Same seed, same draw; another seed, another draw; inside the range.
  EXPECT_EQ(runs[0].parameters[2].second, runs[2].parameters[2].second);
  EXPECT_NE(runs[0].parameters[2].second, runs[1].parameters[2].second);
  const double draw = std::stod(runs[1].parameters[2].second);
  EXPECT_GE(draw, 0.0);
  EXPECT_LT(draw, 0.2);
}

TEST_F(SweepFileTest, ShardsPartitionTheRuns) {
  const std::vector<SweepRun> runs = ExpandSweep(
      LoadSweepFile(Write("seeds: {count: 7}\naxes:\n  cep_m: {path: sensors.gnss_front.cep_m, "
                          "values: [1, 2]}\n")),
      "v1");
  std::multiset<std::string> seen;
  for (int i = 1; i <= 3; ++i) {
    for (const SweepRun& r : ShardOf(runs, i, 3)) seen.insert(r.id);
  }
  std::multiset<std::string> all;
  for (const SweepRun& r : runs) all.insert(r.id);
  EXPECT_EQ(seen, all);
  EXPECT_EQ(ShardOf(runs, 1, 3).size(), 5u);
}

// An axis reaches every section of an estimator's options, also those its options file leaves at
// their defaults (scenarios/estimators/factor_graph.yaml lists neither output_blend nor
// imu_noise_estimation).
TEST_F(SweepFileTest, AxesReachSectionsTheOptionsFileLeavesOut) {
  const std::vector<SweepRun> runs = ExpandSweep(
      LoadSweepFile(Write("seeds: [1]\n"
                          "estimators: [fg_paper_inputs]\n"
                          "axes:\n"
                          "  blend: {path: estimators.fg_paper_inputs.output_blend.max_s, values: "
                          "[0.0, 0.5]}\n"
                          "  noise: {path: "
                          "estimators.fg_paper_inputs.imu_noise_estimation.enabled, values: "
                          "[false]}\n")),
      "v1");
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_NE(runs[1].scenario_yaml.find("output_blend"), std::string::npos);
  EXPECT_NE(runs[1].scenario_yaml.find("max_s: 0.5"), std::string::npos) << runs[1].scenario_yaml;
  EXPECT_NE(runs[0].scenario_yaml.find("imu_noise_estimation"), std::string::npos);
}

TEST_F(SweepFileTest, BadFilesNameTheirLine) {
  // Unknown path (a block map: its line is that of its first key).
  std::string e = Error(
      "seeds: [1]\naxes:\n  x: {path: sensors.gnss_front.cep_m, values: [1]}\n  y:\n    path: "
      "sensors.gnss_rear.cep_m\n    values: [1]\n");
  EXPECT_NE(e.find("sweep.yaml:7:"), std::string::npos) << e;
  EXPECT_NE(e.find("gnss_rear"), std::string::npos) << e;
  // The axis x above has no values: its own message.
  e = Error("seeds: [1]\naxes:\n  x: {path: sensors.gnss_front.cep_m}\n");
  EXPECT_NE(e.find("sweep.yaml:5:"), std::string::npos) << e;
  // Wrong value type: a word where the CEP is a number.
  e = Error("seeds: [1]\naxes:\n  x: {path: sensors.gnss_front.cep_m, values: [two]}\n");
  EXPECT_NE(e.find("sweep.yaml:5:"), std::string::npos) << e;
  EXPECT_NE(e.find("cep_m"), std::string::npos) << e;
  // A key the estimator does not have.
  e = Error("seeds: [1]\naxes:\n  x: {path: estimators.fg_paper_inputs.window_sx, values: [1]}\n");
  EXPECT_NE(e.find("sweep.yaml:5:"), std::string::npos) << e;
  EXPECT_NE(e.find("window_sx"), std::string::npos) << e;
  // A section the estimator does not have (the options file lists only some of the sections).
  e = Error(
      "seeds: [1]\naxes:\n  x: {path: estimators.fg_paper_inputs.output_blnd.max_s, values: "
      "[1]}\n");
  EXPECT_NE(e.find("sweep.yaml:5:"), std::string::npos) << e;
  EXPECT_NE(e.find("output_blnd"), std::string::npos) << e;
  // Empty axis.
  e = Error("seeds: [1]\naxes:\n  x: {path: sensors.gnss_front.cep_m, values: []}\n");
  EXPECT_NE(e.find("sweep.yaml:5:"), std::string::npos) << e;
  EXPECT_NE(e.find("empty"), std::string::npos) << e;
  // Seeds that are not integers.
  e = Error("seeds: [1, 2.5]\n");
  EXPECT_NE(e.find("sweep.yaml:3:"), std::string::npos) << e;
  e = Error("seeds: {count: three}\n");
  EXPECT_NE(e.find("sweep.yaml:3:"), std::string::npos) << e;
  // An estimator the scenario does not have.
  e = Error("seeds: [1]\nestimators: [ukf]\n");
  EXPECT_NE(e.find("sweep.yaml:4:"), std::string::npos) << e;
  // Zip with different lengths.
  e = Error(
      "seeds: [1]\nmode: zip\naxes:\n  a: {path: sensors.gnss_front.cep_m, values: [1, 2]}\n  b: "
      "{path: sensors.gnss_front.rate_hz, values: [1]}\n");
  EXPECT_NE(e.find("sweep.yaml:7:"), std::string::npos) << e;
  // A path through a field that is null in the base scenario.
  e = Error("seeds: [1]\naxes:\n  x: {path: faults.gnss_outages[0].start_s, values: [1]}\n");
  EXPECT_NE(e.find("sweep.yaml:5:"), std::string::npos) << e;
}

}  // namespace
}  // namespace statebench::app
