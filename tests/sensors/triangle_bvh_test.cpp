// The BVH kernel (LidarWorld::CastStatic) against the Bullet-walk reference kernel
// (CastStaticBullet) on the benchmarks' dense town: same hits, same ranges, same surfaces.
#include "sensors/triangle_bvh.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "bench/dense_town.hpp"
#include "core/random.hpp"

namespace statebench::sensors {
namespace {

TEST(TriangleBvh, CastsLikeTheBulletReferenceKernelOnTheDenseTown) {
  const RoadGeometry roads = bench::DenseTownRoads();
  const std::unique_ptr<LidarWorld> world = bench::BuildDenseTown(roads);
  std::mt19937_64 rng = MakeRng(11, "bvh rays");
  int hits = 0;
  int rays = 0;
  const auto check = [&](const Vec3& from, const Vec3& d, double max_range) {
    const auto p = world->CastStatic(from, d, max_range);
    const auto q = world->CastStaticBullet(from, d, max_range);
    ++rays;
    ASSERT_EQ(p.has_value(), q.has_value()) << "ray " << rays;
    if (!p) return;
    ++hits;
    ASSERT_NEAR(p->range_m, q->range_m, 1e-5) << "ray " << rays;
    ASSERT_EQ(p->material, q->material) << "ray " << rays;
    ASSERT_GT(p->normal_world.dot(q->normal_world), 1.0 - 1e-9) << "ray " << rays;
  };
  // Lidar-like rays from street level (inside the town, 0.5-3 m above the ground), any azimuth,
  // elevations from -30 to +20 degrees, and a few from outside the town and from high above.
  for (int k = 0; k < 30000; ++k) {
    const double x = 620.0 * Uniform01(rng) - 10.0;
    const double y = 620.0 * Uniform01(rng) - 10.0;
    const Vec3 from(x, y, bench::DenseTownTerrain(x, y) + 0.5 + 2.5 * Uniform01(rng));
    const double az = 2.0 * M_PI * Uniform01(rng);
    const double el = (-30.0 + 50.0 * Uniform01(rng)) * M_PI / 180.0;
    const Vec3 d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    check(from, d, 120.0);
    if (HasFatalFailure()) return;
  }
  for (int k = 0; k < 5000; ++k) {
    const Vec3 from(1400.0 * Uniform01(rng) - 400.0, 1400.0 * Uniform01(rng) - 400.0,
                    -20.0 + 120.0 * Uniform01(rng));
    const Vec3 d = Vec3(2.0 * Uniform01(rng) - 1.0, 2.0 * Uniform01(rng) - 1.0,
                        2.0 * Uniform01(rng) - 1.0)
                       .normalized();
    check(from, d, 400.0 * Uniform01(rng));
    if (HasFatalFailure()) return;
  }
  // Axis-parallel rays (zero direction components).
  for (const Vec3& d : {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0),
                        Vec3(0, 0, -1), Vec3(0, 0, 1)}) {
    for (int k = 0; k < 200; ++k) {
      const double x = 600.0 * Uniform01(rng);
      const double y = 600.0 * Uniform01(rng);
      check(Vec3(x, y, bench::DenseTownTerrain(x, y) + 1.5), d, 150.0);
      if (HasFatalFailure()) return;
    }
  }
  EXPECT_GT(hits, rays / 2);
}

// Small random soups (1 to 60 triangles: a single leaf, one node, a few levels) against the brute
// force minimum over every triangle.
TEST(TriangleBvh, MatchesBruteForceOnSmallRandomSoups) {
  std::mt19937_64 rng = MakeRng(5, "bvh soups");
  const auto random_point = [&](double half) {
    return Vec3(half * (2.0 * Uniform01(rng) - 1.0), half * (2.0 * Uniform01(rng) - 1.0),
                half * (2.0 * Uniform01(rng) - 1.0));
  };
  int hits = 0;
  for (int soup = 0; soup < 60; ++soup) {
    TriangleMesh mesh;
    const int n = 1 + soup;
    for (int k = 0; k < n; ++k) {
      const Vec3 c = random_point(20.0);
      mesh.AddTriangle(mesh.AddVertex(c + random_point(3.0)), mesh.AddVertex(c + random_point(3.0)),
                       mesh.AddVertex(c + random_point(3.0)),
                       k % 2 == 0 ? SurfaceMaterial::kBuilding : SurfaceMaterial::kGround);
    }
    const TriangleBvh bvh({&mesh}, Vec3(3.0, -2.0, 1.0));
    for (int ray = 0; ray < 300; ++ray) {
      const Vec3 o = random_point(30.0);
      const Vec3 d = (random_point(20.0) - o).normalized();
      double best = 60.0 + 1e-6;
      int best_k = -1;
      for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
        const Vec3& v0 = mesh.vertices[mesh.triangles[k][0]];
        const double r = IntersectTriangle(o, d, v0, mesh.vertices[mesh.triangles[k][1]] - v0,
                                           mesh.vertices[mesh.triangles[k][2]] - v0);
        if (r > 0.0 && r < best) {
          best = r;
          best_k = static_cast<int>(k);
        }
      }
      const auto hit = bvh.Cast(o, d, 60.0);
      ASSERT_EQ(hit.has_value(), best_k >= 0) << "soup " << soup << " ray " << ray;
      if (!hit) continue;
      ++hits;
      ASSERT_DOUBLE_EQ(hit->range_m, best) << "soup " << soup << " ray " << ray;
      ASSERT_EQ(hit->material, mesh.materials[static_cast<std::size_t>(best_k)]);
    }
  }
  EXPECT_GT(hits, 500);  // 810 of the 18,000 rays hit something
}

