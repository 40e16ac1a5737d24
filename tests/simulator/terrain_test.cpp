#include "simulator/terrain.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"

namespace statebench::sim {
namespace {

// A street grid (lanes every 60 m over 480 m x 360 m) sampled from a height function.
template <typename F>
std::vector<std::vector<Vec3>> StreetGrid(F height) {
  std::vector<std::vector<Vec3>> lanes;
  for (double y = 0.0; y <= 360.0; y += 60.0) {
    std::vector<Vec3> lane;
    for (double x = 0.0; x <= 480.0; x += 10.0) lane.emplace_back(x, y, height(x, y));
    lanes.push_back(lane);
  }
  for (double x = 0.0; x <= 480.0; x += 60.0) {
    std::vector<Vec3> lane;
    for (double y = 0.0; y <= 360.0; y += 10.0) lane.emplace_back(x, y, height(x, y));
    lanes.push_back(lane);
  }
  return lanes;
}

double Hill(double x, double y) {
  // 6 m hill (grades up to ~5 %) on a 1 % tilt.
  const double dx = x - 240.0;
  const double dy = y - 180.0;
  return 50.0 + 0.01 * x + 6.0 * std::exp(-(dx * dx + dy * dy) / (2.0 * 70.0 * 70.0));
}

TEST(Terrain, EqualHeightsGiveExactlyFlatTerrain) {
  const Terrain t = Terrain::FitPolylines(StreetGrid([](double, double) { return 12.5; }));
  EXPECT_TRUE(t.IsFlat());
  const TerrainSample s = t.Evaluate(37.0, -5.0, 3);
  EXPECT_EQ(s.h, 12.5);
  EXPECT_EQ(s.gradient, Vec2::Zero());
  EXPECT_EQ(s.hessian, Mat2::Zero());
  EXPECT_EQ(s.third, Vec4::Zero());
}

TEST(Terrain, FitsASmoothHillOnTheRoads) {
  const auto lanes = StreetGrid(Hill);
  const Terrain t = Terrain::FitPolylines(lanes);
  ASSERT_FALSE(t.IsFlat());
  double max_err = 0.0;
  double max_grade_err = 0.0;
  for (const auto& lane : lanes) {
    for (const Vec3& p : lane) {
      max_err = std::max(max_err, std::abs(t.Height(p.x(), p.y()) - p.z()));
      // Grade along the lane direction against the analytic one.
      const double h = 1e-3;
      const Vec2 g_true((Hill(p.x() + h, p.y()) - Hill(p.x() - h, p.y())) / (2 * h),
                        (Hill(p.x(), p.y() + h) - Hill(p.x(), p.y() - h)) / (2 * h));
      max_grade_err = std::max(
          max_grade_err, (t.Evaluate(p.x(), p.y(), 1).gradient - g_true).lpNorm<Eigen::Infinity>());
    }
  }
  RecordProperty("max_height_error_m", std::to_string(max_err));
  EXPECT_LT(max_err, 0.03);
  EXPECT_LT(max_grade_err, 0.005);
}

TEST(Terrain, ReproducesAPlaneExactly) {
  // 4 % grade to the east, 2 % cross slope: the B-spline contains planes and the penalty on
  // second differences does not bias them.
  const auto plane = [](double x, double y) { return 20.0 + 0.04 * x - 0.02 * y; };
  const Terrain t = Terrain::FitPolylines(StreetGrid(plane));
  for (const Vec2& p : {Vec2(0.0, 0.0), Vec2(123.0, 61.0), Vec2(480.0, 360.0)}) {
    const TerrainSample s = t.Evaluate(p.x(), p.y(), 3);
    EXPECT_NEAR(s.h, plane(p.x(), p.y()), 1e-4);
    EXPECT_NEAR(s.gradient.x(), 0.04, 1e-5);
    EXPECT_NEAR(s.gradient.y(), -0.02, 1e-5);
    EXPECT_LT(s.hessian.cwiseAbs().maxCoeff(), 1e-6);
  }
}

TEST(Terrain, DerivativesMatchNumericDifferences) {
  const Terrain t = Terrain::FitPolylines(StreetGrid(Hill));
  const double e = 1e-3;
  for (const Vec2& p : {Vec2(100.0, 60.0), Vec2(237.0, 171.0), Vec2(13.0, 355.0)}) {
    const TerrainSample s = t.Evaluate(p.x(), p.y(), 3);
    const TerrainSample sx0 = t.Evaluate(p.x() - e, p.y(), 3);
    const TerrainSample sx1 = t.Evaluate(p.x() + e, p.y(), 3);
    const TerrainSample sy0 = t.Evaluate(p.x(), p.y() - e, 3);
    const TerrainSample sy1 = t.Evaluate(p.x(), p.y() + e, 3);
    EXPECT_NEAR(s.gradient.x(), (sx1.h - sx0.h) / (2 * e), 1e-7);
    EXPECT_NEAR(s.gradient.y(), (sy1.h - sy0.h) / (2 * e), 1e-7);
    const Vec2 hxx_row = (sx1.gradient - sx0.gradient) / (2 * e);
    const Vec2 hyy_row = (sy1.gradient - sy0.gradient) / (2 * e);
    EXPECT_NEAR(s.hessian(0, 0), hxx_row.x(), 1e-8);
    EXPECT_NEAR(s.hessian(0, 1), hxx_row.y(), 1e-8);
    EXPECT_NEAR(s.hessian(1, 1), hyy_row.y(), 1e-8);
    EXPECT_NEAR(s.third(0), (sx1.hessian(0, 0) - sx0.hessian(0, 0)) / (2 * e), 1e-9);
    EXPECT_NEAR(s.third(1), (sx1.hessian(0, 1) - sx0.hessian(0, 1)) / (2 * e), 1e-9);
    EXPECT_NEAR(s.third(2), (sx1.hessian(1, 1) - sx0.hessian(1, 1)) / (2 * e), 1e-9);
    EXPECT_NEAR(s.third(3), (sy1.hessian(1, 1) - sy0.hessian(1, 1)) / (2 * e), 1e-9);
    EXPECT_NEAR(s.third(1), (sy1.hessian(0, 0) - sy0.hessian(0, 0)) / (2 * e), 1e-9);
    const Vec3 n = t.Normal(p.x(), p.y());
    EXPECT_NEAR(n.norm(), 1.0, 1e-12);
    EXPECT_NEAR(n.head<2>().dot(s.gradient) + n.z() * s.gradient.squaredNorm(), 0.0, 1e-12);
  }
}

TEST(Terrain, FarFromTheRoadsItReturnsToTheBaseHeight) {
  const Terrain t = Terrain::FitPolylines(StreetGrid(Hill));
  const TerrainSample s = t.Evaluate(5000.0, -3000.0, 3);
  EXPECT_EQ(s.h, t.base_height_m());
  EXPECT_EQ(s.gradient, Vec2::Zero());
}

TEST(Terrain, RejectsEmptyInput) { EXPECT_THROW(Terrain::Fit({}), InputError); }

}  // namespace
}  // namespace statebench::sim
