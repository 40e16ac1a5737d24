// The regression gate end to end: ten seeds of the no-lidar setup-1 scenario with the default
// factor graph (base), the same configuration run again, and a candidate that is worse by
// construction (it solves once a second instead of ten times). `statebench compare` with the
// checked-in thresholds says "worse" on position RMSE and exits 1 for the candidate, and "no
// significant change" on every metric with exit code 0 for the same configuration.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace statebench::app {
namespace {

namespace fs = std::filesystem;

struct Outcome {
  int exit_code = -1;
  std::string output;
};

class CompareCommandTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("compare_command_test_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  Outcome Statebench(const std::string& args) {
    const fs::path log = dir_ / "output.log";
    const int status = std::system(
        (std::string(STATEBENCH_BIN) + " " + args + " > " + log.string() + " 2>&1").c_str());
    std::ifstream in(log);
    std::stringstream text;
    text << in.rdbuf();
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text.str()};
  }

  // A sweep of 10 seeds of `scenario` (15 s each) into dir_/name.
  void Sweep(const fs::path& scenario, const std::string& name) {
    std::ofstream(dir_ / (name + ".yaml"))
        << "name: " << name << "\nscenarios: [" << scenario.string() << "]\n"
        << "seeds: {count: 10, first: 101}\nduration_s: 15\nestimators: [factor_graph]\n";
    const Outcome o = Statebench("sweep " + (dir_ / (name + ".yaml")).string() + " --out " +
                                 (dir_ / name).string() + " --jobs 2 --cache " +
                                 (dir_ / "cache").string());
    ASSERT_EQ(o.exit_code, 0) << o.output;
  }

  fs::path dir_;
};

TEST_F(CompareCommandTest, WorseByConstructionFailsTheGateAndTheSameConfigurationPasses) {
  const fs::path base = fs::absolute("scenarios/extra/setup1_quadricycle_nolidar.yaml");
  // The candidate: the same scenario (same name, so runs pair) with the factor graph solving
  // at 1 Hz.
  std::ifstream in(base);
  std::stringstream text;
  text << in.rdbuf();
  std::string scenario = text.str();
  const auto replace = [&scenario](const std::string& from, const std::string& to) {
    scenario.replace(scenario.find(from), from.size(), to);
  };
  replace("vehicle: quadricycle.yaml", "vehicle: " + fs::absolute("scenarios/vehicles/quadricycle.yaml").string());
  replace("sensors: setup1_quadricycle_nolidar.yaml",
          "sensors: " + fs::absolute("scenarios/setups/setup1_quadricycle_nolidar.yaml").string());
  scenario += "\nestimators:\n  - {name: factor_graph, type: factor_graph, "
              "overrides: {solve_interval_s: 1.0}}\n";
  std::ofstream(dir_ / "slow_solve.yaml") << scenario;

  Sweep(base, "base");
  Sweep(base, "again");
  Sweep(dir_ / "slow_solve.yaml", "candidate");

  const Outcome worse = Statebench("compare " + (dir_ / "base").string() + " " +
                                   (dir_ / "candidate").string() + " --out " +
                                   (dir_ / "compare.html").string());
  EXPECT_EQ(worse.exit_code, 1) << worse.output;
  EXPECT_NE(worse.output.find("| factor_graph | rmse.position_m | 10 |"), std::string::npos)
      << worse.output;
  const std::size_t row = worse.output.find("| factor_graph | rmse.position_m |");
  EXPECT_NE(worse.output.find("**worse**", row), std::string::npos) << worse.output;
  EXPECT_LT(worse.output.find("**worse**", row), worse.output.find('\n', row)) << worse.output;
  EXPECT_TRUE(fs::file_size(dir_ / "compare.html") > 1000);

  const Outcome same =
      Statebench("compare " + (dir_ / "base").string() + " " + (dir_ / "again").string());
  EXPECT_EQ(same.exit_code, 0) << same.output;
  EXPECT_EQ(same.output.find("**worse**"), std::string::npos) << same.output;
  EXPECT_EQ(same.output.find("**better**"), std::string::npos) << same.output;
  EXPECT_NE(same.output.find("0 worse, 0 better"), std::string::npos) << same.output;

  // Two estimators of one store: an estimator no run has is bad input naming the store and
  // what it has; a malformed pair is bad input too.
  const Outcome missing = Statebench("compare " + (dir_ / "base").string() + " " +
                                     (dir_ / "base").string() + " --estimators ekf,factor_graph");
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find("no run has the estimator 'ekf' (it has: factor_graph)"),
            std::string::npos)
      << missing.output;
  EXPECT_EQ(Statebench("compare " + (dir_ / "base").string() + " " + (dir_ / "base").string() +
                       " --estimators factor_graph")
                .exit_code,
            2);
  // The same estimator against itself through --estimators: every pair equal.
  const Outcome itself =
      Statebench("compare " + (dir_ / "base").string() + " " + (dir_ / "again").string() +
                 " --estimators factor_graph,factor_graph");
  EXPECT_EQ(itself.exit_code, 0) << itself.output;
  EXPECT_NE(itself.output.find("| factor_graph -> factor_graph | rmse.position_m | 10 |"),
            std::string::npos)
      << itself.output;

  // Nothing in common: a clear message and exit code 2.
  std::ofstream(dir_ / "other.yaml") << "name: other\nscenarios: [" << base.string()
                                     << "]\nseeds: [7]\nduration_s: 3\nestimators: [ekf]\n";
  ASSERT_EQ(Statebench("sweep " + (dir_ / "other.yaml").string() + " --out " +
                       (dir_ / "other").string() + " --no-cache")
                .exit_code,
            0);
  const Outcome none =
      Statebench("compare " + (dir_ / "base").string() + " " + (dir_ / "other").string());
  EXPECT_EQ(none.exit_code, 2) << none.output;
  EXPECT_NE(none.output.find("no run of the base pairs"), std::string::npos) << none.output;
}

}  // namespace
}  // namespace statebench::app