TEST(TriangleBvh, EmptyAndSingleLeafWorlds) {
  const TriangleBvh empty({}, Vec3::Zero());
  EXPECT_FALSE(empty.Cast(Vec3::Zero(), Vec3::UnitX(), 10.0));

  TriangleMesh mesh;
  const int a = mesh.AddVertex(Vec3(5.0, -1.0, -1.0));
  const int b = mesh.AddVertex(Vec3(5.0, 1.0, -1.0));
  const int c = mesh.AddVertex(Vec3(5.0, 0.0, 1.0));
  mesh.AddTriangle(a, b, c, SurfaceMaterial::kBuilding);
  const TriangleBvh one({&mesh}, Vec3(100.0, 0.0, 0.0));
  const auto hit = one.Cast(Vec3::Zero(), Vec3::UnitX(), 10.0);
  ASSERT_TRUE(hit);
  EXPECT_DOUBLE_EQ(hit->range_m, 5.0);
  EXPECT_EQ(hit->material, SurfaceMaterial::kBuilding);
  EXPECT_NEAR(hit->normal_world.x(), -1.0, 1e-12);  // facing the ray's origin
  EXPECT_FALSE(one.Cast(Vec3::Zero(), Vec3::UnitX(), 4.9));   // beyond the range
  EXPECT_FALSE(one.Cast(Vec3::Zero(), -Vec3::UnitX(), 10.0));  // behind the origin

  // Packets: one ray of each kind.
  const Vec3 origins[3] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  const Vec3 directions[3] = {Vec3::UnitX(), -Vec3::UnitX(), Vec3::UnitX()};
  std::optional<RayHit> packet[3];
  one.CastPacket(origins, directions, 3, 10.0, packet);
  ASSERT_TRUE(packet[0]);
  EXPECT_DOUBLE_EQ(packet[0]->range_m, 5.0);
  EXPECT_FALSE(packet[1]);
  ASSERT_TRUE(packet[2]);
  empty.CastPacket(origins, directions, 3, 10.0, packet);
  EXPECT_FALSE(packet[0] || packet[1] || packet[2]);
}

// Packets (CastPacket) against single rays (Cast) on the dense town: the same hits, the same
// ranges bit for bit, the same surfaces. Lidar-like packets (one channel of adjacent columns
// from a moving sensor, every size up to the packet size) and incoherent ones (rays from
// anywhere to anywhere, with zero direction components).
TEST(TriangleBvh, PacketsCastLikeSingleRaysOnTheDenseTown) {
  const RoadGeometry roads = bench::DenseTownRoads();
  const std::unique_ptr<LidarWorld> world = bench::BuildDenseTown(roads);
  std::mt19937_64 rng = MakeRng(12, "bvh packets");
  constexpr int kPacket = LidarWorld::kStaticPacketSize;
  int hits = 0;
  int rays = 0;
  // Both walks: the AVX2 one where this CPU has it (else the same as kSse) and the SSE one.
  const auto check = [&](const Vec3* origins, const Vec3* directions, int count, double max_range) {
    for (const auto kernel : {TriangleBvh::PacketKernel::kBest, TriangleBvh::PacketKernel::kSse}) {
      std::optional<RayHit> packet[kPacket];
      world->CastStaticPacket(origins, directions, count, max_range, packet, kernel);
      for (int k = 0; k < count; ++k) {
        const auto single = world->CastStatic(origins[k], directions[k], max_range);
        ++rays;
        ASSERT_EQ(packet[k].has_value(), single.has_value()) << "ray " << rays;
        if (!single) continue;
        ++hits;
        ASSERT_EQ(packet[k]->range_m, single->range_m) << "ray " << rays;
        ASSERT_EQ(packet[k]->material, single->material) << "ray " << rays;
        ASSERT_EQ(packet[k]->normal_world, single->normal_world) << "ray " << rays;
      }
    }
  };
  Vec3 origins[kPacket];
  Vec3 directions[kPacket];
  for (int trial = 0; trial < 1500; ++trial) {
    const int count = 1 + trial % kPacket;
    const double x = 600.0 * Uniform01(rng);
    const double y = 600.0 * Uniform01(rng);
    const Vec3 start(x, y, bench::DenseTownTerrain(x, y) + 0.5 + 2.5 * Uniform01(rng));
    const Vec3 velocity(20.0 * Uniform01(rng) - 10.0, 20.0 * Uniform01(rng) - 10.0, 0.0);
    const double az0 = 2.0 * M_PI * Uniform01(rng);
    const double el = (-20.0 + 36.0 * Uniform01(rng)) * M_PI / 180.0;
    for (int k = 0; k < count; ++k) {  // columns 50 us and 0.18 degrees apart
      const double az = az0 - k * 2.0 * M_PI / 2000.0;
      origins[k] = start + 50e-6 * k * velocity;
      directions[k] = Vec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    }
    check(origins, directions, count, 120.0);
    if (HasFatalFailure()) return;
  }
  for (int trial = 0; trial < 400; ++trial) {
    const int count = 1 + trial % kPacket;
    for (int k = 0; k < count; ++k) {
      origins[k] = Vec3(800.0 * Uniform01(rng) - 100.0, 800.0 * Uniform01(rng) - 100.0,
                        -5.0 + 40.0 * Uniform01(rng));
      directions[k] = Vec3(2.0 * Uniform01(rng) - 1.0, 2.0 * Uniform01(rng) - 1.0,
                           2.0 * Uniform01(rng) - 1.0)
                          .normalized();
      if (k % 5 == 0) directions[k] = Vec3::Unit(k % 3) * (k % 2 == 0 ? 1.0 : -1.0);
    }
    check(origins, directions, count, 300.0 * Uniform01(rng));
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(hits, rays / 2);
}

}  // namespace
}  // namespace statebench::sensors
