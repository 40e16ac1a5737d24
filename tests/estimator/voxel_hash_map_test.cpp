#include "estimator/voxel_hash_map.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <tuple>
#include <vector>

namespace statebench::est {
namespace {

TEST(VoxelHashMap, KeepsAtMostMaxPointsPerVoxel) {
  VoxelHashMap map({.voxel_size_m = 1.0, .max_points_per_voxel = 20, .max_range_m = 100.0});
  std::vector<Vec3> points;
  for (int i = 0; i < 50; ++i) points.emplace_back(0.1 + 0.01 * i, 0.5, 0.5);  // one voxel
  map.AddPoints(points);
  EXPECT_EQ(map.NumVoxels(), 1u);
  EXPECT_EQ(map.Points().size(), 20u);
}

TEST(VoxelHashMap, NearestNeighborSearchesNeighbouringVoxels) {
  VoxelHashMap map({.voxel_size_m = 1.0, .max_points_per_voxel = 20, .max_range_m = 100.0});
  map.AddPoints({Vec3(1.05, 0.5, 0.5), Vec3(-0.9, 0.5, 0.5), Vec3(3.5, 0.5, 0.5)});
  Vec3 nearest;
  double d = 0.0;
  ASSERT_TRUE(map.NearestNeighbor(Vec3(0.95, 0.5, 0.5), &nearest, &d));
  EXPECT_NEAR(nearest.x(), 1.05, 1e-12);  // in the next voxel
  EXPECT_NEAR(d, 0.1, 1e-12);
  // Two voxels away is outside the 27-voxel neighbourhood.
  EXPECT_FALSE(map.NearestNeighbor(Vec3(5.9, 0.5, 0.5), &nearest, &d));
  // Negative coordinates use floor, not truncation.
  ASSERT_TRUE(map.NearestNeighbor(Vec3(-0.2, 0.5, 0.5), &nearest, &d));
  EXPECT_NEAR(nearest.x(), -0.9, 1e-12);
}

TEST(VoxelHashMap, RemovesVoxelsBeyondMaxRange) {
  VoxelHashMap map({.voxel_size_m = 1.0, .max_points_per_voxel = 20, .max_range_m = 10.0});
  map.AddPoints({Vec3(5.5, 0.5, 0.5), Vec3(15.5, 0.5, 0.5), Vec3(-9.5, 0.5, 0.5)});
  map.RemoveVoxelsFarFrom(Vec3(0, 0, 0));
  EXPECT_EQ(map.NumVoxels(), 2u);
  map.Update({}, SE3(Quat::Identity(), Vec3(10.0, 0.0, 0.0)));  // vehicle moved forward
  const std::vector<Vec3> left = map.Points();
  ASSERT_EQ(left.size(), 1u);
  EXPECT_NEAR(left[0].x(), 5.5, 1e-12);
}

TEST(VoxelHashMap, UpdateTransformsPointsToWorld) {
  VoxelHashMap map({.voxel_size_m = 0.5, .max_points_per_voxel = 20, .max_range_m = 100.0});
  const SE3 T_world_lidar(Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ())), Vec3(1, 2, 3));
  map.Update({Vec3(1, 0, 0)}, T_world_lidar);
  Vec3 nearest;
  double d = 0.0;
  ASSERT_TRUE(map.NearestNeighbor(Vec3(1, 3, 3), &nearest, &d));
  EXPECT_NEAR(d, 0.0, 1e-12);
}

// ---- Queries against brute force ----------------------------------------------------------

using MapQueryVoxel = std::tuple<int, int, int>;

MapQueryVoxel MapQueryVoxelOf(const Vec3& p, double voxel_m) {
  return {static_cast<int>(std::floor(p.x() / voxel_m)),
          static_cast<int>(std::floor(p.y() / voxel_m)),
          static_cast<int>(std::floor(p.z() / voxel_m))};
}

// What the map should hold, kept the plain way: each voxel's points in arrival order.
struct MapQueryReference {
  VoxelHashMapOptions options;
  std::map<MapQueryVoxel, std::vector<Vec3>> voxels;

  void Add(const std::vector<Vec3>& points) {
    for (const Vec3& p : points) {
      std::vector<Vec3>& in_voxel = voxels[MapQueryVoxelOf(p, options.voxel_size_m)];
      if (static_cast<int>(in_voxel.size()) < options.max_points_per_voxel) in_voxel.push_back(p);
    }
  }
  void RemoveFarFrom(const Vec3& origin) {
    std::erase_if(voxels, [&](const auto& voxel) {
      return (voxel.second.front() - origin).norm() > options.max_range_m;
    });
  }
};

