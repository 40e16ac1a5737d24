// --threads: the limit holds for the ThreadLimit's lifetime, suites and sweeps share the cores
// among their runs, and a run's results are the same bits with one thread and with two (the
// lidar simulation's blocks and the ICP's reductions are deterministic).
#include "apps/thread_limit.hpp"

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

TEST(ThreadLimit, HoldsForItsLifetime) {
  const std::size_t before = ThreadLimit::Threads();
  {
    const ThreadLimit one(1);
    EXPECT_EQ(ThreadLimit::Threads(), 1u);
  }
  EXPECT_EQ(ThreadLimit::Threads(), before);
  {
    const ThreadLimit none(std::nullopt);
    EXPECT_EQ(ThreadLimit::Threads(), before);
  }
}

TEST(ThreadLimit, RunsAtOnceShareTheCores) {
  const std::uint64_t cores = OnlineCores();
  ASSERT_GE(cores, 1u);
  EXPECT_EQ(ThreadsPerJob(1), cores);
  EXPECT_EQ(ThreadsPerJob(cores), 1u);
  EXPECT_EQ(ThreadsPerJob(cores + 1), 1u);
  EXPECT_EQ(ThreadsPerJob(2), std::max<std::uint64_t>(1, cores / 2));
}

TEST(ThreadLimit, ARunGivesTheSameBitsWithOneAndTwoThreads) {
  const fs::path dir = testing::RemovedAtExit(fs::temp_directory_path() /
                                              ("thread_limit_test_" + std::to_string(getpid())));
  fs::remove_all(dir);
  std::string estimates[2];
  for (const int threads : {1, 2}) {
    const fs::path out = dir / ("threads" + std::to_string(threads));
    // 8 s of setup 2: 68 lidar scans simulated and registered by the factor graph.
    const std::string command = std::string(STATEBENCH_BIN) +
                                " run scenarios/paper/setup2_quadricycle.yaml --duration 8"
                                " --estimators fg_all_sensors --quiet --threads " +
                                std::to_string(threads) + " --out " + out.string() + " > " +
                                (dir / "output.log").string() + " 2>&1";
    fs::create_directories(dir);
    const int status = std::system(command.c_str());
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << FileText(dir / "output.log");
    const nlohmann::json run = nlohmann::json::parse(FileText(out / "run.json"));
    EXPECT_EQ(run["cpu"]["threads"].get<int>(), threads);
    estimates[threads - 1] = FileText(out / "fg_all_sensors" / "estimate.csv");
  }
  EXPECT_GT(estimates[0].size(), 100000u);
  EXPECT_TRUE(estimates[0] == estimates[1]) << "estimate.csv differs between 1 and 2 threads";

  const std::string zero = std::string(STATEBENCH_BIN) +
                           " run scenarios/paper/setup2_quadricycle.yaml --threads 0 --out " +
                           (dir / "zero").string() + " > " + (dir / "output.log").string() +
                           " 2>&1";
  const int status = std::system(zero.c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 2);
  EXPECT_NE(FileText(dir / "output.log").find("--threads: must be at least 1"), std::string::npos)
      << FileText(dir / "output.log");
}

}  // namespace
}  // namespace statebench::app
