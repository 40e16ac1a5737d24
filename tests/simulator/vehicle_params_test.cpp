#include "simulator/vehicle_params.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <functional>
#include <regex>
#include <sstream>

#include "core/error.hpp"

namespace statebench::sim {
namespace {

std::filesystem::path VehicleFile(const std::string& name) {
  const char* root = std::getenv("STATEBENCH_SOURCE_DIR");
  return std::filesystem::path(root ? root : ".") / "scenarios" / "vehicles" / (name + ".yaml");
}

std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

// 1-based line of the first line starting with `prefix`.
int LineOf(const std::string& text, const std::string& prefix) {
  std::istringstream in(text);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.rfind(prefix, 0) == 0) return n;
  }
  return -1;
}

// 1-based line of the first line containing `needle`.
int LineContaining(const std::string& text, const std::string& needle) {
  std::istringstream in(text);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.find(needle) != std::string::npos) return n;
  }
  return -1;
}

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  return std::regex_replace(text, std::regex(from), to);
}

TEST(VehicleParams, QuadricycleIsTwizyClass) {
  const VehicleParams p = LoadVehicleParamsFile(VehicleFile("quadricycle"));
  EXPECT_EQ(p.kind, VehicleKind::kQuadricycle);
  EXPECT_EQ(p.drive, DriveLayout::kFront);
  EXPECT_NEAR(p.wheelbase_m(), 1.69, 0.03);
  EXPECT_NEAR(p.track_width_m, 1.1, 0.05);
  EXPECT_GT(p.mass_kg, 450.0);
  EXPECT_LT(p.mass_kg, 600.0);
  EXPECT_EQ(p.rear_steering_ratio, 0.0);
  EXPECT_NEAR(p.T_body_imu.translation().z(), p.cg_height_m, 1e-12);
}

TEST(VehicleParams, ShuttleIsEz10Class) {
  const VehicleParams p = LoadVehicleParamsFile(VehicleFile("shuttle"));
  EXPECT_EQ(p.kind, VehicleKind::kShuttle);
  EXPECT_EQ(p.drive, DriveLayout::kAll);
  EXPECT_NEAR(p.body.length_m, 4.0, 0.1);
  EXPECT_NEAR(p.body.width_m, 2.0, 0.05);
  EXPECT_LE(p.max_speed_mps, 25.0 / 3.6 + 1e-9);
  EXPECT_GT(p.rear_steering_ratio, 0.0);
  // Symmetric body: the box centre sits above the body origin.
  EXPECT_NEAR(p.body_box_center().x(), 0.0, 1e-9);
  EXPECT_NEAR(p.body_box_center().z(), p.body.height_m / 2, 1e-12);
}

TEST(VehicleParams, MissingFieldNamesFileLineAndField) {
  const std::string text = Replace(ReadText(VehicleFile("quadricycle")), "mass_kg: 560.0", "");
  const std::string msg =
      ErrorOf([&] { LoadVehicleParams(YamlNode::LoadString(text, "quadricycle.yaml")); });
  EXPECT_NE(msg.find("quadricycle.yaml:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'mass_kg'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("missing field"), std::string::npos) << msg;
}

TEST(VehicleParams, WrongTypeNamesFileLineAndField) {
  const std::string text =
      Replace(ReadText(VehicleFile("quadricycle")), "track_width_m: 1.09", "track_width_m: wide");
  const std::string msg =
      ErrorOf([&] { LoadVehicleParams(YamlNode::LoadString(text, "quadricycle.yaml")); });
  const std::string where = "quadricycle.yaml:" + std::to_string(LineOf(text, "track_width_m"));
  EXPECT_NE(msg.find(where), std::string::npos) << msg;
  EXPECT_NE(msg.find("'track_width_m'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected a number"), std::string::npos) << msg;
}

TEST(VehicleParams, UnknownKeyIsRejected) {
  const std::string text = ReadText(VehicleFile("shuttle")) + "wheelbase_mm: 2800\n";
  const std::string msg =
      ErrorOf([&] { LoadVehicleParams(YamlNode::LoadString(text, "shuttle.yaml")); });
  const std::string where = "shuttle.yaml:" + std::to_string(LineOf(text, "wheelbase_mm"));
  EXPECT_NE(msg.find(where), std::string::npos) << msg;
  EXPECT_NE(msg.find("'wheelbase_mm'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("unknown field"), std::string::npos) << msg;
}

TEST(VehicleParams, UnknownKindAndDriveAreRejected) {
  const std::string base = ReadText(VehicleFile("shuttle"));
  std::string msg = ErrorOf([&] {
    LoadVehicleParams(
        YamlNode::LoadString(Replace(base, "kind: shuttle", "kind: truck"), "s.yaml"));
  });
  EXPECT_NE(msg.find("'kind'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("truck"), std::string::npos) << msg;
  msg = ErrorOf([&] {
    LoadVehicleParams(YamlNode::LoadString(Replace(base, "drive: all", "drive: rear"), "s.yaml"));
  });
  EXPECT_NE(msg.find("'drive'"), std::string::npos) << msg;
}

TEST(VehicleParams, PhysicallyImpossibleValuesAreRejected) {
  const std::string base = ReadText(VehicleFile("quadricycle"));
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"mass_kg: 560.0", "mass_kg: -560.0"},
      {"track_width_m: 1.09", "track_width_m: 1.5"},                  // wider than the body
      {"max_acceleration_mps2: 2.0", "max_acceleration_mps2: 12.0"},  // above mu g
      {"cg_height_m: 0.50", "cg_height_m: 2.0"},                      // above the roof
      {"steering_time_constant_s: 0.08", "steering_time_constant_s: 0.001"},
      {"length_m: 2.34", "length_m: 1.5"},  // shorter than the wheelbase
      {"yaw_inertia_kgm2: 350.0", "yaw_inertia_kgm2: 90000.0"},
  };
  for (const auto& [from, to] : cases) {
    const std::string field = to.substr(0, to.find(':'));
    const std::string text = Replace(base, from, to);
    const std::string msg =
        ErrorOf([&] { LoadVehicleParams(YamlNode::LoadString(text, "q.yaml")); });
    EXPECT_NE(msg.find(field + "'"), std::string::npos) << to << " -> " << msg;
    EXPECT_NE(msg.find("q.yaml:" + std::to_string(LineContaining(text, to)) + ":"),
              std::string::npos)
        << msg;
  }
}

}  // namespace
}  // namespace statebench::sim
