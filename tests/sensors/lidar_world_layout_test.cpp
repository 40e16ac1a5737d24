#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "sensors/synthetic_roads.hpp"
#include "sensors/world_layout.hpp"

namespace statebench::sensors {
namespace {

constexpr double kBlock = 120.0;
constexpr double kLayoutLaneWidth = 3.5;

double Hills(double x, double y) { return 0.02 * x + 3.0 * std::sin(0.01 * y); }

// A ring road (radius 90 m, centre (500, 0)), both directions: curved edges.
void AddRingRoad(RoadGeometry* roads) {
  for (const double offset : {-0.5 * kLayoutLaneWidth, 0.5 * kLayoutLaneWidth}) {
    LaneShape lane;
    lane.width_m = kLayoutLaneWidth;
    for (int i = 0; i <= 72; ++i) {
      const double a = (offset > 0 ? 1 : -1) * 2.0 * std::numbers::pi * i / 72;
      const double r = 90.0 + offset;
      lane.centre.emplace_back(500.0 + r * std::cos(a), r * std::sin(a), 0.0);
    }
    roads->lanes.push_back(lane);
  }
}

RoadGeometry TestRoads() {
  RoadGeometry roads = MakeGridRoads(3, 3, kBlock, 1, kLayoutLaneWidth, Hills);
  AddRingRoad(&roads);
  return roads;
}

// Independent brute-force check of a footprint: sample it densely and test every sample against
// every lane segment and junction square of the network.
double MinDistanceToRoads(const RoadGeometry& roads, const std::vector<Vec2>& samples) {
  double best = 1e9;
  for (const Vec2& p : samples) {
    for (const LaneShape& lane : roads.lanes) {
      for (std::size_t i = 0; i + 1 < lane.centre.size(); ++i) {
        const Vec2 a = lane.centre[i].head<2>(), b = lane.centre[i + 1].head<2>();
        const double u = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
        best = std::min(best, (p - a - u * (b - a)).norm() - 0.5 * lane.width_m);
      }
    }
    for (const auto& j : roads.junctions) {  // axis-aligned squares here
      const double dx = std::max({j[0].x() - p.x(), 0.0, p.x() - j[2].x()});
      const double dy = std::max({j[0].y() - p.y(), 0.0, p.y() - j[2].y()});
      best = std::min(best, std::hypot(dx, dy));
    }
  }
  return best;
}

std::vector<Vec2> BoxSamples(const WorldBox& b) {
  std::vector<Vec2> out;
  const Vec2 u(std::cos(b.yaw_rad), std::sin(b.yaw_rad)), v(-u.y(), u.x());
  const int nu = static_cast<int>(std::ceil(b.size_m.x() / 0.25));
  const int nv = static_cast<int>(std::ceil(b.size_m.y() / 0.25));
  for (int i = 0; i <= nu; ++i) {
    for (int j = 0; j <= nv; ++j) {
      out.push_back(b.centre_world.head<2>() +
                    (static_cast<double>(i) / nu - 0.5) * b.size_m.x() * u +
                    (static_cast<double>(j) / nv - 0.5) * b.size_m.y() * v);
    }
  }
  return out;
}

std::vector<Vec2> CircleSamples(const Vec3& centre, double radius) {
  std::vector<Vec2> out;
  for (int i = 0; i < 32; ++i) {
    const double a = 2.0 * std::numbers::pi * i / 32;
    out.push_back(centre.head<2>() + radius * Vec2(std::cos(a), std::sin(a)));
  }
  return out;
}

TEST(WorldLayout, NoObjectOverlapsARoad) {
  const RoadGeometry roads = TestRoads();
  WorldLayoutOptions options;
  options.seed = 7;
  const WorldLayout layout = BuildWorldLayout(roads, Hills, options);

  int buildings = 0, kerbs = 0, cars = 0;
  for (const WorldBox& b : layout.boxes) {
    const double d = MinDistanceToRoads(roads, BoxSamples(b));
    switch (b.material) {
      case SurfaceMaterial::kBuilding:
        ++buildings;
        EXPECT_GE(d, options.buildings.road_clearance_m - 1e-9);
        break;
      case SurfaceMaterial::kKerb:
        ++kerbs;
        EXPECT_GT(d, 0.0);
        break;
      default:
        ++cars;
        EXPECT_GT(d, 0.0);
    }
  }
  for (const WorldCylinder& c : layout.cylinders) {
    EXPECT_GT(MinDistanceToRoads(roads, CircleSamples(c.base_world, c.radius_m)), 0.0);
  }
  for (const WorldSphere& s : layout.spheres) {
    EXPECT_GT(MinDistanceToRoads(roads, CircleSamples(s.centre_world, s.radius_m)), 0.0);
  }
  // Not vacuous: the grid's 12 streets and the ring are lined with objects.
  EXPECT_GT(buildings, 60);
  EXPECT_GT(kerbs, 500);
  EXPECT_GT(cars, 10);
  EXPECT_GT(layout.cylinders.size(), 40u);
  EXPECT_GT(layout.spheres.size(), 10u);
  RecordProperty("buildings", buildings);
}

TEST(WorldLayout, BuildingsStandOnTheGroundAndDoNotOverlapEachOther) {
  const RoadGeometry roads = TestRoads();
  WorldLayoutOptions options;
  options.seed = 3;
  const WorldLayout layout = BuildWorldLayout(roads, Hills, options);
  for (const WorldBox& b : layout.boxes) {
    if (b.material != SurfaceMaterial::kBuilding) continue;
    const double bottom = b.centre_world.z() - 0.5 * b.size_m.z();
    for (const Vec2& p : BoxSamples(b)) EXPECT_LT(bottom, Hills(p.x(), p.y()));
    EXPECT_GE(b.size_m.z(), options.buildings.height_min_m);
  }
}

TEST(WorldLayout, SameSeedSameWorldDifferentSeedDifferentWorld) {
  const RoadGeometry roads = TestRoads();
  WorldLayoutOptions options;
  options.seed = 11;
  const WorldLayout a = BuildWorldLayout(roads, Hills, options);
  const WorldLayout b = BuildWorldLayout(roads, Hills, options);
  options.seed = 12;
  const WorldLayout c = BuildWorldLayout(roads, Hills, options);
  ASSERT_EQ(a.boxes.size(), b.boxes.size());
  for (std::size_t i = 0; i < a.boxes.size(); ++i) {
    EXPECT_EQ(a.boxes[i].centre_world, b.boxes[i].centre_world);
    EXPECT_EQ(a.boxes[i].size_m, b.boxes[i].size_m);
  }
  ASSERT_EQ(a.spheres.size(), b.spheres.size());
  bool differs = a.boxes.size() != c.boxes.size();
  for (std::size_t i = 0; !differs && i < a.boxes.size(); ++i) {
    differs = a.boxes[i].centre_world != c.boxes[i].centre_world;
  }
  EXPECT_TRUE(differs);
}

TEST(WorldLayout, KerbsOnlyOnOuterEdgesAndOutsideJunctions) {
  const RoadGeometry roads = MakeGridRoads(2, 1, kBlock, 2, kLayoutLaneWidth, Hills);
  WorldLayoutOptions options;
  options.buildings.enabled = false;
  const WorldLayout layout = BuildWorldLayout(roads, Hills, options);
  int kerbs = 0;
  for (const WorldBox& b : layout.boxes) {
    if (b.material != SurfaceMaterial::kKerb) continue;
    ++kerbs;
    // The street runs along x at y = 0 with 2 x 2 lanes: kerbs sit just beyond |y| = 7 m.
    EXPECT_NEAR(std::abs(b.centre_world.y()), 2 * kLayoutLaneWidth + 0.02 + 0.125, 1e-6);
    EXPECT_GT(b.centre_world.x(), 2 * kLayoutLaneWidth + 1.0);
    EXPECT_LT(b.centre_world.x(), kBlock - 2 * kLayoutLaneWidth - 1.0);
    // Top 13 cm above the road.
    const double top = b.centre_world.z() + 0.5 * b.size_m.z();
    EXPECT_NEAR(top - Hills(b.centre_world.x(), b.centre_world.y()), 0.13, 1e-9);
  }
  // Two sides of ~106 m in 2 m pieces.
  EXPECT_GE(kerbs, 100);
}

TEST(WorldLayout, BadOptionsNameTheField) {
  WorldLayoutOptions options;
  options.buildings.height_min_m = 30.0;
  options.buildings.height_max_m = 10.0;
  try {
    BuildWorldLayout(TestRoads(), Hills, options);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("buildings.height"), std::string::npos);
  }
}

}  // namespace
}  // namespace statebench::sensors
