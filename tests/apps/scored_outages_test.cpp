// The windows a run scores as outages: shared GNSS outages (setup 3) and sensor outages that
// silence every GNSS receiver (setup2_imu_only_60s, GNSS and lidar off from 100 to 160 s).
#include "apps/scored_outages.hpp"

#include <gtest/gtest.h>

#include "simulator/scenario.hpp"

namespace statebench::app {
namespace {

sim::ScenarioSensors SensorsOf(const std::string& file) {
  return sim::LoadScenarioSensors(sim::LoadScenario(file));  // ctest runs in the source folder
}

TEST(ScoredOutages, SensorOutagesThatSilenceEveryReceiverAreScored) {
  const auto windows =
      ScoredOutages(SensorsOf("scenarios/extra/setup2_imu_only_60s.yaml"), FromSeconds(240.0));
  ASSERT_EQ(windows.size(), 1u);
  EXPECT_EQ(windows[0].begin_ns, FromSeconds(100.0));
  EXPECT_EQ(windows[0].end_ns, FromSeconds(160.0));
  // Clipped to the run.
  const auto short_run =
      ScoredOutages(SensorsOf("scenarios/extra/setup2_imu_only_60s.yaml"), FromSeconds(120.0));
  ASSERT_EQ(short_run.size(), 1u);
  EXPECT_EQ(short_run[0].end_ns, FromSeconds(120.0));
  EXPECT_TRUE(
      ScoredOutages(SensorsOf("scenarios/extra/setup2_imu_only_60s.yaml"), FromSeconds(90.0))
          .empty());
}

TEST(ScoredOutages, SharedGnssOutagesRunToTheEnd) {
  const auto windows =
      ScoredOutages(SensorsOf("scenarios/paper/setup3_shuttle.yaml"), FromSeconds(120.0));
  ASSERT_EQ(windows.size(), 1u);
  EXPECT_EQ(windows[0].begin_ns, FromSeconds(60.0));
  EXPECT_EQ(windows[0].end_ns, FromSeconds(120.0));
  EXPECT_TRUE(
      ScoredOutages(SensorsOf("scenarios/paper/setup2_quadricycle.yaml"), FromSeconds(240.0))
          .empty());
}

}  // namespace
}  // namespace statebench::app
