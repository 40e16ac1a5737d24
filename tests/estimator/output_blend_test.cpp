// The output's blend of each new solve (estimator/output_blend.hpp): continuity at the solve, the
// correction ramped in at its rates (or over max_s when larger, but never faster than
// max_position_rate_mps after the start period), the covariance that covers the offset; and in the factor graph, a GNSS outage whose end moves the smoothed state by
// decimetres: the output steps stay within the rate and the output joins the unblended one.
#include "estimator/output_blend.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>

#include "core/so3.hpp"
#include "estimator/factor_graph_estimator.hpp"
#include "estimator_scenario.hpp"

namespace statebench::est {
namespace {

// A state moving at a constant 10 m/s east, turning at 0.1 rad/s.
PropagatedState BestAt(double t_s) {
  PropagatedState p;
  p.state.t_ns = FromSeconds(t_s);
  p.state.p_world = Vec3(10.0 * t_s, 0.0, 0.0);
  p.state.v_world = Vec3(10.0, 0.0, 0.0);
  p.state.q_world_imu = so3::FromRollPitchYaw(0.0, 0.0, 0.1 * t_s);
  p.covariance = 1e-4 * Mat15::Identity();
  return p;
}

// What the output showed at t_s with the old anchor: `position` m, 0.02 rad and 0.05 m/s off.
NavState Shown(double t_s, double position) {
  NavState shown = BestAt(t_s).state;
  shown.p_world += position * Vec3(0.6, -0.8, 0.0);
  shown.v_world += Vec3(0.05, 0.0, 0.0);
  shown.q_world_imu = shown.q_world_imu * so3::Exp<double>(Vec3(0.0, 0.0, 0.02));
  return shown;
}

// Steps of the blended output beyond the best estimate's motion over position_duration_s + 1 s
// (at least 3 s) after a solve at t_s, checking continuity, the ramps (rotation and velocity over
// duration_s, position over position_duration_s, by default the same) and the covariance on the
// way; returns the largest step.
double LargestStep(const OutputBlend& blend, const NavState& shown, double t_s, double duration_s,
                   std::optional<double> position_duration = std::nullopt) {
  const double position_duration_s = position_duration.value_or(duration_s);
  const int samples =
      std::max(300, static_cast<int>(std::ceil((position_duration_s + 1.0) / 0.01)));
  const Vec9 d = testing::StateDifference(shown, BestAt(t_s).state);
  const PropagatedState at = blend.Apply(BestAt(t_s));
  EXPECT_LT(testing::StateDifference(at.state, shown).norm(), 1e-12);  // what was shown, exactly
  // Before the solve: untouched.
  EXPECT_LT(testing::StateDifference(blend.Apply(BestAt(t_s - 0.01)).state, BestAt(t_s - 0.01).state).norm(),
            1e-15);
  double largest = 0.0;
  PropagatedState previous = at;
  for (int k = 1; k <= samples; ++k) {
    const double t = t_s + 0.01 * k;
    const PropagatedState best = BestAt(t);
    const PropagatedState out = blend.Apply(best);
    const Vec3 motion = best.state.p_world - BestAt(t - 0.01).state.p_world;
    largest = std::max(largest, (out.state.p_world - previous.state.p_world - motion).norm());
    const Vec9 b = testing::StateDifference(out.state, best.state);
    const double w = std::max(0.0, 1.0 - (t - t_s) / duration_s);
    const double w_position = std::max(0.0, 1.0 - (t - t_s) / position_duration_s);
    Vec9 expected = w * d;
    expected.segment<3>(kPositionIndex) = w_position * d.segment<3>(kPositionIndex);
    EXPECT_LT((b - expected).norm(), 1e-9) << "t " << t;
    // The covariance grows by exactly the square of the offset shown.
    const Mat9 added = out.covariance.topLeftCorner<9, 9>() - best.covariance.topLeftCorner<9, 9>();
    EXPECT_LT((added - b * b.transpose()).norm(), 1e-12);
    const Mat6 biases = out.covariance.bottomRightCorner<6, 6>();
    EXPECT_EQ(biases, (best.covariance.bottomRightCorner<6, 6>()));
    previous = out;
  }
  EXPECT_EQ(previous.state.p_world, BestAt(t_s + 0.01 * samples).state.p_world);  // in, entirely
  return largest;
}

TEST(OutputBlend, ACorrectionComesInAtItsRateAndNoSlowerThanMaxS) {
  OutputBlendOptions o;  // 1 s at most, 1 m/s, 0.1 rad/s
  o.max_s = 1.0;
  // 0.3 m at 1 m/s: 0.3 s, 1 cm per 10 ms sample.
  OutputBlend blend(o);
  blend.Rebase(Shown(3.0, 0.3), BestAt(3.0).state);
  EXPECT_NEAR(LargestStep(blend, Shown(3.0, 0.3), 3.0, 0.3), 0.01, 1e-9);
  // 0.05 m: the 0.02 rad at 0.1 rad/s sets the time, 0.2 s.
  blend.Rebase(Shown(3.0, 0.05), BestAt(3.0).state);
  EXPECT_NEAR(LargestStep(blend, Shown(3.0, 0.05), 3.0, 0.2), 0.05 * 0.01 / 0.2, 1e-9);
  // 2 m would take 2 s at the rate: max_s (1 s) instead, 2 cm per sample.
  blend.Rebase(Shown(3.0, 2.0), BestAt(3.0).state);
  EXPECT_NEAR(LargestStep(blend, Shown(3.0, 2.0), 3.0, 1.0), 0.02, 1e-9);
}

// A correction of tens of metres (a drifted outage that a turn reveals) would come in at
// 0.1-0.4 m per sample over max_s; it slides in at max_position_rate_mps instead.
TEST(OutputBlend, ALargeCorrectionComesInNoFasterThanMaxPositionRate) {
  OutputBlendOptions o;  // 1 s at most, 1 m/s, but never faster than 3 m/s
  ASSERT_EQ(o.max_position_rate_mps, 3.0);
  OutputBlend blend(o);
  // 3 m: max_s, as before (3 m/s, 3 cm per sample).
  blend.Rebase(Shown(3.0, 3.0), BestAt(3.0).state);
  EXPECT_NEAR(LargestStep(blend, Shown(3.0, 3.0), 3.0, 1.0), 0.03, 1e-9);
  // 12 m: 4 s at 3 m/s, 3 cm per sample; within max_s it would have been 12 cm. Rotation and
  // velocity still come in over max_s.
  blend.Rebase(Shown(3.0, 12.0), BestAt(3.0).state);
  EXPECT_NEAR(LargestStep(blend, Shown(3.0, 12.0), 3.0, 1.0, 4.0), 0.03, 1e-9);
  // Without the bound: over max_s.
  o.max_position_rate_mps = 0.0;
  OutputBlend unbounded(o);
  unbounded.Rebase(Shown(3.0, 12.0), BestAt(3.0).state);
  EXPECT_NEAR(LargestStep(unbounded, Shown(3.0, 12.0), 3.0, 1.0), 0.12, 1e-9);
}

// In the start period the converging estimate's corrections come in within start_max_s,
// whatever their size: the bound does not lag the start.
TEST(OutputBlend, TheStartPeriodIsNotBoundByTheMaxPositionRate) {
  OutputBlendOptions o;
  OutputBlend blend(o);
  blend.Start(FromSeconds(0.0));
  blend.Rebase(Shown(3.0, 12.0), BestAt(3.0).state);
  EXPECT_NEAR(LargestStep(blend, Shown(3.0, 12.0), 3.0, o.start_max_s), 12.0 * 0.01 / o.start_max_s,
              1e-9);
  // After it, the bound holds.
  blend.Rebase(Shown(o.after_start_s + 1.0, 12.0), BestAt(o.after_start_s + 1.0).state);
  EXPECT_NEAR(
      LargestStep(blend, Shown(o.after_start_s + 1.0, 12.0), o.after_start_s + 1.0, 1.0, 4.0),
      0.03, 1e-9);
}

TEST(OutputBlend, MaxSZeroOrAResetShowsTheBestEstimate) {
  OutputBlendOptions o;
  o.max_s = 0.0;  // off
  OutputBlend off(o);
  off.Rebase(Shown(1.0, 1.0), BestAt(1.0).state);
  EXPECT_EQ(off.Apply(BestAt(1.2)).state.p_world, BestAt(1.2).state.p_world);
  o.max_s = 1.0;
  OutputBlend on(o);
  on.Rebase(Shown(1.0, 1.0), BestAt(1.0).state);
  EXPECT_GT((on.Apply(BestAt(1.2)).state.p_world - BestAt(1.2).state.p_world).norm(), 0.1);
  on.Reset();
  EXPECT_EQ(on.Apply(BestAt(1.2)).state.p_world, BestAt(1.2).state.p_world);
  EXPECT_EQ(on.Apply(BestAt(1.2)).covariance, BestAt(1.2).covariance);
}

// The real-time outputs of a run, by stamp.
std::map<TimeNs, StateEstimate> BlendRunOutputs(const testing::Scenario& sc, double max_s) {
  FactorGraphOptions o;
  o.origin = testing::kTestOrigin;
  o.output_blend.max_s = max_s;
  FactorGraphEstimator estimator(testing::MakeSetup(sc.options), o);
  std::map<TimeNs, StateEstimate> out;
  for (const Measurement& m : sc.stream) {
    estimator.Add(m);
    if (!std::holds_alternative<ImuSample>(m)) continue;
    if (const auto e = estimator.StateAt(HeaderOf(m).stamp_ns)) out[HeaderOf(m).stamp_ns] = *e;
  }
  return out;
}

// The largest |(p_k - p_k-1) - (p*_k - p*_k-1)| over consecutive outputs from from_s on.
double LargestStep(const testing::Scenario& sc, const std::map<TimeNs, StateEstimate>& out,
                   double from_s) {
  double largest = 0.0;
  const StateEstimate* previous = nullptr;
  for (const auto& [t, e] : out) {
    if (previous != nullptr && t - previous->state.t_ns == 10 * kNsPerMillisecond &&
        ToSeconds(t) >= from_s) {
      const Vec3 motion = sc.Truth(t).p_world - sc.Truth(previous->state.t_ns).p_world;
      largest = std::max(largest, (e.state.p_world - previous->state.p_world - motion).norm());
    }
    previous = &e;
  }
  return largest;
}

// A drifting IMU through a 12 s GNSS outage at ~10 m/s: the first solves with fixes again move
// the smoothed state by decimetres. Without the blend the output jumps by that much between two
// samples; with it no step exceeds the position rate x dt (1 cm) by more than the motion the
// output gets wrong in 10 ms, the output is the unblended one max_s after the correction, and
// its covariance is the unblended one plus the square of the offset it shows.
TEST(OutputBlend, FactorGraphOutputDoesNotJumpWhenTheOutageEnds) {
  testing::ScenarioOptions so = testing::DriftingImuRtkOptions(40.0);
  so.outage_begin_s = 15.0;
  so.outage_end_s = 27.0;
  const testing::Scenario sc = testing::MakeScenario(so);
  OutputBlendOptions blend;
  blend.max_s = 1.0;
  const auto jumping = BlendRunOutputs(sc, 0.0);
  const auto blended = BlendRunOutputs(sc, blend.max_s);
  const double jump = LargestStep(sc, jumping, so.outage_end_s);
  const double step = LargestStep(sc, blended, 5.0);
  std::printf("largest output step against the truth: %.4f m without the blend (after the "
              "outage), %.4f m with it (whole run)\n", jump, step);
  ASSERT_GT(jump, 0.1);  // the scenario does make the output jump
  EXPECT_LT(step, blend.position_rate_mps * 0.01 + 0.003);

  double late_difference = 0.0, covariance_mismatch = 0.0;
  for (const auto& [t, e] : blended) {
    const auto it = jumping.find(t);
    ASSERT_NE(it, jumping.end());
    const Vec9 offset = testing::StateDifference(e.state, it->second.state);
    if (ToSeconds(t) > so.outage_end_s + 1.0 + blend.max_s) {
      late_difference = std::max(late_difference, offset.segment<3>(3).norm());
    }
    const Mat9 added =
        e.covariance.topLeftCorner<9, 9>() - it->second.covariance.topLeftCorner<9, 9>();
    covariance_mismatch =
        std::max(covariance_mismatch, (added - offset * offset.transpose()).norm());
  }
  std::printf("from 2 s after the outage: |output - unblended| <= %.2e m; covariance - (P + b "
              "b^T) <= %.2e\n", late_difference, covariance_mismatch);
  EXPECT_LT(late_difference, 0.02);
  EXPECT_LT(covariance_mismatch, 1e-9);
}

}  // namespace
}  // namespace statebench::est
