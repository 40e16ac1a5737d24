// GyroTrack: the raw gyro's rotation between two stamps, each rate held until the next sample.
#include <gtest/gtest.h>

#include "core/so3.hpp"
#include "estimator/gyro_track.hpp"

namespace statebench::est {
namespace {

TEST(GyroTrack, IntegratesHeldRatesBetweenAnyTwoStamps) {
  GyroTrack track;
  // 100 Hz: 0.2 rad/s about z for 0.5 s, then 0.4 rad/s about x.
  for (int k = 0; k <= 100; ++k) {
    const Vec3 w = k < 50 ? Vec3(0.0, 0.0, 0.2) : Vec3(0.4, 0.0, 0.0);
    track.Add(FromSeconds(0.01 * k), w);
  }
  // Within the first segment, between samples: 0.2 rad/s x 0.125 s.
  const auto q1 = track.Rotation(FromSeconds(0.105), FromSeconds(0.23));
  ASSERT_TRUE(q1);
  EXPECT_LT((so3::Log(*q1) - Vec3(0.0, 0.0, 0.025)).norm(), 1e-12);
  // Across the change: z by 0.2 x 0.1, then x by 0.4 x 0.1, in that order.
  const auto q2 = track.Rotation(FromSeconds(0.4), FromSeconds(0.6));
  ASSERT_TRUE(q2);
  const Quat expected = so3::Exp(Vec3(0.0, 0.0, 0.02)) * so3::Exp(Vec3(0.04, 0.0, 0.0));
  EXPECT_LT(so3::Log(expected.conjugate() * *q2).norm(), 1e-12);
  // Not covered: before the first sample, after the last, reversed.
  EXPECT_FALSE(track.Rotation(FromSeconds(-0.01), FromSeconds(0.1)));
  EXPECT_FALSE(track.Rotation(FromSeconds(0.9), FromSeconds(1.01)));
  EXPECT_FALSE(track.Rotation(FromSeconds(0.3), FromSeconds(0.2)));
  EXPECT_TRUE(track.Rotation(FromSeconds(0.3), FromSeconds(0.3)));
  // Forgetting keeps the sample holding the rate at the cut.
  track.DropBefore(FromSeconds(0.555));
  EXPECT_TRUE(track.Rotation(FromSeconds(0.555), FromSeconds(0.6)));
  EXPECT_FALSE(track.Rotation(FromSeconds(0.54), FromSeconds(0.6)));
  // An older or repeated stamp is ignored.
  track.Add(FromSeconds(0.5), Vec3(9.0, 9.0, 9.0));
  track.Add(FromSeconds(1.0), Vec3(9.0, 9.0, 9.0));
  EXPECT_EQ(track.newest_ns(), FromSeconds(1.0));
  const auto q3 = track.Rotation(FromSeconds(0.9), FromSeconds(1.0));
  ASSERT_TRUE(q3);
  EXPECT_LT((so3::Log(*q3) - Vec3(0.04, 0.0, 0.0)).norm(), 1e-12);
}

}  // namespace
}  // namespace statebench::est
