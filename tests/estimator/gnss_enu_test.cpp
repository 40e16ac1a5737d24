#include "estimator/gnss_enu.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace statebench::est {
namespace {

const LocalEnuFrame kFrame(GeodeticPoint{48.7120, 2.2000, 160.0});

GnssFix FixAt(const Vec3& enu) {
  const GeodeticPoint g = kFrame.ToGeodetic(enu);
  GnssFix fix;
  fix.header.sensor_id = "gnss_front";
  fix.header.stamp_ns = 123;
  fix.latitude_deg = g.latitude_deg;
  fix.longitude_deg = g.longitude_deg;
  fix.altitude_m = g.altitude_m;
  fix.covariance_enu = Mat3::Identity() * 1e-4;
  fix.status = GnssFixStatus::kRtkFixed;
  return fix;
}

TEST(GnssFixToEnu, ConvertsThroughTheLocalFrame) {
  for (const Vec3& enu : {Vec3(0, 0, 0), Vec3(1523.4, -876.2, 12.5), Vec3(-5.0, 20.0, -3.0)}) {
    std::string why;
    const auto out = GnssFixToEnu(FixAt(enu), kFrame, &why);
    ASSERT_TRUE(out.has_value()) << why;
    EXPECT_LT((out->p_enu - enu).norm(), 1e-6);
    EXPECT_EQ(out->header.sensor_id, "gnss_front");
    EXPECT_EQ(out->status, GnssFixStatus::kRtkFixed);
  }
}

TEST(GnssFixToEnu, RejectsBadFixesWithAReason) {
  const auto expect_reject = [](GnssFix fix, const std::string& reason) {
    std::string why;
    EXPECT_FALSE(GnssFixToEnu(fix, kFrame, &why).has_value()) << reason;
    EXPECT_NE(why.find(reason), std::string::npos) << why;
    EXPECT_NE(why.find("gnss_front"), std::string::npos) << why;
  };
  GnssFix fix = FixAt(Vec3(1, 2, 3));
  fix.status = GnssFixStatus::kNone;
  expect_reject(fix, "no fix");
  fix = FixAt(Vec3(1, 2, 3));
  fix.latitude_deg = std::numeric_limits<double>::quiet_NaN();
  expect_reject(fix, "non-finite position");
  fix = FixAt(Vec3(1, 2, 3));
  fix.latitude_deg = 91.0;
  expect_reject(fix, "out of range");
  fix = FixAt(Vec3(1, 2, 3));
  fix.altitude_m = 1e7;
  expect_reject(fix, "out of range");
  fix = FixAt(Vec3(1, 2, 3));
  fix.covariance_enu(1, 1) = std::numeric_limits<double>::infinity();
  expect_reject(fix, "non-finite covariance");
  fix = FixAt(Vec3(1, 2, 3));
  fix.covariance_enu(0, 1) = 5e-5;
  expect_reject(fix, "not symmetric");
  fix = FixAt(Vec3(1, 2, 3));
  fix.covariance_enu = Mat3::Zero();
  expect_reject(fix, "not positive definite");
}

}  // namespace
}  // namespace statebench::est
