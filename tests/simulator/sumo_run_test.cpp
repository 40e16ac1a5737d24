#include "simulator/sumo_run.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <set>

#include "simulator/traffic_demand.hpp"
#include "sumo_test_support.hpp"

namespace statebench::sim {
namespace {

using testing::GridScenarioParts;
using testing::TempDir;
using testing::WriteFile;

// One minute in the 3 x 3 grid town: the ego loops around a block through four traffic lights.
GridScenarioParts MinuteParts(std::uint64_t seed) {
  GridScenarioParts parts;
  parts.header = "name: grid_minute\nseed: " + std::to_string(seed) +
                 "\nduration_s: 60.0\n"
                 "origin: {latitude_deg: 48.78, longitude_deg: 2.13, altitude_m: 100.0}\n"
                 "vehicle: quadricycle\n";
  return parts;
}

struct ScenarioRun {
  Scenario scenario;
  BuiltNetwork built;
  SumoResult result;
};

ScenarioRun Simulate(const TempDir& dir, const std::string& name, const GridScenarioParts& parts) {
  ScenarioRun run;
  run.scenario = LoadScenario(WriteFile(dir.path() / (name + ".yaml"), parts.Text()));
  run.built = NetworkBuilder().Build(run.scenario, EgoVehicleType(), dir.path() / name);
  run.result = RunSumo(run.scenario, run.built);
  return run;
}

class SumoRunTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<TempDir>();
    run_ = std::make_unique<ScenarioRun>(Simulate(*dir_, "seed11", MinuteParts(11)));
  }
  static void TearDownTestSuite() {
    run_.reset();
    dir_.reset();
  }
  static const SumoResult& result() { return run_->result; }

  static std::unique_ptr<TempDir> dir_;
  static std::unique_ptr<ScenarioRun> run_;
};

std::unique_ptr<TempDir> SumoRunTest::dir_;
std::unique_ptr<ScenarioRun> SumoRunTest::run_;

std::string EdgeOfLane(const std::string& lane_id) { return lane_id.substr(0, lane_id.rfind('_')); }

double DistanceToPolyline(const Vec3& p, const std::vector<Vec3>& line) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    const Vec3 d = line[i + 1] - line[i];
    const double f = std::clamp((p - line[i]).dot(d) / d.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (line[i] + f * d - p).norm());
  }
  return best;
}

TEST_F(SumoRunTest, SamplesEveryStepFromZeroToTheDuration) {
  const auto& ego = result().ego;
  ASSERT_EQ(ego.size(), 601u);
  EXPECT_FALSE(result().ego_arrived);
  for (std::size_t k = 0; k < ego.size(); ++k) EXPECT_DOUBLE_EQ(ego[k].t_s, 0.1 * k);
  // The ego departs where the scenario says: 5 m into A0A1, at rest.
  EXPECT_EQ(ego.front().lane_id, "A0A1_0");
  EXPECT_DOUBLE_EQ(ego.front().lane_pos_m, 5.0);
  EXPECT_DOUBLE_EQ(ego.front().v_mps, 0.0);
  EXPECT_GT(ego.back().s_m, 150.0);  // it got somewhere
}

TEST_F(SumoRunTest, EgoFollowsItsRoute) {
  std::vector<std::string> edges;
  for (const DrivenLane& lane : result().driven_path.lanes()) {
    if (lane.lane_id.front() == ':') continue;
    const std::string edge = EdgeOfLane(lane.lane_id);
    if (edges.empty() || edges.back() != edge) edges.push_back(edge);
  }
  const auto& route = run_->built.ego_route;
  ASSERT_GE(edges.size(), 3u);
  ASSERT_LE(edges.size(), route.size());
  for (std::size_t i = 0; i < edges.size(); ++i) EXPECT_EQ(edges[i], route[i]) << i;
  // Junction lanes are part of the driven path, between every pair of edges.
  EXPECT_GE(result().driven_path.lanes().size(), 2 * edges.size() - 1);
}

