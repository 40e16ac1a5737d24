// The shared lidar odometry through the stage cache, end to end through the program: a second
// run of setup 1 with another window reads the first run's registrations (run.json counts the
// hit) and writes the estimate a run without the cache writes, byte for byte.
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

namespace statebench::app {
namespace {

namespace fs = std::filesystem;

class LidarOdometryCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("lidar_odometry_cache_test_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // `statebench run` of 3 s of setup 1 with one of its factor graphs (lidar.motion_prior: gyro).
  int Run(const std::string& estimator, const std::string& out, bool cached) {
    const std::string command =
        std::string(STATEBENCH_BIN) + " run " +
        fs::absolute("scenarios/paper/setup1_quadricycle.yaml").string() + " --duration 3" +
        " --estimators " + estimator + " --quiet --out " + (dir_ / out).string() +
        (cached ? " --cache " + (dir_ / "cache").string() : std::string()) + " > " +
        (dir_ / "output.log").string() + " 2>&1";
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  nlohmann::json LidarCounts(const std::string& out) {
    const nlohmann::json run = nlohmann::json::parse(testing::FileText(dir_ / out / "run.json"));
    return run["cache"].value("lidar_odometry", nlohmann::json::object());
  }

  fs::path dir_;
};

TEST_F(LidarOdometryCacheTest, ASecondWindowReadsTheRegistrationsAndWritesTheSameEstimate) {
  ASSERT_EQ(Run("fg_w1_kin", "first", true), 0) << testing::FileText(dir_ / "output.log");
  EXPECT_EQ(LidarCounts("first").value("misses", -1), 1);
  EXPECT_EQ(LidarCounts("first").value("hits", -1), 0);

  ASSERT_EQ(Run("fg_w2_kin", "second", true), 0) << testing::FileText(dir_ / "output.log");
  EXPECT_EQ(LidarCounts("second").value("hits", -1), 1);
  EXPECT_EQ(LidarCounts("second").value("misses", -1), 0);

  ASSERT_EQ(Run("fg_w2_kin", "fresh", false), 0) << testing::FileText(dir_ / "output.log");
  const std::string fresh = testing::FileText(dir_ / "fresh" / "fg_w2_kin" / "estimate.csv");
  ASSERT_GT(fresh.size(), 1000u);
  EXPECT_TRUE(testing::FileText(dir_ / "second" / "fg_w2_kin" / "estimate.csv") == fresh);
  // The registrations were used: the lidar's factors are in the estimate's diagnostics.
  const nlohmann::json diagnostics =
      nlohmann::json::parse(testing::FileText(dir_ / "second" / "fg_w2_kin" / "diagnostics.json"));
  EXPECT_GT(diagnostics["sensors"]["lidar_roof"]["events"].value("registered", 0), 4);
}

}  // namespace
}  // namespace statebench::app
