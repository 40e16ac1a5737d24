#include "estimator/voxel_hash_map.hpp"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace statebench::est
