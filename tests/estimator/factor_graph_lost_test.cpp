// The factor graph finds itself lost and starts over: when the GNSS gate has refused every fix
// for gate_reset_s while the refused fixes agree with each other (a consistent track the
// estimate no longer matches), it says so in its diagnostics, re-initialises from the sensors and
// follows the fixes again; a short jump of the fixes is ridden out without starting over.
#include <gtest/gtest.h>

#include <map>
#include <utility>
#include <vector>

#include "core/geodetic.hpp"
#include "estimator/factor_graph_estimator.hpp"
#include "estimator_scenario.hpp"

namespace statebench::est {
namespace {

using testing::MakeScenario;
using testing::Scenario;
using testing::ScenarioOptions;

// The scenario's fixes moved by `offset` (ENU) between from_s and to_s.
std::vector<Measurement> ShiftedFixes(const Scenario& sc, const Vec3& offset, double from_s,
                                      double to_s) {
  const LocalEnuFrame frame(testing::kTestOrigin);
  std::vector<Measurement> stream = sc.stream;
  for (Measurement& m : stream) {
    auto* f = std::get_if<GnssFix>(&m);
    if (f == nullptr) continue;
    const double t = ToSeconds(f->header.stamp_ns);
    if (t < from_s || t >= to_s) continue;
    const GeodeticPoint p =
        frame.ToGeodetic(frame.ToEnu({f->latitude_deg, f->longitude_deg, f->altitude_m}) + offset);
    f->latitude_deg = p.latitude_deg;
    f->longitude_deg = p.longitude_deg;
    f->altitude_m = p.altitude_m;
  }
  return stream;
}

struct LostOutcome {
  EstimatorDiagnostics diagnostics;
  int non_finite = 0;
  int missing_after_init = 0;        // IMU samples without an estimate once first initialised
  double final_error_m = 0.0;        // max over the last 5 s, against truth + final offset
  std::map<EstimateStatus, std::pair<double, double>> status_seen;  // first and last time, s
};

LostOutcome Feed(const Scenario& sc, const std::vector<Measurement>& stream, const Vec3& final_offset) {
  FactorGraphOptions options;
  options.origin = testing::kTestOrigin;
  FactorGraphEstimator estimator(testing::MakeSetup(sc.options), options);
  LostOutcome out;
  const double end_s = sc.options.start_s + sc.options.duration_s;
  for (const Measurement& m : stream) {
    estimator.Add(m);
    if (!std::holds_alternative<ImuSample>(m)) continue;
    const TimeNs t = HeaderOf(m).stamp_ns;
    const auto e = estimator.StateAt(t);
    if (!e) {
      out.missing_after_init += estimator.diagnostics().initialized ? 1 : 0;
      continue;
    }
    if (!e->state.p_world.allFinite() || !e->covariance.allFinite()) ++out.non_finite;
    const auto [it, first] =
        out.status_seen.try_emplace(e->status, ToSeconds(t), ToSeconds(t));
    if (!first) it->second.second = ToSeconds(t);
    if (ToSeconds(t) > end_s - 5.0) {
      const Vec3 expected = sc.Truth(t).p_world + final_offset;
      out.final_error_m = std::max(out.final_error_m, (e->state.p_world - expected).norm());
    }
  }
  out.diagnostics = estimator.diagnostics();
  return out;
}

ScenarioOptions Drive() {
  ScenarioOptions so;
  so.start_s = 10.0;  // moving from the first sample
  so.duration_s = 60.0;
  so.seed = 3;
  so.gnss_sigma_h = so.reported_sigma_h = 0.05;
  so.gnss_sigma_v = so.reported_sigma_v = 0.08;
  return so;
}

TEST(FactorGraphLost, FixesThatJumpForGoodMakeItStartOverAndFollowThem) {
  const Scenario sc = MakeScenario(Drive());
  const Vec3 offset(60.0, -25.0, 0.0);
  const LostOutcome o = Feed(sc, ShiftedFixes(sc, offset, 35.0, 1e9), offset);
  ASSERT_EQ(o.diagnostics.lost.size(), 1u);
  // Lost once the gate has refused the fixes for gate_reset_s (10 s) after the jump.
  EXPECT_GE(ToSeconds(o.diagnostics.lost[0].at_ns), 44.9);
  EXPECT_LT(ToSeconds(o.diagnostics.lost[0].at_ns), 47.0);
  ASSERT_TRUE(o.diagnostics.lost[0].reinitialized_ns.has_value());
  EXPECT_GT(*o.diagnostics.lost[0].reinitialized_ns, o.diagnostics.lost[0].at_ns);
  EXPECT_EQ(o.diagnostics.lost[0].reinitialization, "moving (gnss course)");
  EXPECT_EQ(o.diagnostics.sensors.at("gnss_front").events.at("lost"), 1u);
  EXPECT_GT(o.missing_after_init, 0);  // no estimate while re-initialising
  EXPECT_EQ(o.non_finite, 0);
  EXPECT_LT(o.final_error_m, 0.5);  // on the fixes' track again
  // The output status: dead reckoning from 5 s after the gate began refusing the fixes until
  // the estimator gave up; recovering for 10 s after it re-initialised; global again after.
  const double reinit_s = ToSeconds(*o.diagnostics.lost[0].reinitialized_ns);
  ASSERT_TRUE(o.status_seen.count(EstimateStatus::kDeadReckoning));
  EXPECT_NEAR(o.status_seen.at(EstimateStatus::kDeadReckoning).first, 40.0, 0.2);
  // (the fix that makes it give up is stamped lost[0].at_ns and arrives ~0.15 s later)
  EXPECT_LE(o.status_seen.at(EstimateStatus::kDeadReckoning).second,
            ToSeconds(o.diagnostics.lost[0].at_ns) + 0.2);
  ASSERT_TRUE(o.status_seen.count(EstimateStatus::kRecovering));
  EXPECT_NEAR(o.status_seen.at(EstimateStatus::kRecovering).first, reinit_s, 0.2);
  EXPECT_NEAR(o.status_seen.at(EstimateStatus::kRecovering).second, reinit_s + 10.0, 0.02);
  EXPECT_NEAR(o.status_seen.at(EstimateStatus::kGlobal).second, 70.0, 0.02);
}

TEST(FactorGraphLost, AShortJumpIsRiddenOutWithoutStartingOver) {
  const Scenario sc = MakeScenario(Drive());
  const LostOutcome o = Feed(sc, ShiftedFixes(sc, Vec3(100.0, 0.0, 0.0), 35.0, 40.0), Vec3::Zero());
  EXPECT_TRUE(o.diagnostics.lost.empty());
  EXPECT_EQ(o.missing_after_init, 0);
  EXPECT_EQ(o.non_finite, 0);
  EXPECT_LT(o.final_error_m, 0.5);
}

TEST(FactorGraphLost, FixesThatDisagreeWithEachOtherDoNotMakeItStartOver) {
  // Every fix from 35 s on thrown 40-80 m in alternating directions: the gate refuses them, but
  // they do not form a track; the estimator keeps its own (IMU only, then the gate's reset).
  const Scenario sc = MakeScenario(Drive());
  std::vector<Measurement> stream = sc.stream;
  const LocalEnuFrame frame(testing::kTestOrigin);
  int k = 0;
  for (Measurement& m : stream) {
    auto* f = std::get_if<GnssFix>(&m);
    if (f == nullptr || ToSeconds(f->header.stamp_ns) < 35.0) continue;
    ++k;
    const Vec3 jump = (k % 2 == 0 ? 1.0 : -1.0) * Vec3(40.0 + (k % 5) * 10.0, 0.0, 0.0);
    const GeodeticPoint p = frame.ToGeodetic(
        frame.ToEnu({f->latitude_deg, f->longitude_deg, f->altitude_m}) + jump);
    f->latitude_deg = p.latitude_deg;
    f->longitude_deg = p.longitude_deg;
  }
  const LostOutcome o = Feed(sc, stream, Vec3::Zero());
  EXPECT_TRUE(o.diagnostics.lost.empty());
  EXPECT_EQ(o.non_finite, 0);
}

}  // namespace
}  // namespace statebench::est
