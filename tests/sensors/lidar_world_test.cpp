#include "sensors/lidar_world.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/error.hpp"
#include "core/random.hpp"
#include "lidar_test_fixtures.hpp"
#include "sensors/synthetic_roads.hpp"
#include "sensors/traffic_window.hpp"

namespace statebench::sensors {
namespace {

constexpr double kLaneWidth = 3.5;

TEST(LidarWorld, RaysHitTheTerrainAndTheObjectsExactly) {
  // Planar terrain is represented exactly by the triangle grid.
  const GroundHeightFn tilted = [](double x, double y) { return 1.0 + 0.03 * x - 0.01 * y; };
  WorldLayoutOptions options = testing::BareLayoutOptions();
  WorldBox wall;
  wall.centre_world = Vec3(40.0, 20.0, 5.0);
  wall.yaw_rad = 0.3;
  wall.size_m = Vec3(10.0, 2.0, 10.0);
  options.extra_boxes = {wall};
  const auto world =
      LidarWorld::Build(MakeStraightRoad(-50.0, 50.0, 1, kLaneWidth, tilted), tilted, options);
  EXPECT_GT(world->tile_count(), 4u);
  for (const Vec2& xy : {Vec2(0.0, 1.0), Vec2(-37.3, 11.1), Vec2(63.9, -80.2)}) {
    const Vec3 origin(xy.x(), xy.y(), 20.0);
    const auto hit = world->CastStatic(origin, -Vec3::UnitZ(), 100.0);
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->range_m, 20.0 - tilted(xy.x(), xy.y()), 1e-9);
    EXPECT_NEAR(hit->normal_world.dot(Vec3(-0.03, 0.01, 1.0).normalized()), 1.0, 1e-9);
    EXPECT_EQ(hit->material,
              std::abs(xy.y()) < kLaneWidth ? SurfaceMaterial::kRoad : SurfaceMaterial::kGround);
  }
  // Horizontal ray at the wall's centre height towards its long face (normal at yaw 0.3 + 90 deg).
  const Vec3 n(std::cos(0.3 + M_PI / 2), std::sin(0.3 + M_PI / 2), 0.0);
  const Vec3 origin = wall.centre_world + 25.0 * n;
  const auto hit = world->CastStatic(origin, -n, 100.0);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->range_m, 24.0, 1e-9);
  EXPECT_EQ(hit->material, SurfaceMaterial::kBuilding);
  EXPECT_FALSE(world->CastStatic(origin, n, 100.0));  // away from the wall, above falling ground
  EXPECT_FALSE(world->CastStatic(origin, -n, 23.5));  // short of the wall
}

// The same box as the analytic reference of traffic_window.hpp.
TrafficBox AsTrafficBox(const WorldBox& b) {
  TrafficBox box;
  box.centre_world = b.centre_world;
  box.yaw_rad = b.yaw_rad;
  box.length_m = b.size_m.x();
  box.width_m = b.size_m.y();
  box.height_m = b.size_m.z();
  return box;
}

