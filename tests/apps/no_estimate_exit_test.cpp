// Issue 14: an estimator that never initialises makes `statebench estimate` and `statebench run`
// exit with code 3, with one line on stderr per such estimator naming what it waited for, the
// same text in its diagnostics.json (`waiting_for`); the rest is written as usual. A robot with
// an IMU and wheel odometry only starts in a local frame (status `local`), exit code 0.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "core/random.hpp"
#include "core/state.hpp"
#include "sensors/log_writer.hpp"
#include "tests/file_text.hpp"

namespace statebench::app {
namespace {

namespace fs = std::filesystem;

struct Outcome {
  int exit_code = -1;
  std::string out, err;
};

using testing::FileText;

class NoEstimateExit : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("statebench_no_estimate_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  Outcome Statebench(const std::string& args) const {
    const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
    const std::string command =
        std::string(STATEBENCH_BIN) + " " + args + " > " + out.string() + " 2> " + err.string();
    const int status = std::system(command.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, FileText(out), FileText(err)};
  }

  // 5 s of a vehicle standing still, IMU at 100 Hz with `gyro_sigma` white noise per sample (an
  // engine's vibration when large), plus `setup_extra` sensors in setup.yaml; odometry reading
  // zero at 10 Hz when `odometry`.
  fs::path WriteStillLog(const std::string& name, double gyro_sigma, const std::string& setup_extra,
                         bool odometry) const {
    sensors::LogWriterOptions o;
    o.scenario = name;
    o.setup_yaml =
        "name: " + name +
        "\nsensors:\n  - {type: imu, id: imu, rate_hz: 100, T_body_sensor: {translation: [0, 0, "
        "0.3]}}\n" +
        setup_extra;
    const fs::path log = dir_ / name;
    sensors::LogWriter writer(log, o);
    auto rng = MakeRng(3, name);
    NormalSampler normal;
    for (int k = 0; k <= 500; ++k) {
      const TimeNs t = k * 10 * kNsPerMillisecond;
      ImuSample s;
      s.header = {"imu", t, t + kNsPerMillisecond};
      s.gyro = Vec3(1e-3, -2e-3, 1.5e-3) + gyro_sigma * Vec3(normal(rng), normal(rng), normal(rng));
      s.accel = Vec3(0.02, -0.01, kGravity) + 0.02 * Vec3(normal(rng), normal(rng), normal(rng));
      writer.Write(s);
      if (odometry && k % 10 == 0) {
        BodyVelocity v;
        v.header = {"wheel_odom", t, t + 20 * kNsPerMillisecond};
        v.covariance = Mat6::Identity() * 1e6;
        v.covariance(0, 0) = v.covariance(1, 1) = 4e-4;
        writer.Write(v);
      }
    }
    writer.Close();
    return log;
  }

  fs::path dir_;
};

TEST_F(NoEstimateExit, EstimateSaysWhatEachEstimatorWaitedFor) {
  // A GNSS antenna in the setup, no fix in the log, an engine shaking the IMU.
  const fs::path log = WriteStillLog(
      "no_fix", 0.04, "  - {type: gnss, id: gnss, T_body_sensor: {translation: [0, 0, 1.2]}}\n",
      false);
  const Outcome fg =
      Statebench("estimate " + log.string() + " --quiet --out " + (dir_ / "fg").string());
  EXPECT_EQ(fg.exit_code, 3) << fg.out << fg.err;
  const std::string prefix = "error: factor_graph never initialised: ";
  ASSERT_NE(fg.err.find(prefix), std::string::npos) << fg.err;
  const std::string line = fg.err.substr(fg.err.find(prefix) + prefix.size());
  const std::string why = line.substr(0, line.find('\n'));
  EXPECT_NE(why.find("no still period of 1 s (quietest window: gyro std 0.0"), std::string::npos)
      << why;
  EXPECT_NE(why.find(" and no GNSS fix"), std::string::npos) << why;
  const nlohmann::json diag = nlohmann::json::parse(FileText(dir_ / "fg" / "diagnostics.json"));
  EXPECT_EQ(diag["initialized"], false);
  EXPECT_EQ(diag["waiting_for"], why);
  EXPECT_TRUE(fs::exists(dir_ / "fg" / "estimate.csv"));

  const Outcome ekf = Statebench("estimate " + log.string() + " --estimator ekf --vehicle " +
                                 fs::absolute("scenarios/vehicles/quadricycle.yaml").string() +
                                 " --quiet --out " + (dir_ / "ekf").string());
  EXPECT_EQ(ekf.exit_code, 3) << ekf.out << ekf.err;
  EXPECT_NE(ekf.err.find("error: ekf never initialised: no GNSS fix of gnss"), std::string::npos)
      << ekf.err;
}

TEST_F(NoEstimateExit, ImuAndWheelOdometryStartInALocalFrame) {
  const fs::path log = WriteStillLog(
      "robot", 2.4e-3,
      "  - {type: body_velocity, id: wheel_odom, rate_hz: 10, latency_s: 0.02, T_body_sensor: "
      "{translation: [0, 0, 0]}}\n",
      true);
  const Outcome run =
      Statebench("estimate " + log.string() + " --quiet --out " + (dir_ / "robot_est").string());
  EXPECT_EQ(run.exit_code, 0) << run.out << run.err;
  const nlohmann::json diag =
      nlohmann::json::parse(FileText(dir_ / "robot_est" / "diagnostics.json"));
  EXPECT_EQ(diag["initialization"], "static (local frame)");
  EXPECT_TRUE(diag["waiting_for"].is_null());
  std::ifstream csv(dir_ / "robot_est" / "estimate.csv");
  std::string line;
  std::getline(csv, line);
  int rows = 0, local = 0;
  while (std::getline(csv, line)) {
    ++rows;
    local += line.find(",local,") != std::string::npos;  // the status column
  }
  EXPECT_GT(rows, 300);
  EXPECT_EQ(local, rows);
}

TEST_F(NoEstimateExit, RunWritesEveryResultAndNamesTheEstimatorsWithoutOne) {
  // One second of the setup-1 scenario: neither estimator has started yet.
  const Outcome run =
      Statebench("run scenarios/extra/setup1_quadricycle_nolidar.yaml --duration 1 --quiet --out " +
                 (dir_ / "run").string());
  EXPECT_EQ(run.exit_code, 3) << run.out << run.err;
  EXPECT_NE(run.err.find("error: factor_graph never initialised: "), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("error: ekf never initialised: "), std::string::npos) << run.err;
  EXPECT_NE(run.out.find("no estimate: never initialised"), std::string::npos) << run.out;
  const nlohmann::json summary = nlohmann::json::parse(FileText(dir_ / "run" / "run.json"));
  ASSERT_EQ(summary["estimators"].size(), 2u);
  for (const nlohmann::json& e : summary["estimators"]) {
    EXPECT_TRUE(e.contains("no_estimate")) << e.dump();
    EXPECT_EQ(e["metrics"]["availability"]["estimates"], 0);
    const std::string label = e["label"];
    EXPECT_TRUE(fs::exists(dir_ / "run" / label / "metrics.json"));
    EXPECT_FALSE(
        nlohmann::json::parse(FileText(dir_ / "run" / label / "diagnostics.json"))["waiting_for"]
            .is_null());
  }
}

}  // namespace
}  // namespace statebench::app
