#include "core/geodetic.hpp"

#include <gtest/gtest.h>

namespace statebench {
namespace {

TEST(LocalEnuFrame, RoundTripWithinMicrometres) {
  const LocalEnuFrame frame({45.4781, 9.2273, 120.0});  // Milan
  for (const Vec3& enu : {Vec3(0, 0, 0), Vec3(1234.5, -987.6, 12.3), Vec3(-5000, 5000, -30)}) {
    const GeodeticPoint g = frame.ToGeodetic(enu);
    EXPECT_LT((frame.ToEnu(g) - enu).norm(), 1e-6);
  }
  // 1 deg of latitude is about 111 km north.
  const Vec3 north = frame.ToEnu({46.4781, 9.2273, 120.0});
  EXPECT_NEAR(north.y(), 111.1e3, 0.3e3);
  EXPECT_NEAR(north.x(), 0.0, 1e-6);
}

}  // namespace
}  // namespace statebench
