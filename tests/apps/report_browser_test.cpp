// The HTML reports in a real browser: a small sweep (3 seeds x 2 GNSS noise levels, 10 s runs,
// factor graph and EKF) and a candidate solving once a second; the run report of one run, the
// sweep report with its worst runs' reports, and the compare report, each opened in headless
// Chromium by tests/apps/report_browser_check.py, which fails on any console error, failed or
// outside resource load, or a plot element that drew nothing.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

namespace statebench::app {
namespace {

namespace fs = std::filesystem;

struct Outcome {
  int exit_code = -1;
  std::string output;
};

class ReportBrowserTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("report_browser_test_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  Outcome Shell(const std::string& command) {
    const fs::path log = dir_ / "output.log";
    const int status = std::system((command + " > " + log.string() + " 2>" +
                                    (dir_ / "stderr.log").string()).c_str());
    std::ifstream in(log), err(dir_ / "stderr.log");
    std::stringstream text;
    text << in.rdbuf() << err.rdbuf();
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text.str()};
  }
  Outcome Statebench(const std::string& args) {
    return Shell(std::string(STATEBENCH_BIN) + " " + args);
  }

  void Sweep(const fs::path& scenario, const std::string& name) {
    std::ofstream(dir_ / (name + ".yaml"))
        << "name: " << name << "\nscenarios: [" << scenario.string() << "]\n"
        << "seeds: {count: 3, first: 11}\nduration_s: 10\n"
        << "axes:\n  cep_m: {path: sensors.gnss_front.cep_m, values: [0.012, 0.05]}\n";
    const Outcome o = Statebench("sweep " + (dir_ / (name + ".yaml")).string() + " --out " +
                                 (dir_ / name).string() + " --jobs 2 --cache " +
                                 (dir_ / "cache").string());
    ASSERT_EQ(o.exit_code, 0) << o.output;
  }

  fs::path dir_;
};

TEST_F(ReportBrowserTest, RunSweepAndCompareReportsRenderEveryPlotWithoutErrors) {
  const fs::path scenario = fs::absolute("scenarios/extra/setup1_quadricycle_nolidar.yaml");
  std::ifstream in(scenario);
  std::stringstream text;
  text << in.rdbuf();
  std::string candidate = text.str();
  const auto replace = [&candidate](const std::string& from, const std::string& to) {
    candidate.replace(candidate.find(from), from.size(), to);
  };
  replace("vehicle: quadricycle.yaml",
          "vehicle: " + fs::absolute("scenarios/vehicles/quadricycle.yaml").string());
  replace("sensors: setup1_quadricycle_nolidar.yaml",
          "sensors: " + fs::absolute("scenarios/setups/setup1_quadricycle_nolidar.yaml").string());
  candidate += "\nestimators:\n  - {name: factor_graph, type: factor_graph, "
               "overrides: {solve_interval_s: 1.0}}\n  - ekf\n";
  std::ofstream(dir_ / "slow_solve.yaml") << candidate;
  Sweep(scenario, "base");
  Sweep(dir_ / "slow_solve.yaml", "candidate");

  fs::path run_dir;
  for (const auto& entry : fs::directory_iterator(dir_ / "base" / "runs")) run_dir = entry.path();
  ASSERT_FALSE(run_dir.empty());
  const Outcome run = Statebench("report " + run_dir.string() + " --out " +
                                 (dir_ / "run.html").string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const Outcome sweep = Statebench("report " + (dir_ / "base").string() + " --out " +
                                   (dir_ / "sweep.html").string() + " --worst 1");
  ASSERT_EQ(sweep.exit_code, 0) << sweep.output;
  const Outcome compare = Statebench("compare " + (dir_ / "base").string() + " " +
                                     (dir_ / "candidate").string() + " --out " +
                                     (dir_ / "compare.html").string());
  ASSERT_TRUE(compare.exit_code == 0 || compare.exit_code == 1) << compare.output;

  std::string pages = (dir_ / "run.html").string() + " " + (dir_ / "sweep.html").string() + " " +
                      (dir_ / "compare.html").string();
  int run_reports = 0;
  for (const auto& entry : fs::directory_iterator(dir_ / "sweep_runs")) {
    pages += " " + entry.path().string();
    ++run_reports;
  }
  EXPECT_GE(run_reports, 1);
  const char* source = std::getenv("STATEBENCH_SOURCE_DIR");
  const Outcome check = Shell("/usr/bin/python3 " +
                              (fs::path(source ? source : ".") / "tests" / "apps" /
                               "report_browser_check.py").string() + " " + pages);
  EXPECT_EQ(check.exit_code, 0) << check.output;

  // One JSON line per page: no problem, and the plots each report must have.
  std::map<std::string, int> plots;
  std::istringstream lines(check.output);
  for (std::string line; std::getline(lines, line);) {
    if (line.empty() || line[0] != '{') continue;
    const nlohmann::json page = nlohmann::json::parse(line);
    EXPECT_TRUE(page["problems"].empty()) << line;
    plots[fs::path(page["file"].get<std::string>()).filename().string()] =
        page.value("plots", 0);
  }
  // Run: trajectory, errors, NEES, verdicts of each of the two estimators, solve times.
  EXPECT_EQ(plots["run.html"], 6) << check.output;
  // Sweep: the seven default metrics and the ANEES.
  EXPECT_EQ(plots["sweep.html"], 8) << check.output;
  // Compare: one figure per metric of the thresholds file (nine).
  EXPECT_EQ(plots["compare.html"], 9) << check.output;
  EXPECT_EQ(plots.size(), 3u + static_cast<std::size_t>(run_reports)) << check.output;
}

}  // namespace
}  // namespace statebench::app
