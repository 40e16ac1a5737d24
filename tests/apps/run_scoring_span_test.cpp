// `statebench run` scores every estimator of a run over the same span (issue 11): the factor
// graph and the EKF of the no-lidar setup-1 scenario start at different times, and both
// metrics.json files name the same span, from the later of the two first estimates; the earlier
// starter's estimates before it are skipped, not scored.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

namespace statebench::app {
namespace {

namespace fs = std::filesystem;

nlohmann::json ReadJson(const fs::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

// Rows of a CSV file after its header that contain `text` ("" counts every row).
int CountRows(const fs::path& csv, const std::string& text) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  int n = 0;
  while (std::getline(in, line)) n += line.find(text) != std::string::npos;
  return n;
}

// The stamp of the first row of an estimate.csv, s.
double FirstEstimateS(const fs::path& csv) {
  std::ifstream in(csv);
  std::string header, row;
  std::getline(in, header);
  std::getline(in, row);
  return std::stod(row.substr(0, row.find(','))) * 1e-9;
}

TEST(RunScoringSpan, FactorGraphAndEkfShareTheirScoringSpan) {
  const fs::path dir = fs::temp_directory_path() / ("statebench_span_test_" + std::to_string(getpid()));
  fs::remove_all(dir);
  // Removed however the test ends (a failed assertion returns early).
  struct RemoveOnExit {
    fs::path dir;
    ~RemoveOnExit() {
      std::error_code ec;
      fs::remove_all(dir, ec);
      fs::remove(dir.string() + ".log", ec);
    }
  } cleanup{dir};
  const std::string command = std::string(STATEBENCH_BIN) +
                              " run scenarios/extra/setup1_quadricycle_nolidar.yaml --duration 20"
                              " --estimators factor_graph,ekf --quiet --out " +
                              dir.string() + " > " + (dir.string() + ".log") + " 2>&1";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << command;
  const nlohmann::json fg = ReadJson(dir / "factor_graph" / "metrics.json");
  const nlohmann::json ekf = ReadJson(dir / "ekf" / "metrics.json");
  const double fg_start = FirstEstimateS(dir / "factor_graph" / "estimate.csv");
  const double ekf_start = FirstEstimateS(dir / "ekf" / "estimate.csv");
  std::printf("first estimates: factor graph %.2f s, EKF %.2f s; span from %.2f s\n", fg_start,
              ekf_start, fg["availability"]["span_begin_s"].get<double>());
  ASSERT_NE(fg_start, ekf_start) << "the test needs two different starts";
  const double span = fg["availability"]["span_begin_s"];
  EXPECT_EQ(span, ekf["availability"]["span_begin_s"].get<double>());
  EXPECT_NEAR(span, std::max(fg_start, ekf_start), 1e-6);
  EXPECT_EQ(fg["availability"]["span_imu_stamps"], ekf["availability"]["span_imu_stamps"]);
  // The earlier starter's estimates before the span are skipped; the later one has none there.
  const nlohmann::json& early = fg_start < ekf_start ? fg : ekf;
  const nlohmann::json& late = fg_start < ekf_start ? ekf : fg;
  EXPECT_GT(early["skipped"].get<int>(), 0);
  EXPECT_EQ(late["skipped"].get<int>(), 0);
  EXPECT_EQ(early["compared"].get<int>(), early["availability"]["span_finite_estimates"].get<int>());

  // The run's details for the report (docs/estimate-format.md, "Run details"): an errors.csv
  // row per compared estimate, a verdict row per accepted or rejected GNSS fix as the
  // diagnostics count them, the reference from the first output epoch, every fix of the stream.
  for (const std::string label : {"factor_graph", "ekf"}) {
    const nlohmann::json metrics = ReadJson(dir / label / "metrics.json");
    const nlohmann::json diagnostics = ReadJson(dir / label / "diagnostics.json");
    EXPECT_EQ(CountRows(dir / label / "errors.csv", ""), metrics["compared"].get<int>()) << label;
    const nlohmann::json& gnss = diagnostics["sensors"]["gnss_front"];
    int rejected = 0;
    for (const auto& [reason, n] : gnss["rejected"].items()) rejected += n.get<int>();
    EXPECT_EQ(CountRows(dir / label / "measurements.csv", ",gnss_front,"),
              gnss["accepted"].get<int>() + rejected)
        << label;
  }
  EXPECT_EQ(CountRows(dir / "reference.csv", ""), 2001);  // 0 .. 20 s at 100 Hz
  EXPECT_EQ(CountRows(dir / "gnss_fixes.csv", ",gnss_front,"),
            ReadJson(dir / "ekf" / "diagnostics.json")["sensors"]["gnss_front"]["received"].get<int>());
}

}  // namespace
}  // namespace statebench::app
