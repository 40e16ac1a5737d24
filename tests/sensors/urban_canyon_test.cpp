#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "lidar_test_fixtures.hpp"
#include "sensors/synthetic_roads.hpp"
#include "sensors/traffic_window.hpp"
#include "sensors/urban_canyon_visibility.hpp"

namespace statebench::sensors {
namespace {

const GroundHeightFn kFlat = [](double, double) { return 0.0; };

std::shared_ptr<const LidarWorld> StreetWorld(bool tall_buildings) {
  WorldLayoutOptions layout = testing::BareLayoutOptions();
  if (tall_buildings) {
    // An unbroken row of 40-60 m towers 1-2 m behind both edges of a 7 m wide street.
    layout.buildings.enabled = true;
    layout.buildings.probability = 1.0;
    layout.buildings.setback_min_m = 1.0;
    layout.buildings.setback_max_m = 2.0;
    layout.buildings.road_clearance_m = 0.5;
    layout.buildings.facade_min_m = 20.0;
    layout.buildings.facade_max_m = 40.0;
    layout.buildings.gap_min_m = 0.5;
    layout.buildings.gap_max_m = 1.5;
    layout.buildings.height_min_m = 40.0;
    layout.buildings.height_max_m = 60.0;
  }
  return LidarWorld::Build(MakeStraightRoad(-300.0, 300.0, 1, 3.5, kFlat), kFlat, layout);
}

TEST(GnssConstellation, OpenSkyLooksLikeGps) {
  GnssConstellationOptions options;
  options.seed = 5;
  const GnssConstellation constellation(options);
  ASSERT_EQ(constellation.size(), 30);
  const double sin_mask = std::sin(10.0 * std::numbers::pi / 180.0);
  int min_count = 100, max_count = 0;
  std::vector<Vec3> previous;
  for (int minute = 0; minute < 24 * 60; minute += 10) {
    const std::vector<Vec3> los = constellation.DirectionsEnu(FromSeconds(60.0 * minute));
    const int count = static_cast<int>(
        std::count_if(los.begin(), los.end(), [&](const Vec3& d) { return d.z() > sin_mask; }));
    min_count = std::min(min_count, count);
    max_count = std::max(max_count, count);
    for (const Vec3& d : los) EXPECT_NEAR(d.norm(), 1.0, 1e-12);
    if (!previous.empty()) {  // satellites move slowly: < 1 deg per minute
      for (std::size_t i = 0; i < los.size(); ++i) {
        EXPECT_LT(std::acos(std::min(1.0, los[i].dot(previous[i]))), 10 * std::numbers::pi / 180);
      }
    }
    previous = los;
  }
  EXPECT_GE(min_count, 6);
  EXPECT_LE(max_count, 13);
  EXPECT_LT(min_count, max_count);
}

TEST(UrbanCanyon, PdopOfKnownGeometry) {
  // Zenith plus three at 0 deg elevation 120 deg apart: G^T G is diagonal with (1.5, 1.5, 1, 4)
  // after centring; PDOP = sqrt(2/1.5 + 4/3) from the closed form of this symmetric set.
  std::vector<Vec3> los = {Vec3::UnitZ()};
  for (int k = 0; k < 3; ++k) {
    const double a = 2.0 * std::numbers::pi * k / 3;
    los.emplace_back(std::cos(a), std::sin(a), 0.0);
  }
  // Normal matrix: diag(1.5, 1.5) for east/north; up/clock block [[1, -1], [-1, 4]].
  const double up_var = 4.0 / (4.0 - 1.0);
  EXPECT_NEAR(Pdop(los), std::sqrt(2.0 / 1.5 + up_var), 1e-12);
  los.pop_back();
  EXPECT_TRUE(std::isinf(Pdop(los)));
}

TEST(UrbanCanyon, TallBuildingsBlockSatellitesAndDegradeTheFix) {
  GnssConstellationOptions constellation;
  constellation.seed = 1;
  const UrbanCanyonVisibility canyon(StreetWorld(true), constellation);
  const UrbanCanyonVisibility open(StreetWorld(false), constellation);
  const SatelliteVisibility& hook = canyon;
  const Vec3 antenna(0.0, -1.75, 2.0);  // roof of a car in the right lane

  int samples = 0, canyon_fixed = 0, open_fixed = 0, canyon_none_or_single = 0;
  for (int minute = 0; minute < 24 * 60; minute += 10) {
    const TimeNs t = FromSeconds(60.0 * minute);
    const SkyView in_canyon = canyon.Evaluate(antenna, t);
    const SkyView in_open = open.Evaluate(antenna, t);
    ++samples;
    EXPECT_TRUE(in_open.blocked.empty());
    EXPECT_EQ(in_canyon.above_mask(), in_open.above_mask());
    EXPECT_LT(in_canyon.visible.size(), in_open.visible.size());
    EXPECT_EQ(hook.VisibleSatellites(antenna, t), static_cast<int>(in_canyon.visible.size()));
    const GnssFixStatus s_canyon = FixQualityFromSky(in_canyon, SkyFixThresholds{});
    const GnssFixStatus s_open = FixQualityFromSky(in_open, SkyFixThresholds{});
    canyon_fixed += s_canyon == GnssFixStatus::kRtkFixed ? 1 : 0;
    canyon_none_or_single += s_canyon <= GnssFixStatus::kSingle ? 1 : 0;
    open_fixed += s_open == GnssFixStatus::kRtkFixed ? 1 : 0;
  }
  EXPECT_EQ(open_fixed, samples);
  EXPECT_EQ(canyon_fixed, 0);
  EXPECT_GT(canyon_none_or_single, samples * 9 / 10);
}

TEST(UrbanCanyon, BlockedExactlyWhenTheLineOfSightCrossesABuilding) {
  GnssConstellationOptions constellation;
  constellation.seed = 2;
  const auto world = StreetWorld(true);
  const UrbanCanyonVisibility canyon(world, constellation);
  // Independent reference: the analytic ray / box test against every building box.
  const auto crosses_building = [&](const Vec3& from, const Vec3& d) {
    for (const WorldBox& b : world->layout().boxes) {
      TrafficBox box;
      box.centre_world = b.centre_world;
      box.yaw_rad = b.yaw_rad;
      box.length_m = b.size_m.x();
      box.width_m = b.size_m.y();
      box.height_m = b.size_m.z();
      if (IntersectTrafficBox(box, from, d, 1000.0)) return true;
    }
    return false;
  };
  int blocked = 0, visible = 0;
  for (const Vec3& antenna : {Vec3(0.0, 0.0, 2.0), Vec3(-120.0, 3.0, 1.5), Vec3(77.0, -2.0, 3.0)}) {
    for (int minute = 0; minute < 24 * 60; minute += 30) {
      const TimeNs t = FromSeconds(60.0 * minute);
      const std::vector<Vec3> los = canyon.constellation().DirectionsEnu(t);
      const SkyView sky = canyon.Evaluate(antenna, t);
      for (const int id : sky.visible) EXPECT_FALSE(crosses_building(antenna, los[id]));
      for (const int id : sky.blocked) EXPECT_TRUE(crosses_building(antenna, los[id]));
      blocked += static_cast<int>(sky.blocked.size());
      visible += static_cast<int>(sky.visible.size());
    }
  }
  EXPECT_GT(blocked, 2 * visible);
  EXPECT_GT(visible, 0);
}

}  // namespace
}  // namespace statebench::sensors
