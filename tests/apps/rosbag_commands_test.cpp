// Issue 14's acceptance for ROS1 bags: a simulated setup-2 log (statebench record, 5 s) exported
// to a bag (statebench export rosbag) and imported back (statebench import rosbag, with the topic
// map the export wrote) gives the same log: every measurement bit for bit (IMU -> sensor_msgs/Imu,
// GNSS -> NavSatFix, speed encoder -> TwistStamped linear.x, steering encoder -> JointState
// position, lidar -> PointCloud2), the same estimator setup, and `statebench estimate` gives the
// same estimate.csv on both, factor graph and EKF. Also: the listing's suggested map loads, a bad
// map exits 2 naming its line.
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

#include "../sensors/measurement_bytes.hpp"
#include "estimator/estimator_config.hpp"
#include "sensors/log_reader.hpp"
#include "sensors/rosbag_topic_map.hpp"
#include "tests/file_text.hpp"

namespace statebench::app {
namespace {

namespace fs = std::filesystem;

class TempDir {
 public:
  TempDir()
      : path_(fs::temp_directory_path() / ("statebench_rosbag_cmd_" + std::to_string(getpid()))) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// Exit code of `statebench ARGS`, its output in `log`.
int Statebench(const std::string& args, const fs::path& log) {
  const std::string command =
      std::string(STATEBENCH_BIN) + " " + args + " > " + log.string() + " 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

using testing::FileText;

nlohmann::json Json(const fs::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

std::vector<Measurement> ReadAll(const fs::path& dir) {
  sensors::LogReader reader(dir);
  std::vector<Measurement> out;
  while (auto m = reader.Next()) out.push_back(std::move(*m));
  EXPECT_FALSE(reader.error().has_value()) << *reader.error();
  return out;
}

TEST(RosbagCommands, Setup2LogThroughABagGivesTheSameMeasurementsAndEstimates) {
  TempDir tmp;
  const fs::path& d = tmp.path();
  const fs::path out = d / "out.txt";
  // Setup 2 without its `mismatch:`: the importer derives each sensor's latency from the bag
  // (receive time - header stamp), which a simulated clock offset would shift.
  std::string scenario = FileText("scenarios/paper/setup2_quadricycle.yaml");
  const std::size_t from = scenario.find("\nmismatch:");
  ASSERT_NE(from, std::string::npos);
  scenario.erase(from + 1, scenario.find("\n\n", from) - from);
  std::ofstream(d / "setup2_nominal.yaml") << scenario;
  ASSERT_EQ(Statebench("record " + (d / "setup2_nominal.yaml").string() +
                           " --duration 5 --quiet --out " + (d / "log").string(),
                       out),
            0)
      << FileText(out);
  ASSERT_EQ(Statebench("export rosbag " + (d / "log").string() + " --out " +
                           (d / "log.bag").string() + " --topics-out " + (d / "map.yaml").string(),
                       out),
            0)
      << FileText(out);
  ASSERT_EQ(Statebench("import rosbag " + (d / "log.bag").string() + " --topics " +
                           (d / "map.yaml").string() + " --out " + (d / "back").string(),
                       out),
            0)
      << FileText(out);

  // Every measurement, bit for bit, in the same order.
  const std::vector<Measurement> original = ReadAll(d / "log");
  const std::vector<Measurement> back = ReadAll(d / "back");
  ASSERT_EQ(back.size(), original.size());
  std::map<std::size_t, std::size_t> per_type;
  for (std::size_t i = 0; i < back.size(); ++i) {
    ASSERT_EQ(testing::MeasurementBytes(back[i]), testing::MeasurementBytes(original[i]))
        << "measurement " << i;
    ++per_type[back[i].index()];
  }
  EXPECT_EQ(per_type.size(), 5u);  // IMU, GNSS, vehicle speed, steering angle, lidar

  // The estimator reads the same setup from the imported setup.yaml (mounts via /tf_static).
  const est::EstimatorSensorSetup a = est::LoadEstimatorSensorSetup(d / "log" / "setup.yaml");
  const est::EstimatorSensorSetup b = est::LoadEstimatorSensorSetup(d / "back" / "setup.yaml");
  ASSERT_EQ(a.sensors.size(), b.sensors.size());
  for (std::size_t i = 0; i < a.sensors.size(); ++i) {
    const est::EstimatorSensor* s = b.Find(a.sensors[i].id);
    ASSERT_NE(s, nullptr) << a.sensors[i].id;
    EXPECT_EQ(s->kind, a.sensors[i].kind);
    EXPECT_EQ(s->T_imu_sensor.translation(), a.sensors[i].T_imu_sensor.translation());
    EXPECT_EQ(s->T_imu_sensor.rotation().coeffs(), a.sensors[i].T_imu_sensor.rotation().coeffs());
  }
  EXPECT_EQ(b.imu_id, a.imu_id);
  EXPECT_EQ(b.MaxMeasurementLatency(), a.MaxMeasurementLatency());

  // The same estimates. (In 5 s the factor graph starts in a local frame from the speed encoder,
  // setup 2's CEP 2 m fixes being too noisy for a prompt GNSS course; the EKF from its GNSS
  // course at about 4.6 s.)
  for (const std::string estimator : {"factor_graph", "ekf"}) {
    const std::string extra =
        estimator == "ekf" ? " --estimator ekf --vehicle scenarios/vehicles/quadricycle.yaml" : "";
    for (const char* log : {"log", "back"}) {
      ASSERT_EQ(Statebench("estimate " + (d / log).string() + " --quiet --out " +
                               (d / (estimator + "_" + log)).string() + extra,
                           out),
                0)
          << FileText(out);
    }
    const std::string est_a = FileText(d / (estimator + "_log") / "estimate.csv");
    const std::string est_b = FileText(d / (estimator + "_back") / "estimate.csv");
    EXPECT_EQ(est_a, est_b) << estimator;
    std::printf("%s: %zu estimate rows on both logs\n", estimator.c_str(),
                static_cast<std::size_t>(std::count(est_a.begin(), est_a.end(), '\n')) - 1);
    if (estimator == "ekf") {
      EXPECT_GT(std::count(est_a.begin(), est_a.end(), '\n'), 10);
    }
    // What each sensor's measurements became (accepted, rejected and why) is the same too.
    const nlohmann::json diag_a = Json(d / (estimator + "_log") / "diagnostics.json");
    const nlohmann::json diag_b = Json(d / (estimator + "_back") / "diagnostics.json");
    EXPECT_EQ(diag_a["sensors"], diag_b["sensors"]) << estimator;
    EXPECT_EQ(diag_a["initialized"], diag_b["initialized"]) << estimator;
    EXPECT_EQ(diag_a["waiting_for"], diag_b["waiting_for"]) << estimator;
  }

  // Without --topics: the listing and a suggested map, one YAML document on stdout.
  ASSERT_EQ(Statebench("import rosbag " + (d / "log.bag").string(), d / "suggested.yaml"), 0);
  const sensors::RosTopicMap suggested = sensors::LoadRosTopicMap(d / "suggested.yaml");
  EXPECT_EQ(suggested.topics.size(), 4u);  // the JointState (steering) entry is left commented

  // A bad map: exit 2, the map's file:line on stderr, no log written.
  std::ofstream(d / "bad.yaml") << "topics:\n  - {topic: /imu, id: imu, type: imu}\n"
                                   "  - {topic: /nothere, id: x, type: gnss}\n";
  EXPECT_EQ(Statebench("import rosbag " + (d / "log.bag").string() + " --topics " +
                           (d / "bad.yaml").string() + " --out " + (d / "bad").string(),
                       out),
            2);
  EXPECT_NE(FileText(out).find("bad.yaml:3:5: topic '/nothere' is not in"), std::string::npos)
      << FileText(out);
  EXPECT_FALSE(fs::exists(d / "bad"));
}

}  // namespace
}  // namespace statebench::app
