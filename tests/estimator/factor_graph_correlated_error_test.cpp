// The factor graph's slow GNSS error states (gnss.estimate_correlated_error) per receiver: with
// `auto` (the default) a receiver whose setup describes its slow error gets the three states with
// the setup's sigmas, one that does not gets none; `true` gives every receiver states (the
// setup's figures where given, else the options'); `false` none. On the figure eight with a
// noisy IMU and CEP 2 m fixes, seed 12 (not the tuning seed).
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "estimator/factor_graph_estimator.hpp"
#include "estimator_scenario.hpp"

namespace statebench::est {
namespace {

using Globals = std::map<std::string, GlobalDiagnostics>;

testing::ScenarioOptions Options() {
  testing::ScenarioOptions so;
  so.duration_s = 20.0;
  so.imu_noisy = true;
  so.gnss_sigma_h = so.reported_sigma_h = 1.7;
  so.gnss_sigma_v = so.reported_sigma_v = 2.55;
  so.seed = 12;
  return so;
}

// The setup of Options(), its receiver's slow error described (as its `estimator:` block
// would) or not.
EstimatorSensorSetup SetupWith(bool described) {
  EstimatorSensorSetup setup = testing::MakeSetup(Options());
  if (described) {
    GnssAntenna& a = setup.antennas.at(0);
    a.correlated_error_sigma_m = 0.17;
    a.correlated_error_vertical_sigma_m = 0.255;
    a.correlated_error_tau_s = 100.0;
  }
  return setup;
}

Globals GlobalsOfRun(const EstimatorSensorSetup& setup, FactorUse use) {
  const testing::Scenario sc = testing::MakeScenario(Options());
  FactorGraphOptions options;
  options.origin = testing::kTestOrigin;
  options.gnss.estimate_correlated_error = use;
  FactorGraphEstimator estimator(setup, options);
  for (const Measurement& m : sc.stream) estimator.Add(m);
  const auto& sensors = estimator.diagnostics().sensors;
  const auto it = sensors.find("gnss_front");
  return it == sensors.end() ? Globals{} : it->second.globals;
}

// The first and last sigma the states reported, per axis, against its prior.
void ExpectPriors(const Globals& g, double horizontal, double vertical) {
  const char* names[3] = {"error_east_m", "error_north_m", "error_up_m"};
  for (int k = 0; k < 3; ++k) {
    SCOPED_TRACE(names[k]);
    const auto it = g.find(names[k]);
    ASSERT_NE(it, g.end());
    const double prior = k < 2 ? horizontal : vertical;
    ASSERT_FALSE(it->second.history.empty());
    EXPECT_LE(it->second.history.front().sigma, prior * (1.0 + 1e-9));
    // Absolute position and slow error are told apart only by their priors: the fixes leave
    // the error's sigma near its prior.
    EXPECT_GT(it->second.sigma, 0.5 * prior);
    EXPECT_LE(it->second.sigma, prior * (1.0 + 1e-9));
    EXPECT_EQ(it->second.clamped, 0);
  }
}

TEST(FactorGraphCorrelatedError, AutoEstimatesTheDescribedReceiversErrorWithItsSigmas) {
  ExpectPriors(GlobalsOfRun(SetupWith(true), FactorUse::kAuto), 0.17, 0.255);
}

TEST(FactorGraphCorrelatedError, AutoLeavesAnUndescribedReceiverWithoutErrorStates) {
  const Globals g = GlobalsOfRun(SetupWith(false), FactorUse::kAuto);
  EXPECT_EQ(g.count("error_east_m"), 0u);
  EXPECT_EQ(g.count("error_up_m"), 0u);
}

TEST(FactorGraphCorrelatedError, FalseTurnsADescribedReceiversStatesOff) {
  const Globals g = GlobalsOfRun(SetupWith(true), FactorUse::kOff);
  EXPECT_EQ(g.count("error_east_m"), 0u);
}

TEST(FactorGraphCorrelatedError, TrueGivesAnUndescribedReceiverTheOptionsSigmas) {
  const MeasurementGateOptions defaults = FactorGraphOptions{}.gnss;
  ExpectPriors(GlobalsOfRun(SetupWith(false), FactorUse::kOn), defaults.correlated_error_sigma_m,
               defaults.correlated_error_vertical_sigma_m);
}

// The start is made of the receiver's fixes, so it carries the receiver's slow error: with the
// error described, the first estimate's position covariance is the start's plus the error's
// (gnss_front_end_start.cpp): exactly, the start being the same fixes' either way.
TEST(FactorGraphCorrelatedError, TheStartCarriesTheReceiversSlowError) {
  const testing::Scenario sc = testing::MakeScenario(Options());
  FactorGraphOptions options;
  options.origin = testing::kTestOrigin;
  std::vector<StateEstimate> with, without;
  for (const bool described : {true, false}) {
    FactorGraphEstimator estimator(SetupWith(described), options);
    std::vector<StateEstimate>& out = described ? with : without;
    testing::FeedOutputs(estimator, sc.stream, [&](TimeNs, const std::optional<StateEstimate>& e) {
      if (e) out.push_back(*e);
    });
  }
  ASSERT_FALSE(with.empty());
  ASSERT_FALSE(without.empty());
  ASSERT_EQ(with.front().state.t_ns, without.front().state.t_ns);  // the same start
  const Mat3 added = with.front().covariance.block<3, 3>(3, 3) -
                     without.front().covariance.block<3, 3>(3, 3);
  const Vec3 slow(0.17, 0.17, 0.255);
  EXPECT_TRUE(added.isApprox(Mat3(slow.cwiseAbs2().asDiagonal()), 1e-9)) << added;
}

}  // namespace
}  // namespace statebench::est
