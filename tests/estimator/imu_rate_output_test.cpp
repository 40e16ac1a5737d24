// ImuRateOutput after the anchor: the cursor that serves stamps before the newest sample gives
// the same bits as integrating from the anchor for each stamp.
#include "estimator/imu_rate_output.hpp"

#include <gtest/gtest.h>

#include "helix_trajectory.hpp"

namespace statebench::est {
namespace {

using testing::HelixTrajectory;

ImuSample HelixImuSample(const HelixTrajectory& helix, TimeNs t_ns) {
  ImuSample s;
  s.header.stamp_ns = t_ns;
  s.gyro = helix.Gyro(ToSeconds(t_ns));
  s.accel = helix.Accel(ToSeconds(t_ns));
  return s;
}

void ExpectSameBits(const PropagatedState& a, const PropagatedState& b) {
  EXPECT_EQ(a.state.t_ns, b.state.t_ns);
  EXPECT_EQ(a.state.q_world_imu.coeffs(), b.state.q_world_imu.coeffs());
  EXPECT_EQ(a.state.p_world, b.state.p_world);
  EXPECT_EQ(a.state.v_world, b.state.v_world);
  EXPECT_EQ(a.covariance, b.covariance);
}

TEST(ImuRateOutput, StampsBeforeTheNewestAreIntegratedFromTheAnchorExactly) {
  const HelixTrajectory helix;
  const ImuNoise noise;
  ImuRateOutput output(noise);
  const TimeNs step = FromSeconds(0.01);
  for (int k = 0; k <= 40; ++k) output.AddImu(HelixImuSample(helix, FromSeconds(1.0) + k * step));
  // Anchors on a sample stamp and between two samples.
  for (const TimeNs anchor_ns : {FromSeconds(1.1), FromSeconds(1.1) + step / 3}) {
    PropagatedState anchor;
    anchor.state = helix.State(anchor_ns);
    anchor.state.gyro_bias = Vec3(1e-3, -2e-3, 5e-4);
    anchor.covariance = 1e-4 * Mat15::Identity();
    output.SetAnchor(anchor);
    // Increasing sample stamps (the cursor extends), a stamp between samples, then back.
    std::vector<TimeNs> stamps;
    for (int k = 11; k < 40; k += 3) stamps.push_back(FromSeconds(1.0) + k * step);
    stamps.push_back(FromSeconds(1.0) + 35 * step + step / 2);
    stamps.push_back(FromSeconds(1.0) + 36 * step);
    stamps.push_back(FromSeconds(1.0) + 20 * step);
    for (const TimeNs t_ns : stamps) {
      if (t_ns < anchor_ns) continue;
      const std::optional<PropagatedState> got = output.AfterAnchor(t_ns);
      ASSERT_TRUE(got);
      const ImuPreintegration direct = ImuPreintegration::FromSamples(
          output.samples(), anchor_ns, t_ns, noise,
          ImuBias{anchor.state.gyro_bias, anchor.state.accel_bias});
      ExpectSameBits(*got, Propagate(anchor.state, anchor.covariance, direct));
    }
  }
}

// A preintegration from another buffer of the stream (the smoother's) stands in for the output's
// own only where it is the same: the answer is always that of the output's samples.
TEST(ImuRateOutput, ASharedPreintegrationIsUsedOnlyWhereItIsTheAnchors) {
  const HelixTrajectory helix;
  const ImuNoise noise;
  ImuRateOutput output(noise);
  const TimeNs step = FromSeconds(0.01);
  std::vector<ImuSample> other;  // the smoother's buffer: the same stream
  for (int k = 0; k <= 40; ++k) {
    const ImuSample s = HelixImuSample(helix, FromSeconds(1.0) + k * step);
    output.AddImu(s);
    other.push_back(s);
  }
  PropagatedState anchor;
  anchor.state = helix.State(FromSeconds(1.1));
  anchor.state.gyro_bias = Vec3(1e-3, -2e-3, 5e-4);
  anchor.covariance = 1e-4 * Mat15::Identity();
  output.SetAnchor(anchor);
  const ImuBias bias{anchor.state.gyro_bias, anchor.state.accel_bias};
  const TimeNs t_ns = FromSeconds(1.0) + 25 * step;
  const PropagatedState expected = Propagate(
      anchor.state, anchor.covariance,
      ImuPreintegration::FromSamples(output.samples(), anchor.state.t_ns, t_ns, noise, bias));
  ImuBias other_bias = bias;
  other_bias.accel.x() += 0.01;
  std::vector<ImuSample> altered = other;
  altered[24].accel.y() += 1e-3;
  ImuNoise other_noise = noise;
  other_noise.accel_noise_density *= 2.0;
  const std::vector<ImuPreintegration> shared{
      ImuPreintegration::FromSamples(other, anchor.state.t_ns, t_ns, noise, bias),  // the same
      ImuPreintegration::FromSamples(other, anchor.state.t_ns, t_ns, noise, other_bias),
      ImuPreintegration::FromSamples(altered, anchor.state.t_ns, t_ns, noise, bias),
      ImuPreintegration::FromSamples(other, anchor.state.t_ns, t_ns, other_noise, bias),
      ImuPreintegration::FromSamples(other, anchor.state.t_ns, t_ns - step, noise, bias)};
  for (const ImuPreintegration& p : shared) {
    const std::optional<PropagatedState> got = output.AfterAnchor(t_ns, &p);
    ASSERT_TRUE(got);
    ExpectSameBits(*got, expected);
    output.AddImu(HelixImuSample(helix, output.samples().back().header.stamp_ns + step));
  }
}

}  // namespace
}  // namespace statebench::est
