#include "reports/estimate_writer.hpp"

#include <gtest/gtest.h>

#include <sstream>

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

}  // namespace
}  // namespace statebench::reports
