// MakeEstimator: builds both estimators by name; unknown names and missing or bad files fail
// with messages naming what is wrong.
#include "estimator/estimator_factory.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>

#include "core/error.hpp"
#include "ekf_test_drive.hpp"

namespace statebench::est {
namespace {

// The repository root (ctest sets STATEBENCH_SOURCE_DIR and runs in it).
std::filesystem::path RepoDir() {
  const char* dir = std::getenv("STATEBENCH_SOURCE_DIR");
  return dir != nullptr ? std::filesystem::path(dir) : std::filesystem::current_path();
}

std::string MessageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(EstimatorFactory, BuildsKnownEstimators) {
  const EstimatorSensorSetup setup = testing::MakeDriveSetup();
  EXPECT_EQ(MakeEstimator("factor_graph", setup, {})->name(), "factor_graph");
  EstimatorFiles files;
  files.vehicle = RepoDir() / "scenarios/vehicles/quadricycle.yaml";
  EXPECT_EQ(MakeEstimator("ekf", setup, files)->name(), "ekf");
  files.vehicle = RepoDir() / "scenarios/vehicles/shuttle.yaml";
  files.options = RepoDir() / "scenarios/estimators/ekf.yaml";
  EXPECT_EQ(MakeEstimator("ekf", setup, files)->name(), "ekf");
  EXPECT_EQ(KnownEstimators(), (std::vector<std::string>{"factor_graph", "ekf"}));
}

TEST(EstimatorFactory, UnknownNameListsKnownOnes) {
  const std::string message =
      MessageOf([] { MakeEstimator("ukf", testing::MakeDriveSetup(), {}); });
  EXPECT_NE(message.find("unknown estimator 'ukf'"), std::string::npos) << message;
  EXPECT_NE(message.find("factor_graph, ekf"), std::string::npos) << message;
}

TEST(EstimatorFactory, EkfNeedsValidVehicleFile) {
  const EstimatorSensorSetup setup = testing::MakeDriveSetup();
  EXPECT_NE(MessageOf([&] { MakeEstimator("ekf", setup, {}); }).find("vehicle"), std::string::npos);
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("ekf_factory_test_vehicle_" + std::to_string(::getpid()) + ".yaml");
  {
    std::ofstream out(path);
    out << "name: broken\nmass_kg: 500\nyaw_inertia_kgm2: -3\n";
  }
  EstimatorFiles files;
  files.vehicle = path;
  const std::string message = MessageOf([&] { MakeEstimator("ekf", setup, files); });
  EXPECT_NE(message.find("yaw_inertia_kgm2"), std::string::npos) << message;
  EXPECT_NE(message.find(path.filename().string() + ":3"), std::string::npos) << message;
  std::filesystem::remove(path);
}

TEST(EkfOptions, ParsesVehicleFileIgnoringOtherKeys) {
  const SingleTrackParams p =
      LoadSingleTrackParams(RepoDir() / "scenarios/vehicles/quadricycle.yaml");
  EXPECT_DOUBLE_EQ(p.mass_kg, 560.0);
  EXPECT_DOUBLE_EQ(p.yaw_inertia_kgm2, 350.0);
  EXPECT_DOUBLE_EQ(p.cg_to_front_axle_m, 0.93);
  EXPECT_DOUBLE_EQ(p.cg_to_rear_axle_m, 0.76);
  EXPECT_DOUBLE_EQ(p.cornering_stiffness_front_npr, 22000.0);
  EXPECT_DOUBLE_EQ(p.cornering_stiffness_rear_npr, 35000.0);
  EXPECT_DOUBLE_EQ(p.rear_steering_ratio, 0.0);
  const std::string missing =
      MessageOf([] { ParseSingleTrackParams(YamlNode::LoadString("mass_kg: 1\n", "v.yaml")); });
  EXPECT_NE(missing.find("yaw_inertia_kgm2"), std::string::npos) << missing;
}

TEST(EkfOptions, DefaultFileListsTheDefaults) {
  const EkfOptions parsed = LoadEkfOptions(RepoDir() / "scenarios/estimators/ekf.yaml");
  const EkfOptions defaults;
  EXPECT_EQ(parsed.position_density, defaults.position_density);
  EXPECT_EQ(parsed.gnss_gate_chi2, defaults.gnss_gate_chi2);
  EXPECT_EQ(parsed.course_max_yaw_sigma_rad, defaults.course_max_yaw_sigma_rad);
  EXPECT_EQ(parsed.history_s, defaults.history_s);
  const std::string typo = MessageOf([] {
    ParseEkfOptions(
        YamlNode::LoadString("gyro_sigma_radps: 0.01\nposition_densty: 1\n", "ekf.yaml"));
  });
  EXPECT_NE(typo.find("ekf.yaml:2"), std::string::npos) << typo;
  EXPECT_NE(typo.find("position_densty"), std::string::npos) << typo;
  const std::string invalid =
      MessageOf([] { ParseEkfOptions(YamlNode::LoadString("history_s: -1\n", "ekf.yaml")); });
  EXPECT_NE(invalid.find("history_s"), std::string::npos) << invalid;
}

}  // namespace
}  // namespace statebench::est
