#include "reports/estimate_writer.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/csv.hpp"
#include "core/truth_io.hpp"
#include "tests/file_text.hpp"
#include "tests/removed_at_exit.hpp"

namespace statebench::reports {
namespace {

// estimate.tum copies the CSV's pose text where SE3 keeps the doubles; each line must be the one
// AppendTumLine writes from SE3, also where SE3 normalises the quaternion or a component is -0.
TEST(EstimateWriter, TumLinesAreThoseOfTheSe3Pose) {
  const auto dir = testing::RemovedAtExit(std::filesystem::temp_directory_path() /
                                          "statebench_estimate_writer_tum");
  std::vector<StateEstimate> estimates(4);
  estimates[0].state.t_ns = 10160000000;
  estimates[0].state.p_world = Vec3(61.80769952165979, 140.8247490148438, -0.8176042998014026);
  estimates[0].state.q_world_imu = Quat(0.7378305752318954, -0.005633212612782546,
                                        -0.008040296124870408, 0.6749145596346653);
  estimates[1].state.t_ns = -500000000;
  estimates[1].state.p_world = Vec3(-0.0, 1e-300, 3.0);
  estimates[1].state.q_world_imu = Quat(1.0, -0.0, 0.0, -0.0);
  estimates[2].state.t_ns = 20000000001;
  estimates[2].state.p_world = Vec3(1.0, 2.0, 3.0);
  estimates[2].state.q_world_imu = Quat(0.6, 0.0, 0.0, 0.9);  // not unit: SE3 normalises it
  estimates[3].state.t_ns = 20010000000;
  estimates[3].state.p_world = Vec3(1.5, -2.25, 1e9);
  estimates[3].state.q_world_imu = Quat(0.5, 0.5, 0.5, 0.5);
  {
    EstimateWriter writer(dir, /*full_covariance=*/false);
    for (const StateEstimate& e : estimates) writer.Write(e);
    writer.Close();
  }
  std::string expected = "# t tx ty tz qx qy qz qw  (T_world_imu, estimate)\n";
  for (const StateEstimate& e : estimates) {
    AppendTumLine(expected, e.state.t_ns, SE3(e.state.q_world_imu, e.state.p_world));
  }
  EXPECT_EQ(testing::FileText(dir / "estimate.tum"), expected);
}

// A row copies the previous row's bias text when the biases are the same bits: every row's bias
// columns must still be its own (unchanged, changed, back, and +0 after -0).
TEST(EstimateWriter, BiasColumnsAreEachRowsOwn) {
  const auto dir = testing::RemovedAtExit(std::filesystem::temp_directory_path() /
                                          "statebench_estimate_writer_bias");
  const std::vector<std::pair<Vec3, Vec3>> biases{
      {Vec3(1e-3, -2e-3, 5e-4), Vec3(0.05, -0.02, 0.03)},
      {Vec3(1e-3, -2e-3, 5e-4), Vec3(0.05, -0.02, 0.03)},
      {Vec3(1e-3, -2e-3, 5.000000000000001e-4), Vec3(0.05, -0.02, 0.03)},
      {Vec3(1e-3, -2e-3, 5e-4), Vec3(0.05, -0.02, 0.03)},
      {Vec3(-0.0, 0.0, 0.0), Vec3::Zero()},
      {Vec3(0.0, 0.0, 0.0), Vec3::Zero()},
      {Vec3(0.0, 0.0, 0.0), Vec3(0.0, 0.0, 7.0)}};
  {
    EstimateWriter writer(dir, /*full_covariance=*/false);
    StateEstimate e;
    for (const auto& [bg, ba] : biases) {
      e.state.t_ns += 10000000;
      e.state.gyro_bias = bg;
      e.state.accel_bias = ba;
      writer.Write(e);
    }
    writer.Close();
  }
  std::istringstream csv(testing::FileText(dir / "estimate.csv"));
  std::string line;
  std::getline(csv, line);  // header
  for (const auto& [bg, ba] : biases) {
    ASSERT_TRUE(std::getline(csv, line));
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    ASSERT_GT(cells.size(), 16u);
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(cells[11 + i], NumberText(bg[i])) << line;
      EXPECT_EQ(cells[14 + i], NumberText(ba[i])) << line;
    }
  }
  EXPECT_FALSE(std::getline(csv, line));
}

}  // namespace
}  // namespace statebench::reports