// Random points in [-half_width, half_width)^3 (seeded), on a grid of `step` metres (0:
// continuous): on a grid, distances tie exactly and points sit exactly on voxel faces and at
// the query radii.
std::vector<Vec3> MapQueryRandomPoints(std::mt19937* rng, int count, double half_width,
                                       double step) {
  std::uniform_real_distribution<double> u(-half_width, half_width);
  std::vector<Vec3> points;
  for (int i = 0; i < count; ++i) {
    Vec3 p(u(*rng), u(*rng), u(*rng));
    if (step > 0.0) p = (p / step).array().floor().matrix() * step;
    points.push_back(p);
  }
  return points;
}

// NearestNeighbor and NeighborsWithin against brute force over the reference: the same points,
// bit for bit, in the documented order (nearest: the first of equally close points, voxels
// visited by offset 0, -1, 1 per axis with x outermost, each voxel's points in arrival order;
// within: voxels by offset from -reach to reach with z innermost, then arrival order).
void ExpectQueriesMatchBruteForce(const VoxelHashMap& map, const MapQueryReference& reference,
                                  const std::vector<Vec3>& queries,
                                  const std::vector<double>& radii_m) {
  const double v = map.options().voxel_size_m;
  auto rank = [](int d) { return d == 0 ? 0 : (d == -1 ? 1 : 2); };
  std::vector<Vec3> out;
  int found_nearest = 0, found_within = 0;
  for (const Vec3& q : queries) {
    const auto [cx, cy, cz] = MapQueryVoxelOf(q, v);
    // Nearest neighbour among the 27 voxels around q's.
    const Vec3* best = nullptr;
    double best2 = 0.0;
    std::tuple<int, int, int, std::size_t> best_order;
    for (const auto& [voxel, points] : reference.voxels) {
      const auto [x, y, z] = voxel;
      if (std::abs(x - cx) > 1 || std::abs(y - cy) > 1 || std::abs(z - cz) > 1) continue;
      for (std::size_t k = 0; k < points.size(); ++k) {
        const double d2 = (points[k] - q).squaredNorm();
        const std::tuple<int, int, int, std::size_t> order{rank(x - cx), rank(y - cy), rank(z - cz),
                                                           k};
        if (best == nullptr || d2 < best2 || (d2 == best2 && order < best_order)) {
          best = &points[k];
          best2 = d2;
          best_order = order;
        }
      }
    }
    Vec3 nearest;
    double d = -1.0;
    ASSERT_EQ(map.NearestNeighbor(q, &nearest, &d), best != nullptr);
    if (best != nullptr) {
      ++found_nearest;
      ASSERT_EQ(nearest, *best) << "query " << q.transpose();
      ASSERT_EQ(d, std::sqrt(best2));
    }
    // Neighbours within each radius.
    for (const double r : radii_m) {
      const int reach = std::max(1, static_cast<int>(std::ceil(r / v)));
      std::vector<std::pair<std::tuple<int, int, int, std::size_t>, Vec3>> expected;
      for (const auto& [voxel, points] : reference.voxels) {
        const auto [x, y, z] = voxel;
        if (std::abs(x - cx) > reach || std::abs(y - cy) > reach || std::abs(z - cz) > reach) {
          continue;
        }
        for (std::size_t k = 0; k < points.size(); ++k) {
          if ((points[k] - q).squaredNorm() > r * r) continue;
          expected.push_back({{x - cx, y - cy, z - cz, k}, points[k]});
        }
      }
      std::sort(expected.begin(), expected.end(),
                [](const auto& a, const auto& b) { return a.first < b.first; });
      map.NeighborsWithin(q, r, &out);  // `out` reused: stale contents must not leak
      ASSERT_EQ(out.size(), expected.size()) << "query " << q.transpose() << " radius " << r;
      for (std::size_t i = 0; i < out.size(); ++i) ASSERT_EQ(out[i], expected[i].second);
      found_within += static_cast<int>(out.size());
    }
  }
  // The queries were not all trivially empty.
  EXPECT_GT(found_nearest, static_cast<int>(queries.size()) / 2);
  EXPECT_GT(found_within, static_cast<int>(queries.size()));
}

