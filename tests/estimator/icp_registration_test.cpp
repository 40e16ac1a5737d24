#include "estimator/icp_registration.hpp"

#include <gtest/gtest.h>

#include "estimator/lidar_preprocessing.hpp"
#include "tests/estimator/synthetic_lidar_scene.hpp"

namespace statebench::est {
namespace {

constexpr double kVoxel = 1.0;

struct Pair {
  VoxelHashMap map{{.voxel_size_m = kVoxel, .max_points_per_voxel = 20, .max_range_m = 100.0}};
  std::vector<Vec3> source;  // scan B, downsampled for registration
};

// Map from a scan at T_world_a (world frame), source from a scan at T_world_b.
Pair MakePair(const testing::Scene& scene, const SE3& T_world_a, const SE3& T_world_b) {
  Pair pair;
  testing::ScannerModel model;
  model.range_noise_m = 0.01;
  const auto a =
      PositionsOf(FilterScanPoints(testing::StaticScan(scene, T_world_a, model, 1), {}, nullptr));
  const auto b =
      PositionsOf(FilterScanPoints(testing::StaticScan(scene, T_world_b, model, 2), {}, nullptr));
  pair.map.Update(a, T_world_a);  // full resolution: up to 20 points per voxel
  pair.source = VoxelDownsample(VoxelDownsample(b, 0.5 * kVoxel), 1.5 * kVoxel);
  return pair;
}

SE3 PoseAt(double x, double y, double yaw_deg, double roll_deg = 0.0) {
  return SE3(Quat(so3::FromRollPitchYaw(roll_deg * M_PI / 180.0, 0.0, yaw_deg * M_PI / 180.0)),
             Vec3(x, y, 1.8));
}

double RotationErrorDeg(const SE3& a, const SE3& b) {
  return so3::Log(a.rotation().inverse() * b.rotation()).norm() * 180.0 / M_PI;
}

TEST(IcpRegistration, RecoversKnownRigidTransformInStructuredScene) {
  const testing::Scene scene = testing::StructuredStreet();
  const SE3 T_world_a = PoseAt(0.0, 0.0, 0.0);
  const SE3 T_world_b = PoseAt(1.2, 0.4, 2.5, 0.5);
  const Pair pair = MakePair(scene, T_world_a, T_world_b);
  for (IcpMetric metric : {IcpMetric::kSurfaceProjected, IcpMetric::kPointToPoint}) {
    IcpOptions options;
    options.metric = metric;
    const IcpResult r = RegisterScanToMap(pair.source, pair.map, T_world_a, 2.0, 0.5, options);
    ASSERT_TRUE(r.ok) << r.failure;
    const double dt = (r.T_map_scan.translation() - T_world_b.translation()).norm();
    const double dr = RotationErrorDeg(r.T_map_scan, T_world_b);
    const std::string name = metric == IcpMetric::kPointToPoint ? "p2p" : "projected";
    RecordProperty(name + "_translation_error_m", std::to_string(dt));
    RecordProperty(name + "_rotation_error_deg", std::to_string(dr));
    std::printf("%s: %zu source points, %d iterations, error %.4f m %.4f deg, sigma %.4f\n",
                name.c_str(), pair.source.size(), r.iterations, dt, dr, r.residual_sigma_m);
    EXPECT_TRUE(r.converged);
    if (metric == IcpMetric::kSurfaceProjected) {
      EXPECT_LT(dt, 0.01);
      EXPECT_LT(dr, 0.05);
      EXPECT_FALSE(r.degenerate);
      const double max_var = r.covariance.topLeftCorner<3, 3>().diagonal().maxCoeff();
      EXPECT_LT(max_var, 1e-2);
    } else {
      // Plain point-to-point ICP sticks to the rings of the sparse scans: it recovers less
      // than half of the 1.26 m motion (the forward-motion under-estimate the projected metric
      // removes). Measured, not required; the check keeps the comparison honest.
      EXPECT_GT(dt, 0.1);
    }
  }
}

TEST(IcpRegistration, CorridorIsDegenerateAlongItsAxis) {
  const testing::Scene corridor = testing::Corridor();
  const SE3 T_world_a = PoseAt(0.0, 0.0, 0.0);
  const SE3 T_world_b = PoseAt(1.0, 0.1, 1.0);
  const Pair pair = MakePair(corridor, T_world_a, T_world_b);
  const IcpResult r = RegisterScanToMap(pair.source, pair.map, T_world_a, 2.0, 0.5, {});
  ASSERT_TRUE(r.ok) << r.failure;
  EXPECT_TRUE(r.degenerate);
  EXPECT_EQ(r.degenerate_directions, 1);
  // The weakest direction is translation along the corridor (world x = scan x rotated 1 deg),
  // with little information (measured 10 point-equivalents, from the noise of the estimated
  // normals; the next direction has 17).
  EXPECT_LT(r.scaled_eigenvalues(0), IcpOptions{}.min_information);
  const Vec6 weakest = r.scaled_eigenvectors.col(0);
  const Vec3 axis_scan = r.T_map_scan.rotation().inverse() * Vec3::UnitX();
  EXPECT_GT(std::abs(weakest.head<3>().dot(axis_scan)), 0.99);
  // Its variance along the axis dwarfs the across-axis one.
  const Mat3 cov_t = r.covariance.topLeftCorner<3, 3>();
  const double var_axis = axis_scan.dot(cov_t * axis_scan);
  const Vec3 across = r.T_map_scan.rotation().inverse() * Vec3::UnitY();
  const double var_across = across.dot(cov_t * across);
  std::printf("corridor: var along %.3g, across %.3g, eigenvalues %s\n", var_axis, var_across,
              ::testing::PrintToString(r.scaled_eigenvalues.transpose()).c_str());
  EXPECT_GE(var_axis, IcpOptions{}.degenerate_variance * 0.99);
  EXPECT_GT(var_axis, 1e4 * var_across);
  // Across the corridor the registration is still right.
  const Vec3 err = r.T_map_scan.translation() - T_world_b.translation();
  EXPECT_LT(std::abs(err.y()), 0.01);
  EXPECT_LT(std::abs(err.z()), 0.01);
}

TEST(IcpRegistration, StructuredSceneCovarianceIsNotInflated) {
  const testing::Scene scene = testing::StructuredStreet();
  const Pair pair = MakePair(scene, PoseAt(0, 0, 0), PoseAt(0.5, 0, 0));
  const IcpResult r = RegisterScanToMap(pair.source, pair.map, PoseAt(0, 0, 0), 2.0, 0.5, {});
  ASSERT_TRUE(r.ok);
  EXPECT_FALSE(r.degenerate);
  EXPECT_LT(r.covariance(0, 0), 1e-3);
}

TEST(IcpRegistration, FailsWithReasonOnEmptyMapOrTooFewCorrespondences) {
  VoxelHashMap empty({});
  const IcpResult r1 = RegisterScanToMap({Vec3(1, 0, 0)}, empty, SE3(), 2.0, 0.5, {});
  EXPECT_FALSE(r1.ok);
  EXPECT_EQ(r1.failure, "empty map");
  VoxelHashMap map({});
  map.AddPoints({Vec3(1, 0, 0), Vec3(2, 0, 0)});
  const IcpResult r2 = RegisterScanToMap({Vec3(1, 0, 0)}, map, SE3(), 2.0, 0.5, {});
  EXPECT_FALSE(r2.ok);
  EXPECT_NE(r2.failure.find("too few correspondences"), std::string::npos);
}

}  // namespace
}  // namespace statebench::est