TEST(LidarWorld, RaysGrazingABuildingCornerHitTheRightFace) {
  // A large building: Bullet's float triangle test is inclusive by ~1e-4 of the triangle size at
  // the edges (several mm here); the exact double test must pick the face the ray really enters.
  const GroundHeightFn low = [](double, double) { return -30.0; };
  WorldLayoutOptions options = testing::BareLayoutOptions();
  WorldBox building;
  building.centre_world = Vec3(30.0, 10.0, 0.0);
  building.yaw_rad = 0.7;
  building.size_m = Vec3(40.0, 30.0, 60.0);
  options.extra_boxes = {building};
  const auto world =
      LidarWorld::Build(MakeStraightRoad(-50.0, 50.0, 1, kLaneWidth, low), low, options);
  const TrafficBox box = AsTrafficBox(building);
  const Mat3 r = Eigen::AngleAxisd(building.yaw_rad, Vec3::UnitZ()).toRotationMatrix();
  const Vec3 origin(-20.0, -30.0, 1.0);
  std::mt19937_64 rng = MakeRng(3, "corner rays");
  int hits = 0, misses = 0;
  for (int k = 0; k < 4000; ++k) {
    // Aim within 2 cm of a random vertical edge (or corner) of the box.
    const double sx = Uniform01(rng) < 0.5 ? -1.0 : 1.0, sy = Uniform01(rng) < 0.5 ? -1.0 : 1.0;
    const double z = (Uniform01(rng) < 0.1 ? 30.0 : 60.0 * (Uniform01(rng) - 0.5));
    const Vec3 edge = building.centre_world + r * Vec3(sx * 20.0, sy * 15.0, z) +
                      Vec3(0.04 * (Uniform01(rng) - 0.5), 0.04 * (Uniform01(rng) - 0.5),
                           0.04 * (Uniform01(rng) - 0.5));
    const Vec3 d = (edge - origin).normalized();
    const auto expected = IntersectTrafficBox(box, origin, d, 200.0);
    const auto hit = world->CastStatic(origin, d, 200.0);
    if (expected) {
      ++hits;
      ASSERT_TRUE(hit);
      ASSERT_NEAR(hit->range_m, expected->range_m, 1e-9);
      ASSERT_NEAR(hit->normal_world.dot(expected->normal_world), 1.0, 1e-9);
    } else {
      ++misses;
      EXPECT_TRUE(!hit || hit->material != SurfaceMaterial::kBuilding);
    }
  }
  EXPECT_GT(hits, 500);
  EXPECT_GT(misses, 500);
}

TEST(LidarWorld, HitsDoNotDependOnTheTiling) {
  const GroundHeightFn hills = [](double x, double y) {
    return 0.02 * x + 2.0 * std::sin(0.02 * y) + 0.5 * std::cos(0.05 * x);
  };
  const RoadGeometry roads = MakeGridRoads(3, 2, 100.0, 1, kLaneWidth, hills);
  WorldLayoutOptions layout;
  layout.seed = 9;
  const WorldLayout objects = BuildWorldLayout(roads, hills, layout);
  LidarWorldOptions a, b;
  b.ground_tile_size_m = 16.0;
  b.object_tile_size_m = 40.0;
  const LidarWorld fine(roads, hills, objects, a);
  const LidarWorld coarse(roads, hills, objects, b);
  ASSERT_NE(fine.tile_count(), coarse.tile_count());
  std::mt19937_64 rng = MakeRng(4, "tiling rays");
  int hits = 0;
  for (int k = 0; k < 20000; ++k) {
    const Vec3 origin(250.0 * Uniform01(rng) - 25.0, 150.0 * Uniform01(rng) - 25.0, 0.0);
    const Vec3 from(origin.x(), origin.y(),
                    hills(origin.x(), origin.y()) + 0.5 + 3.0 * Uniform01(rng));
    const double az = 2.0 * M_PI * Uniform01(rng), el = 0.6 * (Uniform01(rng) - 0.6);
    const Vec3 d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    const auto p = fine.CastStatic(from, d, 120.0);
    const auto q = coarse.CastStatic(from, d, 120.0);
    ASSERT_EQ(p.has_value(), q.has_value()) << k;
    if (!p) continue;
    ++hits;
    ASSERT_NEAR(p->range_m, q->range_m, 1e-9) << k;
    ASSERT_EQ(p->material, q->material) << k;
  }
  EXPECT_GT(hits, 10000);
}

TEST(LidarWorld, BadOptionsAndEmptyInputsAreRejected) {
  const GroundHeightFn flat = [](double, double) { return 0.0; };
  EXPECT_THROW(LidarWorld(RoadGeometry{}, flat, WorldLayout{}), InputError);
  LidarWorldOptions options;
  options.ground_spacing_m = 0.0;
  EXPECT_THROW(LidarWorld(MakeStraightRoad(0, 10, 1, 3.0, flat), flat, WorldLayout{}, options),
               InputError);
}

}  // namespace
}  // namespace statebench::sensors