TEST(VoxelHashMap, QueriesMatchBruteForceOnAGridWithTiesAndBoundaries) {
  std::mt19937 rng(99);
  // Voxel 0.5 m, a grid of 0.125 m: more points per voxel than the 6 kept, exact ties, points
  // on voxel faces and exactly at the radii (0.5, 1.0, 1.375 m: reaches 1, 2 and 3).
  MapQueryReference reference{
      .options = {.voxel_size_m = 0.5, .max_points_per_voxel = 6, .max_range_m = 3.0}};
  VoxelHashMap map(reference.options);
  const std::vector<Vec3> first = MapQueryRandomPoints(&rng, 6000, 4.0, 0.125);
  map.AddPoints(first);
  reference.Add(first);
  ExpectQueriesMatchBruteForce(map, reference, MapQueryRandomPoints(&rng, 300, 4.5, 0.125),
                               {0.5, 1.0, 1.375});
  // Voxels removed (the last ones moving into the holes), then more points added.
  const std::size_t voxels_before = map.NumVoxels();
  map.RemoveVoxelsFarFrom(Vec3(1.0, 0.5, 0.0));
  reference.RemoveFarFrom(Vec3(1.0, 0.5, 0.0));
  ASSERT_EQ(map.NumVoxels(), reference.voxels.size());
  ASSERT_LT(map.NumVoxels(), voxels_before);
  const std::vector<Vec3> second = MapQueryRandomPoints(&rng, 3000, 4.0, 0.125);
  map.AddPoints(second);
  reference.Add(second);
  ASSERT_EQ(map.NumVoxels(), reference.voxels.size());
  ExpectQueriesMatchBruteForce(map, reference, MapQueryRandomPoints(&rng, 300, 4.5, 0.125),
                               {0.5, 1.375});
}

TEST(VoxelHashMap, QueriesMatchBruteForceOnContinuousPoints) {
  std::mt19937 rng(5);
  MapQueryReference reference{
      .options = {.voxel_size_m = 1.0, .max_points_per_voxel = 20, .max_range_m = 100.0}};
  VoxelHashMap map(reference.options);
  const std::vector<Vec3> points = MapQueryRandomPoints(&rng, 8000, 4.0, 0.0);
  map.AddPoints(points);
  reference.Add(points);
  ExpectQueriesMatchBruteForce(map, reference, MapQueryRandomPoints(&rng, 300, 5.0, 0.0),
                               {0.3, 1.0, 3.0});
}

TEST(VoxelHashMap, QueriesMatchBruteForceWithReachBeyondOneColumnAndWindow) {
  // Voxel 0.1 m, radius 1.7 m: a reach of 17 voxels (35 per axis: two column stretches, more
  // bricks than a window holds).
  std::mt19937 rng(8);
  MapQueryReference reference{
      .options = {.voxel_size_m = 0.1, .max_points_per_voxel = 3, .max_range_m = 100.0}};
  VoxelHashMap map(reference.options);
  const std::vector<Vec3> points = MapQueryRandomPoints(&rng, 4000, 1.0, 0.0);
  map.AddPoints(points);
  reference.Add(points);
  ExpectQueriesMatchBruteForce(map, reference, MapQueryRandomPoints(&rng, 40, 1.2, 0.0),
                               {0.05, 1.7});
}

// A proof, wherever NearestNeighborFromProof accepts it, gives what a search gives (point and
// distance bits); it is accepted for most small moves; it is refused across a voxel face, for
// far moves and under exact ties (a grid: the proof must not single out one of equal points).
TEST(VoxelHashMap, NearestNeighborFromProofGivesTheSearchAnswerWhereItApplies) {
  std::mt19937 rng(17);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (const double step : {0.0, 0.125}) {
    const VoxelHashMapOptions options{
        .voxel_size_m = 0.5, .max_points_per_voxel = 20, .max_range_m = 100.0};
    VoxelHashMap map(options);
    map.AddPoints(MapQueryRandomPoints(&rng, 5000, 4.0, step));
    int used_small = 0, small = 0, used_far = 0;
    for (const Vec3& q0 : MapQueryRandomPoints(&rng, 400, 4.0, step)) {
      NearestNeighborProof proof;
      Vec3 nearest;
      double d = 0.0;
      if (!map.NearestNeighbor(q0, &nearest, &d, &proof)) {
        EXPECT_FALSE(proof.valid);
        EXPECT_FALSE(map.NearestNeighborFromProof(proof, q0, &nearest, &d));
        continue;
      }
      for (const double move_m : {0.0, 1e-4, 1e-3, 1e-2, 0.1, 0.3, 1.0}) {
        const Vec3 direction(normal(rng), normal(rng), normal(rng));
        const Vec3 q = q0 + move_m * direction.normalized();
        Vec3 from_proof, searched;
        double d_proof = 0.0, d_searched = 0.0;
        const bool applies = map.NearestNeighborFromProof(proof, q, &from_proof, &d_proof);
        const bool found = map.NearestNeighbor(q, &searched, &d_searched);
        if (move_m <= 1e-3) ++small;
        if (!applies) continue;
        ASSERT_TRUE(found);
        ASSERT_EQ(from_proof, searched) << q.transpose();
        ASSERT_EQ(d_proof, d_searched);
        if (move_m <= 1e-3) ++used_small;
        if (move_m >= 1.0) ++used_far;
      }
    }
    if (step == 0.0) EXPECT_GT(used_small, small * 3 / 4);
    EXPECT_EQ(used_far, 0);  // two voxels away: never the same voxel
  }
}

}  // namespace
}  // namespace statebench::est