TEST_F(SumoRunTest, EgoStopsAtARedLight) {
  int red_stops = 0;
  const auto& ego = result().ego;
  for (std::size_t k = 1; k < ego.size(); ++k) {
    const bool stopped = ego[k].v_mps < 0.1 && ego[k - 1].v_mps >= 0.1;
    if (stopped && ego[k].tls_state == 'r' && ego[k].tls_distance_m < 10.0) ++red_stops;
  }
  EXPECT_GE(red_stops, 1);
  // It also drives: somewhere near the road speed limit of 13.89 m/s (the ego's own limit is
  // 12.5 m/s).
  double v_max = 0.0;
  for (const EgoSample& s : ego) v_max = std::max(v_max, s.v_mps);
  EXPECT_GT(v_max, 8.0);
  EXPECT_LE(v_max, 12.5 + 1e-9);
}

TEST_F(SumoRunTest, FrontBumperLiesOnTheDrivenPolyline) {
  const DrivenPath& path = result().driven_path;
  double worst = 0.0;
  for (const EgoSample& s : result().ego) {
    worst = std::max(worst, (path.PointAt(s.s_m) - s.p_world_front).norm());
  }
  EXPECT_LT(worst, 0.02);
  // The path has grades (junction heights of sigma 1 m), so a 2D arc length would be off by
  // more than this.
  double z_min = 1e9;
  double z_max = -1e9;
  for (const Vec3& p : path.points()) {
    z_min = std::min(z_min, p.z());
    z_max = std::max(z_max, p.z());
  }
  EXPECT_GT(z_max - z_min, 0.5);
}

TEST_F(SumoRunTest, ArcLengthIntegratesThePathSpeed) {
  const auto& ego = result().ego;
  double integral = 0.0;
  for (std::size_t k = 1; k < ego.size(); ++k) {
    EXPECT_GE(ego[k].s_m, ego[k - 1].s_m - 1e-9);
    integral += 0.5 * (ego[k - 1].ds_dt_mps + ego[k].ds_dt_mps) * 0.1;
  }
  const double travelled = ego.back().s_m - ego.front().s_m;
  EXPECT_NEAR(integral, travelled, 0.005 * travelled);
  // Lookahead past the last sample for the path tracker.
  EXPECT_GE(result().driven_path.length_m() - ego.back().s_m, 50.0);
}

TEST_F(SumoRunTest, RecordsTrafficBoxesOnTheLanes) {
  const auto& traffic = result().traffic;
  ASSERT_EQ(traffic.size(), result().ego.size());
  std::set<std::string> types;
  std::size_t most = 0;
  for (std::size_t k = 0; k < traffic.size(); ++k) {
    EXPECT_DOUBLE_EQ(traffic[k].t_s, result().ego[k].t_s);
    most = std::max(most, traffic[k].boxes.size());
    std::set<std::string> ids;
    for (const TrafficBox& box : traffic[k].boxes) {
      EXPECT_NE(box.id, "ego");
      EXPECT_TRUE(ids.insert(box.id).second) << "duplicate " << box.id;
    }
  }
  EXPECT_GE(most, 10u);  // density 12 plus the flow
  // The box's front-bottom edge centre (centre moved L/2 forward, H/2 down in body axes) is
  // SUMO's front bumper position, which lies on a lane centre line.
  std::size_t checked = 0;
  for (std::size_t k = 0; k < traffic.size(); k += 50) {
    for (const TrafficBox& box : traffic[k].boxes) {
      const double cy = std::cos(box.yaw_rad), sy = std::sin(box.yaw_rad);
      const double cp = std::cos(box.pitch_rad), sp = std::sin(box.pitch_rad);
      const Vec3 forward(cy * cp, sy * cp, -sp);  // R = Rz(yaw) Ry(pitch)
      const Vec3 up(cy * sp, sy * sp, cp);
      const Vec3 front =
          box.p_world_center + 0.5 * box.length_m * forward - 0.5 * box.height_m * up;
      double best = std::numeric_limits<double>::infinity();
      for (const LaneGeometry& lane : result().lanes) {
        best = std::min(best, DistanceToPolyline(front, lane.shape));
      }
      EXPECT_LT(best, 0.01) << box.id << " at t " << traffic[k].t_s;
      bool known_type = false;
      for (const TrafficVehicleType& t : TrafficVehicleTypes()) {
        known_type = known_type || (t.length_m == box.length_m && t.height_m == box.height_m);
      }
      EXPECT_TRUE(known_type) << box.id;
      ++checked;
    }
  }
  EXPECT_GT(checked, 50u);
}

