// One scoring span for every estimator of a run, availability counted, truth paired whether it
// comes ahead of the estimates or behind them.
#include "reports/run_scorer.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/so3.hpp"

namespace statebench::reports {
namespace {

constexpr TimeNs kMs = kNsPerMillisecond;

// Straight drive at 5 m/s along x; truth at 1 kHz.
TruthSample Truth(TimeNs t_ns) {
  TruthSample s;
  s.t_ns = t_ns;
  s.body.T_world_frame = SE3(Quat::Identity(), Vec3(5.0 * ToSeconds(t_ns), 0, 0));
  s.body.v_world = Vec3(5.0, 0, 0);
  return s;
}

// An estimate `error_m` off in y, with a 1 m^2 position and 0.01 rad^2 rotation covariance.
StateEstimate Estimate(TimeNs t_ns, double error_m) {
  StateEstimate e;
  e.state.t_ns = t_ns;
  e.state.p_world = Truth(t_ns).body.T_world_frame.translation() + Vec3(0, error_m, 0);
  e.state.v_world = Vec3(5.0, 0, 0);
  e.covariance = Mat15::Identity();
  e.covariance.topLeftCorner<3, 3>() *= 0.01;
  return e;
}

// Estimator 0 starts at 1 s and is 0.1 m off; estimator 1 starts at 3 s and is 0.2 m off,
// except a 1 s gap (3.5 s ... 4.5 s) after which it is 10 m off for 0.5 s; outputs at 100 Hz to
// 10 s. The truth runs `truth_lead_ms` ahead of the outputs (negative: behind them).
std::vector<RunScore> ScoreTwoEstimators(TimeNs truth_lead_ms, RunScoringOptions options = {}) {
  RunScorer scorer(2, SE3(), options);
  TimeNs truth_t = 0;
  for (TimeNs t = 0; t <= 10'000 * kMs; t += 10 * kMs) {
    while (truth_t <= std::min<TimeNs>(t + truth_lead_ms * kMs, 10'000 * kMs)) {
      scorer.AddTruth(Truth(truth_t));
      truth_t += kMs;
    }
    std::vector<std::optional<StateEstimate>> e(2);
    if (t >= 1000 * kMs) e[0] = Estimate(t, 0.1);
    const bool gap = t > 3500 * kMs && t < 4500 * kMs;
    if (t >= 3000 * kMs && !gap) e[1] = Estimate(t, t < 5000 * kMs ? 10.0 : 0.2);
    scorer.AddEpoch(t, e);
  }
  while (truth_t <= 10'000 * kMs) {
    scorer.AddTruth(Truth(truth_t));
    truth_t += kMs;
  }
  return scorer.Finish();
}

TEST(RunScorer, EveryEstimatorIsScoredFromTheLatestFirstEstimate) {
  for (const TimeNs lead : {TimeNs{50}, TimeNs{0}, TimeNs{-200}}) {
    SCOPED_TRACE("truth lead " + std::to_string(lead) + " ms");
    const std::vector<RunScore> s = ScoreTwoEstimators(lead);
    ASSERT_EQ(s.size(), 2u);
    // Span 3.00 s .. 10.00 s: 701 epochs for both.
    EXPECT_EQ(s[0].availability.span_epochs, 701u);
    EXPECT_EQ(s[1].availability.span_epochs, 701u);
    EXPECT_EQ(s[0].metrics.compared, 701u);
    EXPECT_EQ(s[0].metrics.skipped, 200u);  // 1 s .. 2.99 s: before the span
    EXPECT_NEAR(s[0].metrics.rmse_y_m, 0.1, 1e-9);
    // Estimator 1 missed 99 epochs of the span (3.51 .. 4.49 s).
    EXPECT_EQ(s[1].availability.span_finite_estimates, 701u - 99u);
    EXPECT_NEAR(s[1].availability.SpanFraction(), 602.0 / 701.0, 1e-12);
    EXPECT_EQ(s[1].metrics.compared, 602u);
    EXPECT_EQ(s[0].availability.epochs, 1001u);
    EXPECT_EQ(s[0].availability.finite_estimates, 901u);
  }
}

TEST(RunScorer, AnEstimatorThatStartsAfterTheWaitDoesNotHoldTheOthersSpan) {
  RunScoringOptions options;
  options.span_wait_ns = FromSeconds(1.0);  // estimator 1 starts 2 s after estimator 0
  const std::vector<RunScore> s = ScoreTwoEstimators(20, options);
  // Span from 1 s: estimator 0 scored over 901 epochs; estimator 1 unavailable for the first
  // 2 s of it and in its gap.
  EXPECT_EQ(s[0].metrics.compared, 901u);
  EXPECT_EQ(s[1].availability.span_epochs, 901u);
  EXPECT_EQ(s[1].availability.span_finite_estimates, 602u);
}

TEST(RunScorer, NonFiniteEstimatesAreUnavailableAndNotScored) {
  RunScorer scorer(1, SE3(), {});
  for (TimeNs t = 0; t <= 1000 * kMs; t += kMs) scorer.AddTruth(Truth(t));
  for (TimeNs t = 0; t <= 1000 * kMs; t += 10 * kMs) {
    StateEstimate e = Estimate(t, 0.1);
    if (t == 500 * kMs) e.state.p_world.x() = std::nan("");
    scorer.AddEpoch(t, {e});
  }
  const RunScore s = scorer.Finish().front();
  EXPECT_EQ(s.availability.span_epochs, 101u);
  EXPECT_EQ(s.availability.span_finite_estimates, 100u);
  EXPECT_EQ(s.metrics.non_finite, 1u);
  EXPECT_EQ(s.metrics.compared, 100u);
  EXPECT_TRUE(std::isfinite(s.metrics.rmse_x_m));
}

// A factor graph that starts in a local frame (status `local`: its own origin at the first state,
// x along the vehicle's heading) and moves into ENU at 3 s, as setup 2's does with a speed
// encoder and a CEP 2 m receiver. Its local estimates lie 100 m and 90 deg from the truth: they
// are not in the truth's frame and must not be compared with it. The span begins at the first
// ENU estimate.
TEST(RunScorer, LocalFrameEstimatesAreNotComparedWithTheTruth) {
  RunScorer scorer(1, SE3(), {});
  for (TimeNs t = 0; t <= 10'000 * kMs; t += kMs) scorer.AddTruth(Truth(t));
  for (TimeNs t = 1000 * kMs; t <= 10'000 * kMs; t += 10 * kMs) {
    StateEstimate e = Estimate(t, 0.1);
    if (t < 3000 * kMs) {
      e.status = EstimateStatus::kLocal;
      e.state.p_world = Vec3(0.0, 5.0 * ToSeconds(t - 1000 * kMs), 0.0) - Vec3(60, 80, 0);
      e.state.q_world_imu = Quat(Eigen::AngleAxisd(0.5 * M_PI, Vec3::UnitZ()));
    }
    scorer.AddEpoch(t, {e});
  }
  const RunScore s = scorer.Finish().front();
  EXPECT_EQ(s.metrics.skipped, 200u);  // 1 s .. 2.99 s, local
  EXPECT_EQ(s.metrics.compared, 701u);
  EXPECT_NEAR(s.metrics.rmse_y_m, 0.1, 1e-9);
  EXPECT_NEAR(s.metrics.rmse_x_m, 0.0, 1e-9);
  EXPECT_EQ(s.availability.span_epochs, 701u);
  EXPECT_EQ(s.availability.span_finite_estimates, 701u);
  EXPECT_EQ(s.availability.span_local_estimates, 0u);
  EXPECT_EQ(s.availability.finite_estimates, 901u);
}

// An estimator that never leaves its local frame (no GNSS) while another is in ENU: the span
// begins with the ENU one; the local estimates inside it are counted, not compared.
TEST(RunScorer, AnEstimatorStillLocalInsideTheSpanIsCountedNotCompared) {
  RunScorer scorer(2, SE3(), {});
  for (TimeNs t = 0; t <= 2000 * kMs; t += kMs) scorer.AddTruth(Truth(t));
  for (TimeNs t = 0; t <= 2000 * kMs; t += 10 * kMs) {
    StateEstimate local = Estimate(t, 50.0);
    local.status = EstimateStatus::kLocal;
    scorer.AddEpoch(t, {Estimate(t, 0.1), local});
  }
  const std::vector<RunScore> s = scorer.Finish();
  EXPECT_EQ(s[0].metrics.compared, 201u);
  EXPECT_EQ(s[1].metrics.compared, 0u);
  EXPECT_EQ(s[1].metrics.skipped, 201u);
  EXPECT_EQ(s[1].availability.span_epochs, 201u);
  EXPECT_EQ(s[1].availability.span_local_estimates, 201u);
  EXPECT_EQ(s[1].availability.span_finite_estimates, 0u);
  EXPECT_EQ(s[1].availability.finite_estimates, 201u);
}

}  // namespace
}  // namespace statebench::reports
