#include "estimator/lidar_preprocessing.hpp"

#include <gtest/gtest.h>

#include <limits>

#include "tests/estimator/synthetic_lidar_scene.hpp"

namespace statebench::est {
namespace {

TEST(LidarPreprocessing, DropsNonFiniteAndOutOfRangePointsAndCountsThem) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<LidarPoint> points = {{5, 0, 0, 1, 0, 0},    {nan, 0, 0, 1, 0, 0},
                                    {0, inf, 0, 1, 0, 0},  {3, 0, 0, 1, nan, 0},
                                    {0.2f, 0, 0, 1, 0, 0}, {150, 0, 0, 1, 0, 0}};
  LidarFilterStats stats;
  const auto kept = FilterScanPoints(points, {.min_range_m = 1.0, .max_range_m = 100.0}, &stats);
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_EQ(kept[0].p_lidar.x(), 5.0);
  EXPECT_EQ(stats.points_in, 6u);
  EXPECT_EQ(stats.non_finite, 3u);
  EXPECT_EQ(stats.out_of_range, 2u);
  EXPECT_EQ(stats.kept, 1u);
}

TEST(LidarPreprocessing, VoxelDownsampleKeepsOnePointPerVoxel) {
  std::vector<Vec3> points;
  for (int i = 0; i < 100; ++i) points.emplace_back(0.01 * i, 0.3, -0.3);  // x in [0, 1)
  const auto out = VoxelDownsample(points, 0.5);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].x(), 0.0);  // first of each voxel, in input order
  EXPECT_NEAR(out[1].x(), 0.5, 1e-12);
}

// Mean distance to the scene's surfaces of stamp-frame points placed at the stamp pose.
double MeanSurfaceDistance(const testing::Scene& scene, const SE3& T_world_stamp,
                           const std::vector<Vec3>& points_stamp) {
  double sum = 0.0;
  for (const Vec3& p : points_stamp) sum += scene.SurfaceDistance(T_world_stamp * p);
  return sum / static_cast<double>(points_stamp.size());
}

// Found by fuzz_estimators: a garbage point 2e10 voxels away made the voxel index cast undefined
// (UBSan). Such points are dropped; the others are kept as before.
TEST(LidarPreprocessing, VoxelDownsampleDropsPointsBeyondAnyVoxelIndex) {
  const std::vector<Vec3> points = {Vec3(1.0, 2.0, 0.5), Vec3(1e10, 0.0, 0.0),
                                    Vec3(0.0, -1e12, 3.0)};
  const auto out = VoxelDownsample(points, 0.5);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0], points[0]);
}

TEST(LidarPreprocessing, DeskewWithTrueMotionRemovesDistortion) {
  // 15 m/s forward with a 30 deg/s yaw rate: 1.5 m and 3 deg during the 0.1 s sweep.
  const testing::Scene scene = testing::StructuredStreet();
  Vec6 twist;
  twist << 15.0, 0.0, 0.0, 0.0, 0.0, 30.0 * M_PI / 180.0;
  const SE3 T_world_start(Quat::Identity(), Vec3(0, 0, 1.8));
  auto pose = [&](double t) { return T_world_start * SE3::Exp(t * twist); };
  const auto moving = testing::Scan(scene, pose);
  const auto timed = FilterScanPoints(moving, {}, nullptr);
  ASSERT_GT(timed.size(), 10000u);

  const SweepMotion truth_motion = [&](double t) { return SE3::Exp(t * twist); };
  const double raw_error = MeanSurfaceDistance(scene, T_world_start, PositionsOf(timed));
  const double deskewed_error =
      MeanSurfaceDistance(scene, T_world_start, DeskewPoints(timed, truth_motion));
  const double static_error =
      MeanSurfaceDistance(scene, T_world_start, DeskewPoints(timed, StaticSweepMotion()));
  RecordProperty("raw_error_m", std::to_string(raw_error));
  RecordProperty("deskewed_error_m", std::to_string(deskewed_error));
  EXPECT_GT(raw_error, 0.2);  // the distortion is real
  EXPECT_EQ(static_error, raw_error);
  EXPECT_LT(deskewed_error, 1e-4);  // float storage of the points only
}

TEST(LidarPreprocessing, ConstantVelocityMotionInterpolatesThePreviousMotion) {
  Vec6 xi;
  xi << 1.0, 0.2, 0.0, 0.0, 0.0, 0.1;
  const SE3 T_prev_curr = SE3::Exp(xi);
  const SweepMotion motion = ConstantVelocitySweepMotion(T_prev_curr, 0.1);
  EXPECT_LT((motion(0.1).Log() - xi).norm(), 1e-12);
  EXPECT_LT((motion(0.05).Log() - 0.5 * xi).norm(), 1e-12);
  EXPECT_LT(motion(0.0).Log().norm(), 1e-15);
}

// The tabulated motion is SE3::Interpolate between the table's neighbouring poses, held beyond
// the ends, bit for bit (it keeps each segment's logarithm instead of taking it per call).
TEST(LidarPreprocessing, TabulatedMotionIsTheInterpolationOfItsTable) {
  std::vector<std::pair<double, SE3>> table;
  for (int k = 0; k <= 20; ++k) {
    Vec6 xi;
    xi << 0.1 * k, 0.01 * k * k, -0.002 * k, 0.001 * k, -0.0005 * k * k, 0.02 * k;
    table.emplace_back(0.005 * k, SE3::Exp(xi));
  }
  const SweepMotion motion = TabulatedSweepMotion(table);
  const auto expected = [&](double ts) {
    if (ts <= table.front().first) return table.front().second;
    for (std::size_t k = 1; k < table.size(); ++k) {
      if (ts <= table[k].first) {
        const double a = (ts - table[k - 1].first) / (table[k].first - table[k - 1].first);
        return SE3::Interpolate(table[k - 1].second, table[k].second, a);
      }
    }
    return table.back().second;
  };
  std::vector<double> times = {-1.0, 0.0, 0.1, 0.2, 0.5, std::numeric_limits<double>::quiet_NaN()};
  for (int i = 0; i <= 1000; ++i) times.push_back(0.0001 * i + 1e-7);
  for (int k = 0; k <= 20; ++k) times.push_back(0.005 * k);
  for (const double ts : times) {
    const SE3 got = motion(ts);
    const SE3 want = expected(ts);
    EXPECT_EQ(got.rotation().coeffs(), want.rotation().coeffs()) << ts;
    EXPECT_EQ(got.translation(), want.translation()) << ts;
  }
}

}  // namespace
}  // namespace statebench::est
