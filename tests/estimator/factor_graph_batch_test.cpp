// The full-batch smoother (FactorGraphOptions::batch) against the fixed-lag smoother it bounds, and
// the fixed-lag smoother's smoothed output (FactorGraphOptions::lagged_output): each state as it
// left the window, against the real-time output of the same smoother.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

#include "estimator/factor_graph_estimator.hpp"
#include "estimator_scenario.hpp"

namespace statebench::est {
namespace {

// Every estimate at an IMU stamp: the fixed-lag one as it runs (real time), the batch one after
// the end of the log.
std::map<TimeNs, StateEstimate> BatchRunOutputs(const testing::Scenario& sc, FactorGraphOptions o,
                                        bool batch, EstimatorDiagnostics* diagnostics) {
  o.batch = batch;
  FactorGraphEstimator estimator(testing::MakeSetup(sc.options), o);
  EXPECT_EQ(estimator.EstimatesAtEnd(), batch);
  std::map<TimeNs, StateEstimate> out;
  std::vector<TimeNs> stamps;
  testing::FeedOutputs(estimator, sc.stream,
                       [&](TimeNs t, const std::optional<StateEstimate>& e) {
                         stamps.push_back(t);
                         if (batch) EXPECT_FALSE(e.has_value());  // not before the end
                         if (e && !batch) out[t] = *e;
                       });
  estimator.EndOfLog();
  if (batch) {
    for (TimeNs t : stamps) {
      if (const auto e = estimator.StateAt(t)) out[t] = *e;
    }
  }
  *diagnostics = estimator.diagnostics();
  return out;
}

struct BatchRmse {
  double position_m = 0.0;
  double yaw_rad = 0.0;
  double velocity_mps = 0.0;
  int epochs = 0;
};

// Over the stamps both estimators estimated from from_s on.
BatchRmse BatchRmseOf(const testing::Scenario& sc, const std::map<TimeNs, StateEstimate>& out,
            const std::map<TimeNs, StateEstimate>& other, double from_s) {
  BatchRmse r;
  for (const auto& [t, e] : out) {
    if (ToSeconds(t) < from_s || !other.count(t)) continue;
    const NavState truth = sc.Truth(t);
    r.position_m += (e.state.p_world - truth.p_world).squaredNorm();
    r.yaw_rad += std::pow(testing::YawError(e.state, truth), 2);
    r.velocity_mps += (e.state.v_world - truth.v_world).squaredNorm();
    ++r.epochs;
  }
  r.position_m = std::sqrt(r.position_m / r.epochs);
  r.yaw_rad = std::sqrt(r.yaw_rad / r.epochs);
  r.velocity_mps = std::sqrt(r.velocity_mps / r.epochs);
  return r;
}

// `better` is no worse than `worse` on position, yaw and velocity from 5 s on, over the same
// stamps.
void ExpectNoWorse(const testing::Scenario& sc, const char* names,
                   const std::map<TimeNs, StateEstimate>& worse,
                   const std::map<TimeNs, StateEstimate>& better) {
  const BatchRmse w = BatchRmseOf(sc, worse, better, 5.0);
  const BatchRmse b = BatchRmseOf(sc, better, worse, 5.0);
  std::printf("RMSE %s: position %.3f / %.3f m, yaw %.4f / %.4f rad, "
              "velocity %.3f / %.3f m/s over %d epochs\n",
              names, w.position_m, b.position_m, w.yaw_rad, b.yaw_rad, w.velocity_mps,
              b.velocity_mps, w.epochs);
  EXPECT_EQ(w.epochs, b.epochs);
  EXPECT_LE(b.position_m, w.position_m);
  EXPECT_LE(b.yaw_rad, w.yaw_rad);
  EXPECT_LE(b.velocity_mps, w.velocity_mps);
}

FactorGraphOptions BatchTestOptions() {
  FactorGraphOptions o;
  o.origin = testing::kTestOrigin;
  return o;
}

testing::Scenario NoisyDriveWithOutage() {
  testing::ScenarioOptions so = testing::DriftingImuRtkOptions(45.0);
  so.gnss_sigma_h = so.reported_sigma_h = 0.3;
  so.gnss_sigma_v = so.reported_sigma_v = 0.5;
  so.outage_begin_s = 20.0;
  so.outage_end_s = 30.0;
  so.seed = 7;
  return testing::MakeScenario(so);
}

// A noisy IMU with biases and 0.3 m GNSS with a 10 s outage: the fixed-lag output through the
// outage is an IMU prediction; the batch has the fixes after it too. The batch is no worse on
// any metric, and much better through the outage.
TEST(FactorGraphBatch, IsNoWorseThanTheFixedLagSmootherOnANoisyDrive) {
  const testing::Scenario sc = NoisyDriveWithOutage();
  EstimatorDiagnostics fixed_diag, batch_diag;
  const auto fixed = BatchRunOutputs(sc, BatchTestOptions(), false, &fixed_diag);
  const auto batch = BatchRunOutputs(sc, BatchTestOptions(), true, &batch_diag);
  ASSERT_EQ(batch_diag.batch_solves.size(), 1u);
  EXPECT_TRUE(batch_diag.batch_solves[0].usable);
  EXPECT_LT(batch_diag.batch_solves[0].final_cost, batch_diag.batch_solves[0].initial_cost);
  EXPECT_TRUE(fixed_diag.batch_solves.empty());
  // The batch estimates every stamp the fixed-lag smoother does, and its covariance is finite.
  for (const auto& [t, e] : fixed) {
    const auto it = batch.find(t);
    ASSERT_NE(it, batch.end()) << ToSeconds(t);
    ASSERT_TRUE(it->second.covariance.allFinite());
  }
  ExpectNoWorse(sc, "fixed-lag / batch", fixed, batch);
}

// With a window longer than the drive nothing is marginalised: the fixed-lag smoother's last
// window (after EndOfLog: every measurement in, solved once more) is the batch problem, so its
// smoothed states and the batch's agree to the solver's tolerance.
TEST(FactorGraphBatch, AgreesWithAFixedLagSmootherWhoseWindowHoldsTheWholeDrive) {
  testing::ScenarioOptions so = testing::DriftingImuRtkOptions(20.0);
  so.gnss_sigma_h = so.reported_sigma_h = 0.3;
  so.gnss_sigma_v = so.reported_sigma_v = 0.5;
  const testing::Scenario sc = testing::MakeScenario(so);
  FactorGraphOptions o = BatchTestOptions();
  o.window_s = 100.0;
  o.max_iterations = 50;
  o.output_blend.max_s = 0.0;  // the smoothed states as they are
  FactorGraphEstimator fixed(testing::MakeSetup(so), o);
  std::vector<TimeNs> stamps;
  testing::FeedOutputs(fixed, sc.stream, [&](TimeNs t, const auto&) { stamps.push_back(t); });
  fixed.EndOfLog();  // as the batch: the held measurements in, one more solve
  EstimatorDiagnostics batch_diag;
  const auto batch = BatchRunOutputs(sc, o, true, &batch_diag);
  ASSERT_EQ(batch_diag.batch_solves.size(), 1u);
  const BatchSolve& solve = batch_diag.batch_solves[0];
  // The same problem at the same point: the batch finds nothing to improve beyond the
  // Levenberg-Marquardt's function tolerance (1e-6 of the cost).
  EXPECT_TRUE(solve.usable);
  EXPECT_LE(solve.initial_cost - solve.final_cost, 1e-6 * solve.initial_cost);
  // Two points whose costs differ by less than the tolerance differ by d with
  // d^T H d <= 2 x 1e-6 x cost, and any state's part of d by as much in its marginal's metric:
  // the bound on the squared Mahalanobis distance of rotation, position and velocity.
  const double bound = 2.0 * 1e-6 * solve.initial_cost;
  double largest = 0.0, position = 0.0;
  int compared = 0;
  for (TimeNs t : stamps) {
    const std::optional<StateEstimate> f = fixed.StateAt(t);
    const auto b = batch.find(t);
    if (!f || b == batch.end()) continue;
    const Vec9 d = testing::StateDifference(f->state, b->second.state);
    const Mat9 P = b->second.covariance.topLeftCorner<9, 9>();
    largest = std::max(largest, d.dot(P.ldlt().solve(d)));
    position = std::max(position, d.segment<3>(3).norm());
    ++compared;
  }
  std::printf("fixed-lag (whole-drive window) vs batch over %d stamps: squared Mahalanobis "
              "distance up to %.2e (bound %.2e), position up to %.2e m\n",
              compared, largest, bound, position);
  EXPECT_GT(compared, 1600);
  EXPECT_LE(largest, bound);
}

// The lagged estimator gives nothing before the end of the log and, after it, an estimate at
// every stamp the real-time one estimated; at the stamp of each state that left the window its
// mean is that state's estimate when it left (what the real-time estimator's
// TakeSmoothedStates hands out), bit for bit: the smoother ran the same way.
TEST(FactorGraphLagged, IsTheSmootherStatesAsTheyLeftTheWindow) {
  const testing::Scenario sc = NoisyDriveWithOutage();
  FactorGraphOptions o = BatchTestOptions();
  FactorGraphEstimator online(testing::MakeSetup(sc.options), o);
  online.KeepSmoothedStates();
  std::map<TimeNs, StateEstimate> real_time;
  std::vector<NavState> smoothed;
  testing::FeedOutputs(online, sc.stream, [&](TimeNs t, const std::optional<StateEstimate>& e) {
    if (e) real_time[t] = *e;
    for (const NavState& s : online.TakeSmoothedStates()) smoothed.push_back(s);
  });

  o.lagged_output = true;
  FactorGraphEstimator lagged(testing::MakeSetup(sc.options), o);
  EXPECT_TRUE(lagged.EstimatesAtEnd());
  std::vector<TimeNs> stamps;
  testing::FeedOutputs(lagged, sc.stream, [&](TimeNs t, const std::optional<StateEstimate>& e) {
    EXPECT_FALSE(e.has_value());  // not before the end
    stamps.push_back(t);
  });
  lagged.EndOfLog();
  std::map<TimeNs, StateEstimate> out;
  for (TimeNs t : stamps) {
    if (const auto e = lagged.StateAt(t)) out[t] = *e;
  }
  for (const auto& [t, e] : real_time) {
    const auto it = out.find(t);
    ASSERT_NE(it, out.end()) << ToSeconds(t);
    ASSERT_TRUE(it->second.covariance.allFinite());
    ASSERT_GT(it->second.covariance.diagonal().minCoeff(), 0.0);
  }
  ASSERT_GT(smoothed.size(), 300u);
  int compared = 0;
  for (const NavState& s : smoothed) {
    const auto it = out.find(s.t_ns);
    if (it == out.end()) continue;
    EXPECT_EQ(it->second.state.p_world, s.p_world) << ToSeconds(s.t_ns);
    EXPECT_EQ(it->second.state.v_world, s.v_world) << ToSeconds(s.t_ns);
    EXPECT_EQ(it->second.state.q_world_imu.coeffs(), s.q_world_imu.coeffs());
    ++compared;
  }
  EXPECT_EQ(compared, static_cast<int>(smoothed.size()));

  // The lag's measurements make it no worse than the real-time output on any metric.
  ExpectNoWorse(sc, "real-time / lagged", real_time, out);
}

TEST(FactorGraphLagged, ExcludesTheBatch) {
  FactorGraphOptions o = BatchTestOptions();
  o.lagged_output = true;
  EXPECT_TRUE(o.IsValid());
  o.batch = true;
  std::string why;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("lagged_output"), std::string::npos);
}

}  // namespace
}  // namespace statebench::est