TEST_F(SumoRunTest, KeepsTheRoadGeometry) {
  const SumoResult& r = result();
  ASSERT_FALSE(r.lanes.empty());
  ASSERT_FALSE(r.junctions.empty());
  double length = 0.0;
  for (const LaneGeometry& lane : r.lanes) {
    EXPECT_GE(lane.shape.size(), 2u) << lane.id;
    EXPECT_NEAR(lane.width_m, 3.2, 1e-9) << lane.id;
    EXPECT_EQ(lane.internal, lane.id.front() == ':');
    for (std::size_t i = 1; i < lane.shape.size(); ++i) {
      length += (lane.shape[i] - lane.shape[i - 1]).norm();
    }
  }
  EXPECT_GE(static_cast<double>(r.LanePoints(2.0).size()), length / 2.0);
  EXPECT_EQ(r.LaneShapes().size(), r.lanes.size());
  for (const JunctionGeometry& j : r.junctions) EXPECT_GE(j.shape.size(), 3u) << j.id;
}

TEST_F(SumoRunTest, SameSeedSameResultOtherSeedOtherTraffic) {
  TempDir dir;
  const ScenarioRun again = Simulate(dir, "again", MinuteParts(11));
  EXPECT_TRUE(again.result == result());
  const ScenarioRun other = Simulate(dir, "other", MinuteParts(12));
  EXPECT_EQ(other.result.lanes, result().lanes);  // the network does not depend on the seed
  EXPECT_FALSE(other.result.traffic == result().traffic);
}

TEST_F(SumoRunTest, RestoresTheCallersStreamFormatting) {
  std::cout.precision(9);
  std::cout.unsetf(std::ios::fixed);
  TempDir dir;
  GridScenarioParts parts = MinuteParts(3);
  parts.ego = "ego:\n  route: [A0A1]\n";
  parts.traffic = "traffic:\n  density: 0\n";
  Simulate(dir, "format", parts);
  EXPECT_EQ(std::cout.precision(), 9);
  EXPECT_FALSE(std::cout.flags() & std::ios::fixed);
}

TEST(SumoRun, EndsWhenTheEgoReachesTheEndOfItsRoute) {
  TempDir dir;
  GridScenarioParts parts = MinuteParts(5);
  parts.ego = "ego:\n  route: [A0A1, A1A2]\n  depart_speed_mps: 5.0\n";
  const ScenarioRun run = Simulate(dir, "arrive", parts);
  EXPECT_TRUE(run.result.ego_arrived);
  ASSERT_FALSE(run.result.ego.empty());
  EXPECT_LT(run.result.ego.size(), 601u);
  EXPECT_EQ(run.result.ego.back().lane_id, "A1A2_0");
  // No path beyond the end of the route.
  const DrivenLane& last = run.result.driven_path.lanes().back();
  EXPECT_EQ(last.lane_id, "A1A2_0");
  EXPECT_DOUBLE_EQ(run.result.driven_path.length_m(), last.s_end_m);
  EXPECT_DOUBLE_EQ(run.result.ego.front().v_mps, 5.0);
}

// ego.parked_s: the ego stands at its departure position, then drives off as SUMO's driver
// would.
TEST(SumoRun, AParkedEgoStandsUntilParkedSThenDrivesOff) {
  TempDir dir;
  GridScenarioParts parts = MinuteParts(5);
  parts.ego = "ego:\n  route: [A0A1, A1B1, B1B0, B0A0]\n  loops: 3\n  depart_pos_m: 5.0\n"
              "  parked_s: 12.0\n";
  const ScenarioRun run = Simulate(dir, "parked", parts);
  const auto& ego = run.result.ego;
  ASSERT_EQ(ego.size(), 601u);
  for (std::size_t k = 0; k <= 120; ++k) {
    EXPECT_EQ(ego[k].v_mps, 0.0) << ego[k].t_s;
    EXPECT_EQ(ego[k].s_m, ego[0].s_m) << ego[k].t_s;
  }
  EXPECT_GT(ego[121].v_mps, 0.0);
  EXPECT_GT(ego[200].s_m - ego[0].s_m, 10.0);
}

}  // namespace
}  // namespace statebench::sim
