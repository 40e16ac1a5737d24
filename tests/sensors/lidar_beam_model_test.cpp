#include "sensors/lidar_beam_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "sensors/lidar_model_params.hpp"

namespace statebench::sensors {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(LidarBeamModel, HesaiXt32Pattern) {
  const LidarBeamModel m = HesaiXt32BeamModel();
  ASSERT_EQ(m.channels(), 32);
  EXPECT_EQ(m.columns, 2000);
  EXPECT_NEAR(m.elevations_rad.front(), -16.0 * kDeg, 1e-12);
  EXPECT_NEAR(m.elevations_rad.back(), 15.0 * kDeg, 1e-12);
  for (int r = 1; r < 32; ++r) {
    EXPECT_NEAR(m.elevations_rad[r] - m.elevations_rad[r - 1], 1.0 * kDeg, 1e-12);
  }
  // 10 Hz: columns every 50 us, 0.18 deg apart, clockwise.
  EXPECT_EQ(m.ColumnOffsetNs(0), 0);
  EXPECT_EQ(m.ColumnOffsetNs(1), 50'000);
  EXPECT_EQ(m.ColumnOffsetNs(1999), 99'950'000);
  EXPECT_NEAR(m.ColumnAzimuthRad(0) - m.ColumnAzimuthRad(1), 0.18 * kDeg, 1e-12);
}

TEST(LidarBeamModel, VelodyneVlp16Pattern) {
  const LidarBeamModel m = VelodyneVlp16BeamModel();
  ASSERT_EQ(m.channels(), 16);
  EXPECT_EQ(m.columns, 1800);
  EXPECT_NEAR(m.elevations_rad.front(), -15.0 * kDeg, 1e-12);
  EXPECT_NEAR(m.elevations_rad.back(), 15.0 * kDeg, 1e-12);
  EXPECT_NEAR(m.ColumnAzimuthRad(0) - m.ColumnAzimuthRad(1), 0.2 * kDeg, 1e-12);
  EXPECT_EQ(m.ColumnOffsetNs(900), 50'000'000);
  EXPECT_EQ(m.ColumnOffsetNs(1), 55'556);  // 100 ms / 1800, rounded to the nanosecond
}

TEST(LidarBeamModel, DirectionsAreUnitWithTheRingElevation) {
  const LidarBeamModel m = HesaiXt32BeamModel();
  for (const int c : {0, 517, 1999}) {
    for (int r = 0; r < m.channels(); ++r) {
      const Vec3 d = m.Direction(c, r);
      EXPECT_NEAR(d.norm(), 1.0, 1e-15);
      EXPECT_NEAR(std::asin(d.z()), m.elevations_rad[r], 1e-12);
      EXPECT_NEAR(std::atan2(d.y(), d.x()),
                  std::remainder(m.ColumnAzimuthRad(c), 2.0 * std::numbers::pi), 1e-12);
    }
  }
  // Column 0 points backwards (-x) by default.
  EXPECT_NEAR(m.Direction(0, 16).x(), -1.0, 1e-12);
}

TEST(LidarModelParams, DatasheetDefaultsAndOverrides) {
  LidarModelValues v;
  v.model = "velodyne_vlp16";
  v.sensor_id = "front";
  LidarModelParams p = MakeLidarModelParams(v, "setup.yaml: sensors[1]");
  EXPECT_EQ(p.beams.channels(), 16);
  EXPECT_DOUBLE_EQ(p.max_range_m, 100.0);
  EXPECT_DOUBLE_EQ(p.range_noise_sigma_m, 0.03);

  v.model = "hesai_xt32";
  v.max_range_m = 80.0;
  v.rotation_rate_hz = 20.0;
  p = MakeLidarModelParams(v, "setup.yaml: sensors[1]");
  EXPECT_DOUBLE_EQ(p.max_range_m, 80.0);
  EXPECT_DOUBLE_EQ(p.range_noise_sigma_m, 0.01);
  EXPECT_EQ(p.beams.columns, 1000);
  EXPECT_EQ(p.beams.PeriodNs(), 50'000'000);
}

TEST(LidarModelParams, BadValuesNameTheField) {
  LidarModelValues v;
  v.model = "ouster_os1";
  v.sensor_id = "roof";
  try {
    MakeLidarModelParams(v, "setup.yaml: sensors[3]");
    FAIL() << "unknown model accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("setup.yaml: sensors[3]: field 'model'"),
              std::string::npos)
        << e.what();
  }
  v.model = "hesai_xt32";
  v.dropout_probability = 1.5;
  EXPECT_THROW(MakeLidarModelParams(v, "x"), InputError);
  v.dropout_probability = 0.1;
  v.min_range_m = 50.0;
  v.max_range_m = 10.0;
  EXPECT_THROW(MakeLidarModelParams(v, "x"), InputError);
}

}  // namespace
}  // namespace statebench::sensors
