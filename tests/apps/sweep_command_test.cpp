// `statebench sweep` end to end, through the program itself: a sweep killed with SIGKILL and
// resumed, and a sweep run in three shards and merged, give the same store as one uninterrupted
// sweep; a failing run is recorded and the sweep goes on; a bad sweep file stops everything
// before any run. Short runs of the no-lidar setup-1 scenario (bit-reproducible).
#include <gtest/gtest.h>
#include <signal.h>
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "apps/thread_limit.hpp"
#include "core/error.hpp"
#include "reports/results_store.hpp"

namespace statebench::app {
namespace {

namespace fs = std::filesystem;

struct Outcome {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

class SweepCommandTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("sweep_command_test_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    std::ofstream(dir_ / "window.yaml")
        << "name: window\n"
        << "scenarios: [" << fs::absolute("scenarios/extra/setup1_quadricycle_nolidar.yaml").string()
        << "]\n"
        << "seeds: [5, 6]\n"
        << "duration_s: 6\n"
        << "axes:\n"
        << "  window_s: {path: estimators.factor_graph.window_s, values: [1.0, 2.0]}\n";
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static Outcome Statebench(const std::string& args) {
    const fs::path log = dir_ / "output.log";
    const std::string command =
        std::string(STATEBENCH_BIN) + " " + args + " > " + log.string() + " 2>&1";
    const int status = std::system(command.c_str());
    std::ifstream in(log);
    std::stringstream text;
    text << in.rdbuf();
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text.str()};
  }

  static std::string Sweep(const std::string& out, const std::string& extra = "") {
    return "sweep " + (dir_ / "window.yaml").string() + " --out " + (dir_ / out).string() +
           " --jobs 2 --cache " + (dir_ / "cache").string() + " " + extra;
  }

  // Run id -> status, then "estimator metric" -> value.
  using StoreContents = std::map<std::string, std::pair<std::string, std::map<std::string, double>>>;
  static StoreContents Contents(const fs::path& store_file) {
    // Read-only: the test polls a store a sweep is creating and writing.
    const reports::ResultsStore store(store_file, reports::ResultsStore::Access::kRead);
    StoreContents contents;
    for (const reports::RunRecord& r : store.Runs()) {
      auto& [status, metrics] = contents[r.id];
      status = r.status;
      for (const reports::MetricValue& m : r.metrics) {
        if (!reports::IsTimingMetric(m.name)) metrics[m.estimator + " " + m.name] = m.value;
      }
    }
    return contents;
  }

  // The first difference, or "" when the stores hold the same runs with the same metrics, bit
  // for bit (timing figures aside).
  static std::string Difference(const StoreContents& a, const StoreContents& b) {
    if (a.size() != b.size()) {
      return std::to_string(a.size()) + " runs vs " + std::to_string(b.size());
    }
    for (const auto& [id, run] : a) {
      const auto it = b.find(id);
      if (it == b.end()) return "run " + id + " is missing";
      if (run.first != it->second.first) return "run " + id + ": status " + run.first;
      if (run.second.size() != it->second.second.size()) return "run " + id + ": metric count";
      for (const auto& [name, x] : run.second) {
        const auto other = it->second.second.find(name);
        if (other == it->second.second.end()) return "run " + id + ": no " + name;
        const double y = other->second;
        if (!(x == y || (std::isnan(x) && std::isnan(y)))) {
          return "run " + id + ": " + name + " " + std::to_string(x) + " vs " + std::to_string(y);
        }
      }
    }
    return "";
  }

