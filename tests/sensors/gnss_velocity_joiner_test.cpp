#include "sensors/gnss_velocity_joiner.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace statebench::sensors {
namespace {

constexpr TimeNs kMs = kNsPerMillisecond;

GnssVelocity Velocity(double east) { return GnssVelocity{Vec3(east, 0.0, 0.0), Vec3::Ones()}; }

// What was written: (fix stamp, east velocity or -1 for none), in order.
struct Written {
  std::vector<std::pair<TimeNs, double>> rows;
  GnssVelocityJoiner::Write At(TimeNs stamp_ns) {
    return [this, stamp_ns](const std::optional<GnssVelocity>& v) {
      rows.emplace_back(stamp_ns, v ? v->v_enu.x() : -1.0);
    };
  }
};

// nmea_navsat_driver style: the velocity's stamp a few ms from its fix's, before or after it;
// a fix without a velocity waits kWaitNs of receive time, then goes out alone, in order.
TEST(GnssVelocityJoiner, JoinsTheNearestVelocityEitherWayRound) {
  GnssVelocityJoiner joiner;
  Written w;
  joiner.AddFix("gps", 1000 * kMs, 1010 * kMs, w.At(1000 * kMs));
  EXPECT_TRUE(w.rows.empty());                                       // waits for its velocity
  EXPECT_TRUE(joiner.AddVelocity("gps", 1012 * kMs, Velocity(1)));   // 12 ms after: joined
  EXPECT_FALSE(joiner.AddVelocity("gps", 1240 * kMs, Velocity(2)));  // before its fix
  joiner.AddFix("gps", 1250 * kMs, 1260 * kMs, w.At(1250 * kMs));    // joined at once
  joiner.AddFix("gps", 1500 * kMs, 1510 * kMs, w.At(1500 * kMs));
  joiner.AddVelocity("other", 1500 * kMs, Velocity(9));  // another receiver's
  joiner.Advance(1900 * kMs);
  EXPECT_EQ(w.rows.size(), 2u);  // the 1.5 s fix still waits
  joiner.Advance(2011 * kMs);    // 501 ms after it came
  joiner.AddFix("gps", 1750 * kMs, 2020 * kMs, w.At(1750 * kMs));
  joiner.AddVelocity("gps", 1900 * kMs, Velocity(3));  // 150 ms off: not its velocity
  joiner.Flush();
  const std::vector<std::pair<TimeNs, double>> expected = {
      {1000 * kMs, 1.0}, {1250 * kMs, 2.0}, {1500 * kMs, -1.0}, {1750 * kMs, -1.0}};
  EXPECT_EQ(w.rows, expected);
  EXPECT_EQ(joiner.joined("gps"), 2u);
  EXPECT_EQ(joiner.joined("other"), 0u);
}

}  // namespace
}  // namespace statebench::sensors
