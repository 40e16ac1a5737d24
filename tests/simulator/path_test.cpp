#include "simulator/path.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "core/so3.hpp"

namespace statebench::sim {
namespace {

constexpr double kPi = std::numbers::pi;

// Distance from p to the polyline.
double DistanceToPolyline(const std::vector<Vec2>& line, const Vec2& p) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < line.size(); ++i) {
    const Vec2 ab = line[i] - line[i - 1];
    const double a = std::clamp((p - line[i - 1]).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (line[i - 1] + a * ab - p).norm());
  }
  return best;
}

// Two 100 m legs meeting at a right angle (left turn), with a duplicated vertex.
std::vector<Vec3> LRoute() {
  return {Vec3(0, 0, 0), Vec3(50, 0, 0), Vec3(50, 0, 0), Vec3(100, 0, 1), Vec3(100, 100, 2)};
}

TEST(Path, StraightPolylineStaysExactlyStraight) {
  const Path path = Path::Build({Vec3(10, 5, 0), Vec3(40, 45, 0), Vec3(70, 85, 0)});
  EXPECT_NEAR(path.length_m(), 100.0, 1e-9);
  for (double s = 0.0; s <= 100.0; s += 7.3) {
    const PathPoint p = path.At(s);
    EXPECT_NEAR((p.position - Vec2(10 + 0.6 * s, 5 + 0.8 * s)).norm(), 0.0, 1e-9);
    EXPECT_NEAR(p.heading_rad, std::atan2(0.8, 0.6), 1e-10);
    EXPECT_NEAR(p.curvature_1pm, 0.0, 1e-10);
  }
}

TEST(Path, RightAngleCornerIsRoundedLikeADriverWould) {
  PathOptions options;
  options.max_curvature_1pm = 0.2;
  const Path path = Path::Build(LRoute(), options);
  double max_kappa = 0.0;
  double max_heading_jump = 0.0;
  double max_kappa_jump = 0.0;
  double max_straight_dev = 0.0;
  PathPoint prev = path.At(0.0);
  const double ds = 0.05;
  for (double s = ds; s <= path.length_m(); s += ds) {
    const PathPoint p = path.At(s);
    max_kappa = std::max(max_kappa, std::abs(p.curvature_1pm));
    max_heading_jump =
        std::max(max_heading_jump, std::abs(so3::WrapAngle(p.heading_rad - prev.heading_rad)));
    max_kappa_jump = std::max(max_kappa_jump, std::abs(p.curvature_1pm - prev.curvature_1pm));
    // More than 20 m from the corner the path lies on the lane.
    const double to_corner = (p.position - Vec2(100, 0)).norm();
    if (to_corner > 20.0) {
      max_straight_dev =
          std::max(max_straight_dev, DistanceToPolyline(path.raw_polyline(), p.position));
    }
    prev = p;
  }
  const double cut = path.Project(Vec2(100, 0)).lateral_m;
  RecordProperty("corner_cut_m", std::to_string(cut));
  RecordProperty("max_curvature", std::to_string(max_kappa));
  EXPECT_LE(max_kappa, 0.2 * 1.02);
  EXPECT_GT(max_kappa, 0.1);  // a real turn, not a wide sweep
  EXPECT_LT(cut, -0.5);       // the corner lies to the right of a left turn
  EXPECT_GT(cut, -4.0);
  EXPECT_LT(max_straight_dev, 0.02);
  EXPECT_LT(max_heading_jump, 0.2 * ds * 1.05);  // |dheading/ds| = |kappa| <= 0.2
  EXPECT_LT(max_kappa_jump, 0.01);
}

TEST(Path, DiscretisedArcKeepsItsCurvature) {
  // Quarter circle of radius 20 m given as a polyline with 2 m chords, between two straights.
  std::vector<Vec3> line{Vec3(-30, 0, 0)};
  for (int i = 0; i <= 16; ++i) {
    const double a = -kPi / 2 + i * (kPi / 2) / 16;
    line.emplace_back(20 * std::cos(a), 20 + 20 * std::sin(a), 0);
  }
  line.emplace_back(20, 50, 0);
  const Path path = Path::Build(line);
  // Middle of the arc: s = 30 (straight) + quarter arc / 2.
  const PathPoint mid = path.At(30.0 + 10.0 * kPi / 2);
  EXPECT_NEAR(mid.curvature_1pm, 1.0 / 20.0, 0.05 / 20.0);
  EXPECT_NEAR((mid.position - Vec2(0, 20)).norm(), 20.0, 0.05);
}

