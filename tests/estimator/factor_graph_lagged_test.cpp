// The fixed-lag smoother's smoothed output (FactorGraphOptions::lagged_output): each state as it
// left the window, against the real-time output of the same smoother.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

#include "estimator/factor_graph_estimator.hpp"
#include "estimator_scenario.hpp"

namespace statebench::est {
namespace {

FactorGraphOptions LaggedTestOptions() {
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

struct LaggedRmse {
  double position_m = 0.0;
  double yaw_rad = 0.0;
  double velocity_mps = 0.0;
  int epochs = 0;
};

LaggedRmse LaggedRmseOf(const testing::Scenario& sc, const std::map<TimeNs, StateEstimate>& out,
                        const std::map<TimeNs, StateEstimate>& other, double from_s) {
  LaggedRmse r;
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

// The lagged estimator gives nothing before the end of the log and, after it, an estimate at
// every stamp the real-time one estimated; at the stamp of each state that left the window its
// mean is that state's estimate when it left (what the real-time estimator's
// TakeSmoothedStates hands out), bit for bit: the smoother ran the same way.
TEST(FactorGraphLagged, IsTheSmootherStatesAsTheyLeftTheWindow) {
  const testing::Scenario sc = NoisyDriveWithOutage();
  FactorGraphOptions o = LaggedTestOptions();
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
  const LaggedRmse f = LaggedRmseOf(sc, real_time, out, 5.0);
  const LaggedRmse l = LaggedRmseOf(sc, out, real_time, 5.0);
  std::printf("RMSE real-time / lagged: position %.3f / %.3f m, yaw %.4f / %.4f rad, "
              "velocity %.3f / %.3f m/s over %d epochs\n",
              f.position_m, l.position_m, f.yaw_rad, l.yaw_rad, f.velocity_mps, l.velocity_mps,
              f.epochs);
  EXPECT_LE(l.position_m, f.position_m);
  EXPECT_LE(l.yaw_rad, f.yaw_rad);
  EXPECT_LE(l.velocity_mps, f.velocity_mps);
}

TEST(FactorGraphLagged, ExcludesTheBatch) {
  FactorGraphOptions o = LaggedTestOptions();
  o.lagged_output = true;
  EXPECT_TRUE(o.IsValid());
  o.batch = true;
  std::string why;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("lagged_output"), std::string::npos);
}

}  // namespace
}  // namespace statebench::est
