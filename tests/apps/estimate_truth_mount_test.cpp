// `statebench estimate` on a recorded simulated log scores like `statebench run`
// (docs/scenarios.md, `mismatch`: "Scores use the truth of the IMU as it is mounted"): with the
// paper scenario's mismatch the simulator's IMU mount is not the setup file's, and the log's
// manifest carries the mount the truth was written through (`truth_imu_mount`). Before,
// `estimate` scored against the setup file's mount: the same estimates gave another errors.csv
// and NEES (setup 1, seed 123: pose NEES 5.4 against run's 16.0).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "tests/file_text.hpp"
#include "tests/removed_at_exit.hpp"

namespace statebench::app {
namespace {

namespace fs = std::filesystem;

using testing::FileText;

int Statebench(const std::string& args, const fs::path& log) {
  const std::string command =
      std::string(STATEBENCH_BIN) + " " + args + " > " + log.string() + " 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(EstimateTruthMount, RecordedLogIsScoredAgainstTheMountedImuAsRunScoresIt) {
  const fs::path dir = testing::RemovedAtExit(
      fs::temp_directory_path() / ("statebench_truth_mount_" + std::to_string(getpid())));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string scenario = "scenarios/paper/setup2_quadricycle.yaml --seed 11 --duration 15";
  ASSERT_EQ(
      Statebench("run " + scenario + " --estimators fg_all_sensors --quiet --threads 1 --out " +
                     (dir / "run").string(),
                 dir / "run.log"),
      0)
      << FileText(dir / "run.log");
  ASSERT_EQ(Statebench("record " + scenario + " --quiet --out " + (dir / "log").string(),
                       dir / "record.log"),
            0)
      << FileText(dir / "record.log");
  const fs::path run = dir / "run" / "fg_all_sensors";
  ASSERT_EQ(Statebench("estimate " + (dir / "log").string() + " --config " +
                           (run / "estimator_config.yaml").string() + " --quiet --out " +
                           (dir / "estimate").string(),
                       dir / "estimate.log"),
            0)
      << FileText(dir / "estimate.log");

  // The mismatch turned the IMU: the manifest's mount is not the setup file's identity.
  const std::string manifest = FileText(dir / "log" / "log.yaml");
  ASSERT_NE(manifest.find("truth_imu_mount:"), std::string::npos) << manifest;
  ASSERT_EQ(manifest.find("rotation_wxyz: [1, 0, 0, 0]"), std::string::npos) << manifest;

  // Same estimates, same errors, same metrics.
  const std::string run_estimate = FileText(run / "estimate.csv");
  ASSERT_FALSE(run_estimate.empty());
  ASSERT_TRUE(run_estimate == FileText(dir / "estimate" / "estimate.csv")) << "estimates differ";
  EXPECT_TRUE(FileText(run / "errors.csv") == FileText(dir / "estimate" / "errors.csv"))
      << "errors.csv differ";
  std::ifstream a(run / "metrics.json"), b(dir / "estimate" / "metrics.json");
  const nlohmann::json ma = nlohmann::json::parse(a), mb = nlohmann::json::parse(b);
  EXPECT_EQ(ma["nees"], mb["nees"]);
  EXPECT_EQ(ma["rmse"], mb["rmse"]);
}

}  // namespace
}  // namespace statebench::app