  static fs::path dir_;
};

fs::path SweepCommandTest::dir_;

TEST_F(SweepCommandTest, KilledAndResumedOrShardedSweepsGiveTheSameStore) {
  const Outcome whole = Statebench(Sweep("whole"));
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  const auto expected = Contents(dir_ / "whole" / "results.db");
  ASSERT_EQ(expected.size(), 4u);
  for (const auto& [id, run] : expected) {
    EXPECT_EQ(run.first, "ok") << id;
    EXPECT_GT(run.second.size(), 20u) << id;
  }
  // The first runs of each seed simulated SUMO; the others reused it.
  EXPECT_NE(whole.output.find("cache sumo"), std::string::npos) << whole.output;

  // Killed with SIGKILL once the first run is in the store, then resumed.
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const std::string out = (dir_ / "killed").string();
    const std::string sweep = (dir_ / "window.yaml").string();
    const std::string cache = (dir_ / "cache").string();
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, STDOUT_FILENO);
    dup2(null, STDERR_FILENO);
    execl(STATEBENCH_BIN, STATEBENCH_BIN, "sweep", sweep.c_str(), "--out", out.c_str(), "--jobs",
          "1", "--cache", cache.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  const fs::path killed_store = dir_ / "killed" / "results.db";
  for (int i = 0; i < 6000; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    std::error_code ec;
    try {  // the sweep may still be creating the store: no table yet is no run yet
      if (fs::exists(killed_store, ec) && !Contents(killed_store).empty()) break;
    } catch (const statebench::InputError&) {
    }
  }
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  const std::size_t before_resume = Contents(killed_store).size();
  EXPECT_GE(before_resume, 1u);
  EXPECT_LT(before_resume, 4u) << "the sweep ended before it was killed";
  const Outcome resumed = Statebench(Sweep("killed", "--resume"));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_EQ(Difference(Contents(killed_store), expected), "");

  // Three shards, merged.
  std::string stores;
  for (int i = 1; i <= 3; ++i) {
    const std::string shard = "shard" + std::to_string(i);
    const Outcome part = Statebench(Sweep(shard, "--shard " + std::to_string(i) + "/3"));
    ASSERT_EQ(part.exit_code, 0) << part.output;
    stores += (dir_ / shard / "results.db").string() + " ";
  }
  const Outcome merged =
      Statebench("results merge " + stores + "--out " + (dir_ / "merged.db").string());
  ASSERT_EQ(merged.exit_code, 0) << merged.output;
  EXPECT_EQ(Difference(Contents(dir_ / "merged.db"), expected), "");

  // The summary groups by the axis.
  const Outcome summary = Statebench("results summary " + (dir_ / "merged.db").string() +
                                     " --by window_s --format csv");
  ASSERT_EQ(summary.exit_code, 0) << summary.output;
  EXPECT_NE(summary.output.find("factor_graph,1.0,2,0,0,rmse.x_m,2,"), std::string::npos)
      << summary.output;
}

TEST_F(SweepCommandTest, AFailingRunIsRecordedAndTheSweepGoesOn) {
  std::ofstream(dir_ / "failing.yaml")
      << "name: failing\n"
      << "scenarios: [" << fs::absolute("scenarios/extra/setup1_quadricycle_nolidar.yaml").string()
      << "]\n"
      << "seeds: [5]\n"
      << "duration_s: 3\n"
      << "estimators: [ekf]\n"
      << "axes:\n"
      << "  depart: {path: ego.depart_pos_m, values: [10.0, 99999.0]}\n";
  const Outcome outcome = Statebench("sweep " + (dir_ / "failing.yaml").string() + " --out " +
                                     (dir_ / "failing").string() + " --jobs 2 --no-cache");
  EXPECT_EQ(outcome.exit_code, 1) << outcome.output;
  EXPECT_NE(outcome.output.find("1 runs ok, 1 failed"), std::string::npos) << outcome.output;
  const reports::ResultsStore store(dir_ / "failing" / "results.db");
  const std::vector<reports::RunRecord> runs = store.Runs();
  ASSERT_EQ(runs.size(), 2u);
  int failed = 0;
  for (const reports::RunRecord& r : runs) {
    if (r.status != "failed") continue;
    ++failed;
    EXPECT_EQ(r.parameters[0].second, "99999.0");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.error.find("depart"), std::string::npos) << r.error;
  }
  EXPECT_EQ(failed, 1);
  // Two runs at a time share the cores: each got max(1, cores / 2) threads.
  for (const reports::RunRecord& r : runs) {
    if (r.status != "ok") continue;
    std::ifstream in(dir_ / "failing" / "runs" / r.id / "run.json");
    const nlohmann::json run = nlohmann::json::parse(in);
    EXPECT_EQ(run["cpu"]["threads"].get<std::uint64_t>(), ThreadsPerJob(2));
  }
}

TEST_F(SweepCommandTest, ARunWhoseEstimatorNeverStartsIsCompleteAndItsFiguresUnavailable) {
  // One second: the EKF has no GNSS course yet; its run exits with 3 (an estimator without an
  // estimate) and is recorded as a complete run whose EKF figures are unavailable.
  std::ofstream(dir_ / "short.yaml")
      << "name: short\n"
      << "scenarios: [" << fs::absolute("scenarios/extra/setup1_quadricycle_nolidar.yaml").string()
      << "]\n"
      << "seeds: [5]\n"
      << "duration_s: 1\n"
      << "estimators: [ekf]\n";
  const Outcome outcome = Statebench("sweep " + (dir_ / "short.yaml").string() + " --out " +
                                     (dir_ / "short").string() + " --no-cache");
  EXPECT_EQ(outcome.exit_code, 0) << outcome.output;
  const std::vector<reports::RunRecord> runs =
      reports::ResultsStore(dir_ / "short" / "results.db").Runs();
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].status, "ok");
  EXPECT_EQ(runs[0].exit_code, 3);
  const Outcome summary =
      Statebench("results summary " + (dir_ / "short" / "results.db").string() + " --format csv");
  ASSERT_EQ(summary.exit_code, 0) << summary.output;
  EXPECT_NE(summary.output.find("ekf,1,0,1,"), std::string::npos)
      << summary.output;  // runs, failed, no estimate
}

TEST_F(SweepCommandTest, ABadSweepFileStopsBeforeAnyRun) {
  std::ofstream(dir_ / "bad.yaml")
      << "name: bad\n"
      << "scenarios: [" << fs::absolute("scenarios/extra/setup1_quadricycle_nolidar.yaml").string()
      << "]\n"
      << "seeds: [5]\n"
      << "axes:\n"
      << "  cep: {path: sensors.gnss_middle.cep_m, values: [1.0]}\n";
  const Outcome outcome =
      Statebench("sweep " + (dir_ / "bad.yaml").string() + " --out " + (dir_ / "bad").string());
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_NE(outcome.output.find("bad.yaml:5:"), std::string::npos) << outcome.output;
  EXPECT_FALSE(fs::exists(dir_ / "bad"));
  const Outcome dry = Statebench(Sweep("dry", "--dry-run"));
  EXPECT_EQ(dry.exit_code, 0) << dry.output;
  EXPECT_NE(dry.output.find("4 of 4 runs"), std::string::npos) << dry.output;
  EXPECT_NE(dry.output.find("window_s=2.0"), std::string::npos) << dry.output;
  EXPECT_FALSE(fs::exists(dir_ / "dry"));
}

}  // namespace
}  // namespace statebench::app
