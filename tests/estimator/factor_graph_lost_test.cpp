// The factor graph finds itself lost and starts over: when the GNSS gate has refused every fix
// for gate_reset_s while the refused fixes agree with each other (a consistent track the
// estimate no longer matches), it says so in its diagnostics, re-initialises from the sensors and
// follows the fixes again; a short jump of the fixes is ridden out without starting over.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "core/geodetic.hpp"
#include "core/so3.hpp"
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
  testing::FeedOutputs(estimator, stream, [&](TimeNs t, const std::optional<StateEstimate>& e) {
    if (!e) {
      out.missing_after_init += estimator.diagnostics().initialized ? 1 : 0;
      return;
    }
    if (!e->state.p_world.allFinite() || !e->covariance.allFinite()) ++out.non_finite;
    const auto [it, first] =
        out.status_seen.try_emplace(e->status, ToSeconds(t), ToSeconds(t));
    if (!first) it->second.second = ToSeconds(t);
    if (ToSeconds(t) > end_s - 5.0) {
      const Vec3 expected = sc.Truth(t).p_world + final_offset;
      out.final_error_m = std::max(out.final_error_m, (e->state.p_world - expected).norm());
    }
  });
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


// A dual-antenna start whose heading is `angle` off: for the first `seconds` the rear
// antenna's fixes turned by `angle` about the front antenna's of the same stamp (the front
// fixes, the position, stay right); after that the rear antenna is silent and only the front
// antenna's positions can correct the yaw.
std::vector<Measurement> TurnedHeadingThenSingleAntenna(const Scenario& sc, double angle,
                                                        double seconds) {
  const LocalEnuFrame frame(testing::kTestOrigin);
  std::map<TimeNs, Vec3> front;
  for (const Measurement& m : sc.stream) {
    if (const auto* f = std::get_if<GnssFix>(&m); f && f->header.sensor_id == "gnss_front") {
      front[f->header.stamp_ns] = frame.ToEnu({f->latitude_deg, f->longitude_deg, f->altitude_m});
    }
  }
  const Eigen::AngleAxisd turn(angle, Vec3::UnitZ());
  std::vector<Measurement> stream;
  for (Measurement m : sc.stream) {
    if (auto* f = std::get_if<GnssFix>(&m); f && f->header.sensor_id == "gnss_rear") {
      if (ToSeconds(f->header.stamp_ns) >= sc.options.start_s + seconds) continue;
      const Vec3& p_front = front.at(f->header.stamp_ns);
      const Vec3 p = frame.ToEnu({f->latitude_deg, f->longitude_deg, f->altitude_m});
      const GeodeticPoint g = frame.ToGeodetic(p_front + turn * (p - p_front));
      f->latitude_deg = g.latitude_deg;
      f->longitude_deg = g.longitude_deg;
      f->altitude_m = g.altitude_m;
    }
    stream.push_back(m);
  }
  return stream;
}

// Issue 14: a start with a 90 deg yaw error (a dual-antenna heading turned by 90 deg) and then
// only one antenna's positions to correct it. The estimate must not gate every later fix out for
// ever: it is within 2 m of the truth, for good, less than 60 s after the start (on seeds 4 and 5
// it finds itself lost and starts over from the GNSS course; on seed 3 the fixes turn it round
// before the gate refuses them).
TEST(FactorGraphLost, ANinetyDegreeYawErrorAtTheStartIsRecoveredFromGnssAlone) {
  ScenarioOptions so = Drive();
  so.duration_s = 80.0;
  so.antennas.push_back({"gnss_rear", Vec3(-0.8, 0.0, 1.0)});
  for (const std::uint64_t seed : {3u, 4u, 5u}) {
    so.seed = seed;
    const Scenario sc = MakeScenario(so);
    const std::vector<Measurement> stream = TurnedHeadingThenSingleAntenna(sc, M_PI / 2.0, 2.0);
    FactorGraphOptions options;
    options.origin = testing::kTestOrigin;
    FactorGraphEstimator estimator(testing::MakeSetup(sc.options), options);
    std::optional<double> first_yaw_error_rad;
    double last_far_s = sc.options.start_s;  // the last output more than 2 m off
    int non_finite = 0;
    double final_rotation_error_rad = NAN;
    testing::FeedOutputs(estimator, stream, [&](TimeNs t, const std::optional<StateEstimate>& e) {
      if (!e) return;
      if (!e->state.p_world.allFinite() || !e->covariance.allFinite()) ++non_finite;
      const NavState truth = sc.Truth(t);
      if (!first_yaw_error_rad) first_yaw_error_rad = testing::YawError(e->state, truth);
      if ((e->state.p_world - truth.p_world).norm() > 2.0) last_far_s = ToSeconds(t);
      final_rotation_error_rad = testing::RotationError(e->state, truth);
    });
    const EstimatorDiagnostics& d = estimator.diagnostics();
    std::printf("seed %llu: initial yaw error %.0f deg, lost %zu times, within 2 m from %.1f s "
                "after the start, final attitude error %.2f deg\n",
                static_cast<unsigned long long>(seed),
                first_yaw_error_rad.value_or(NAN) * 180.0 / M_PI, d.lost.size(),
                last_far_s - sc.options.start_s, final_rotation_error_rad * 180.0 / M_PI);
    ASSERT_TRUE(first_yaw_error_rad.has_value());
    EXPECT_GT(*first_yaw_error_rad, 60.0 * M_PI / 180.0);  // the start really was wrong
    EXPECT_LT(last_far_s - sc.options.start_s, 60.0);
    EXPECT_LT(final_rotation_error_rad, 0.02);
    EXPECT_EQ(non_finite, 0);
  }
}

}  // namespace
}  // namespace statebench::est