TEST(Path, DerivativesAreConsistent) {
  const Path path = Path::Build(LRoute());
  const double e = 1e-4;
  for (double s : {30.0, 97.0, 100.5, 104.0, 150.0}) {
    const PathPoint p = path.At(s);
    const PathPoint p0 = path.At(s - e);
    const PathPoint p1 = path.At(s + e);
    const Vec2 tangent = (p1.position - p0.position) / (2 * e);
    EXPECT_NEAR(tangent.norm(), 1.0, 1e-7);  // unit speed: s is arc length
    EXPECT_NEAR(std::atan2(tangent.y(), tangent.x()), p.heading_rad, 1e-7);
    EXPECT_NEAR((p1.heading_rad - p0.heading_rad) / (2 * e), p.curvature_1pm, 1e-6);
    EXPECT_NEAR((p1.curvature_1pm - p0.curvature_1pm) / (2 * e), p.curvature_rate_1pm2, 1e-5);
    EXPECT_NEAR((path.Position(s) - p.position).norm(), 0.0, 1e-12);
  }
}

TEST(Path, ProjectionRecoversArcLengthAndOffset) {
  const Path path = Path::Build(LRoute());
  for (double s : {5.0, 60.0, 99.0, 101.0, 103.0, 180.0}) {
    for (double d : {-1.5, 0.0, 0.4, 2.0}) {
      const PathPoint p = path.At(s);
      const Vec2 normal(-std::sin(p.heading_rad), std::cos(p.heading_rad));
      const Vec2 q = p.position + d * normal;
      const PathProjection local = path.Project(q, path.HintAt(s + 2.0));
      const PathProjection global = path.Project(q);
      EXPECT_NEAR(local.s_m, s, 1e-7) << s << " " << d;
      EXPECT_NEAR(local.lateral_m, d, 1e-7);
      EXPECT_NEAR(global.s_m, s, 1e-7);
    }
  }
  // Beyond the ends: along the straight extensions.
  const PathProjection before = path.Project(Vec2(-3.0, 0.5));
  EXPECT_NEAR(before.s_m, -3.0, 1e-6);
  EXPECT_NEAR(before.lateral_m, 0.5, 1e-6);
  const PathProjection after = path.Project(Vec2(99.0, 104.0), path.HintAt(path.length_m()));
  EXPECT_NEAR(after.s_m, path.length_m() + 4.0, 1e-6);
  EXPECT_NEAR(after.lateral_m, 1.0, 1e-6);
}

TEST(Path, MapsSumoArcLengthToThePath) {
  const Path path = Path::Build(LRoute());
  EXPECT_NEAR(path.raw_length_m(), 200.0, 1e-12);
  // Before the corner both arc lengths agree; after it the path is shorter by the cut.
  EXPECT_NEAR(path.FromRaw(40.0).s_m, 40.0, 1e-6);
  EXPECT_NEAR(path.FromRaw(40.0).ds_draw, 1.0, 1e-6);
  const double shortcut = 200.0 - path.length_m();
  EXPECT_GT(shortcut, 0.1);
  EXPECT_NEAR(path.FromRaw(170.0).s_m, 170.0 - shortcut, 1e-6);
  // The mapped point is the path point nearest the raw point.
  const RawToPath m = path.FromRaw(100.0);
  EXPECT_NEAR(path.Project(Vec2(100.0, 0.0)).s_m, m.s_m, 0.05);
  EXPECT_NEAR((path.PositionAtRaw(100.0) - path.Position(m.s_m)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((path.PositionAtRaw(205.0) - path.Position(path.length_m() + 5.0)).norm(), 0.0, 1e-9);
  // Derivatives in s_raw.
  const double e = 1e-4;
  for (double u : {95.0, 100.0, 103.0}) {
    const RawToPath a = path.FromRaw(u - e);
    const RawToPath b = path.FromRaw(u + e);
    const RawToPath c = path.FromRaw(u);
    EXPECT_NEAR((b.s_m - a.s_m) / (2 * e), c.ds_draw, 1e-7);
    EXPECT_NEAR((b.ds_draw - a.ds_draw) / (2 * e), c.d2s_draw2, 1e-6);
    EXPECT_GT(c.ds_draw, 0.5);
  }
}

TEST(Path, RejectsDegeneratePolyline) {
  EXPECT_THROW(Path::Build({Vec3(1, 1, 0), Vec3(1, 1, 0)}), InputError);
}

}  // namespace
}  // namespace statebench::sim
