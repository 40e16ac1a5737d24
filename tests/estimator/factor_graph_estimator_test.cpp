#include "estimator/factor_graph_estimator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numbers>
#include <type_traits>

#include "core/random.hpp"
#include "estimator_scenario.hpp"

namespace statebench::est {
namespace {

using testing::Antenna;
using testing::DriftingImuRtkOptions;
using testing::MakeScenario;
using testing::MakeSetup;
using testing::Scenario;
using testing::ScenarioOptions;

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

struct RunResult {
  // Real-time output (StateAt the newest IMU sample) from eval_from_s on.
  double max_position_error = 0.0;  // m
  double max_rotation_error = 0.0;  // rad
  double max_velocity_error = 0.0;  // m/s
  int outputs = 0;
  int non_finite_outputs = 0;
  std::vector<NavState> smoothed;
  EstimatorDiagnostics diagnostics;
};

// Feeds the stream in arrival order and reads the IMU-rate output after each IMU sample.
RunResult RunEstimator(const Scenario& sc, const std::vector<Measurement>& stream,
                       const EstimatorSensorSetup& setup, const FactorGraphOptions& options,
                       double eval_from_s, double eval_to_s = 1e9) {
  FactorGraphEstimator estimator(setup, options);
  estimator.KeepSmoothedStates();
  RunResult r;
  for (const Measurement& m : stream) {
    estimator.Add(m);
    const std::vector<NavState> s = estimator.TakeSmoothedStates();
    r.smoothed.insert(r.smoothed.end(), s.begin(), s.end());
    if (!std::holds_alternative<ImuSample>(m)) continue;
    const TimeNs t = HeaderOf(m).stamp_ns;
    const std::optional<StateEstimate> e = estimator.StateAt(t);
    if (!e) continue;
    ++r.outputs;
    const NavState& x = e->state;
    if (!e->covariance.allFinite() || !x.p_world.allFinite() || !x.v_world.allFinite() ||
        !x.q_world_imu.coeffs().allFinite() || !std::isfinite(e->latitude_deg)) {
      ++r.non_finite_outputs;
    }
    if (ToSeconds(t) < eval_from_s || ToSeconds(t) > eval_to_s) continue;
    const NavState truth = sc.Truth(t);
    r.max_position_error = std::max(r.max_position_error, (x.p_world - truth.p_world).norm());
    r.max_rotation_error = std::max(r.max_rotation_error, testing::RotationError(x, truth));
    r.max_velocity_error = std::max(r.max_velocity_error, (x.v_world - truth.v_world).norm());
  }
  r.diagnostics = estimator.diagnostics();
  return r;
}

RunResult RunEstimator(const Scenario& sc, const FactorGraphOptions& options, double eval_from_s) {
  return RunEstimator(sc, sc.stream, MakeSetup(sc.options), options, eval_from_s);
}

FactorGraphOptions TestOptions() {
  FactorGraphOptions o;
  o.origin = testing::kTestOrigin;
  return o;
}

std::uint64_t Rejected(const RunResult& r, const std::string& id, RejectReason reason) {
  const auto s = r.diagnostics.sensors.find(id);
  if (s == r.diagnostics.sensors.end()) return 0;
  const auto c = s->second.rejected.find(reason);
  return c == s->second.rejected.end() ? 0 : c->second;
}

void PrintRun(const char* what, const RunResult& r, double from_s) {
  std::printf(
      "%s: initialised '%s' at %.2f s; from %.0f s max error position %.2e m, rotation "
      "%.2e deg, velocity %.2e m/s over %d outputs\n",
      what, r.diagnostics.initialization.c_str(), ToSeconds(r.diagnostics.initialized_at_ns),
      from_s, r.max_position_error, r.max_rotation_error * kRadToDeg, r.max_velocity_error,
      r.outputs);
}

// Acceptance: noise-free IMU + GNSS, default estimator noise: within 5 mm / 0.01 deg.
TEST(FactorGraphEstimator, NoiseFreeImuAndGnssTrackTruth) {
  for (const bool dual : {false, true}) {
    ScenarioOptions so;
    so.duration_s = 30.0;
    if (dual) so.antennas.push_back({"gnss_rear", Vec3(-0.8, 0.0, 1.0)});
    const Scenario sc = MakeScenario(so);
    const RunResult r = RunEstimator(sc, TestOptions(), 12.0);
    PrintRun(dual ? "noise-free, two antennas" : "noise-free, one antenna", r, 12.0);
    EXPECT_TRUE(r.diagnostics.initialized);
    EXPECT_EQ(r.non_finite_outputs, 0);
    EXPECT_GT(r.outputs, 2500);
    EXPECT_LT(r.max_position_error, 0.005);
    EXPECT_LT(r.max_rotation_error * kRadToDeg, 0.01);
    EXPECT_LT(r.max_velocity_error, 0.005);
  }
}

TEST(FactorGraphEstimator, InitialisesWhileMovingAndConverges) {
  for (const bool dual : {false, true}) {
    ScenarioOptions so;
    so.start_s = 10.0;  // the data starts while driving
    so.duration_s = 30.0;
    if (dual) so.antennas.push_back({"gnss_rear", Vec3(-0.8, 0.0, 1.0)});
    const Scenario sc = MakeScenario(so);
    const RunResult r = RunEstimator(sc, TestOptions(), 25.0);
    PrintRun(dual ? "moving start, two antennas" : "moving start, one antenna", r, 25.0);
    EXPECT_EQ(r.diagnostics.initialization,
              dual ? "moving (dual antenna)" : "moving (gnss course)");
    EXPECT_LT(ToSeconds(r.diagnostics.initialized_at_ns), 13.0);
    EXPECT_EQ(r.non_finite_outputs, 0);
    EXPECT_LT(r.max_position_error, 0.005);
    EXPECT_LT(r.max_rotation_error * kRadToDeg, 0.01);
  }
}

TEST(FactorGraphEstimator, StaticModeInitialisesOnlyAfterAStillPeriod) {
  ScenarioOptions so;
  so.start_s = 10.0;
  so.duration_s = 5.0;
  FactorGraphOptions o = TestOptions();
  o.initialization.mode = InitializationMode::kStatic;
  const Scenario moving = MakeScenario(so);
  const RunResult r = RunEstimator(moving, o, 0.0);
  EXPECT_FALSE(r.diagnostics.initialized);
  EXPECT_EQ(r.outputs, 0);
  so.start_s = 0.0;
  const RunResult s = RunEstimator(MakeScenario(so), o, 0.0);
  EXPECT_EQ(s.diagnostics.initialization, "static (gnss course)");
}

// Acceptance: GNSS delivered up to 0.5 s late and out of order gives the in-order smoothed
// states once they leave the window (noisy data, so any difference in the graph would show).
// The smoother sees the same stamp-ordered stream in both runs; what remains is rounding (Ceres
// sums in an order that depends on parameter block addresses), about 1e-10.
TEST(FactorGraphEstimator, OutOfOrderGnssGivesTheInOrderSmoothedStates) {
  ScenarioOptions so;
  so.duration_s = 20.0;
  so.imu_noisy = true;
  so.gnss_sigma_h = so.reported_sigma_h = 0.05;
  so.gnss_sigma_v = so.reported_sigma_v = 0.08;
  so.gnss_latency_s = 0.1;
  const Scenario in_order = MakeScenario(so);
  so.gnss_extra_latency_s = 0.4;  // latency 0.1-0.5 s, fixes overtake each other
  const Scenario shuffled = MakeScenario(so);
  int overtaken = 0;
  TimeNs last_fix_stamp = 0;
  for (const Measurement& m : shuffled.stream) {
    if (const auto* f = std::get_if<GnssFix>(&m)) {
      overtaken += f->header.stamp_ns < last_fix_stamp;
      last_fix_stamp = std::max(last_fix_stamp, f->header.stamp_ns);
    }
  }
  FactorGraphOptions options = TestOptions();
  options.reorder_latency_s = 0.5;  // the setup says 0.1 s
  const RunResult a = RunEstimator(in_order, options, 10.0);
  const RunResult b = RunEstimator(shuffled, options, 10.0);
  ASSERT_EQ(a.smoothed.size(), b.smoothed.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < a.smoothed.size(); ++i) {
    const NavState& x = a.smoothed[i];
    const NavState& y = b.smoothed[i];
    ASSERT_EQ(x.t_ns, y.t_ns);
    worst = std::max({worst, (x.p_world - y.p_world).cwiseAbs().maxCoeff(),
                      (x.v_world - y.v_world).cwiseAbs().maxCoeff(), testing::RotationError(x, y),
                      (x.gyro_bias - y.gyro_bias).norm(), (x.accel_bias - y.accel_bias).norm()});
  }
  std::printf(
      "out of order: %d fixes overtaken by a later one; %zu smoothed states differ by at "
      "most %.2e\n",
      overtaken, a.smoothed.size(), worst);
  EXPECT_GT(overtaken, 20);
  EXPECT_GT(a.smoothed.size(), 100u);
  EXPECT_LT(worst, 1e-6);
  EXPECT_EQ(Rejected(b, "gnss_front", RejectReason::kTooOld), 0u);
}

// Acceptance: with GNSS cut for 30 s, a 0.5 s window drifts no more than a 2 s window (10 %):
// marginalisation keeps the information of the states that leave.
TEST(FactorGraphEstimator, ShortWindowDriftsNoMoreThanLongWindowInAnOutage) {
  ScenarioOptions so = DriftingImuRtkOptions(50.0);
  so.outage_begin_s = 18.0;
  so.outage_end_s = 48.0;
  const Scenario sc = MakeScenario(so);
  double drift[2];
  const double windows[2] = {0.5, 2.0};
  for (int i = 0; i < 2; ++i) {
    FactorGraphOptions o = TestOptions();
    o.window_s = windows[i];
    const RunResult r =
        RunEstimator(sc, sc.stream, MakeSetup(so), o, so.outage_begin_s, so.outage_end_s);
    drift[i] = r.max_position_error;
    std::printf(
        "window %.1f s: max position error during the 30 s outage %.3f m, rotation %.3f "
        "deg\n",
        windows[i], r.max_position_error, r.max_rotation_error * kRadToDeg);
  }
  EXPECT_GT(drift[1], 0.05);  // the outage is long enough to drift
  EXPECT_LE(drift[0], 1.1 * drift[1]);
}

// A stream with one measurement replaced.
std::vector<Measurement> WithReplaced(std::vector<Measurement> stream, const std::string& id,
                                      double stamp_s, const std::function<void(GnssFix&)>& edit) {
  for (Measurement& m : stream) {
    if (auto* f = std::get_if<GnssFix>(&m);
        f != nullptr && f->header.sensor_id == id && f->header.stamp_ns == FromSeconds(stamp_s)) {
      edit(*f);
    }
  }
  return stream;
}

void MoveFix(GnssFix& f, const Vec3& d_enu) {
  const LocalEnuFrame frame(testing::kTestOrigin);
  const GeodeticPoint g =
      frame.ToGeodetic(frame.ToEnu({f.latitude_deg, f.longitude_deg, f.altitude_m}) + d_enu);
  f.latitude_deg = g.latitude_deg;
  f.longitude_deg = g.longitude_deg;
  f.altitude_m = g.altitude_m;
}

TEST(FactorGraphEstimator, OutlierFixIsRejectedByTheMahalanobisGate) {
  ScenarioOptions so;
  so.duration_s = 20.0;
  const Scenario sc = MakeScenario(so);
  const auto stream = WithReplaced(sc.stream, "gnss_front", 15.0,
                                   [](GnssFix& f) { MoveFix(f, Vec3(10.0, 0.0, 0.0)); });
  const RunResult r = RunEstimator(sc, stream, MakeSetup(so), TestOptions(), 12.0);
  PrintRun("10 m outlier at 15 s", r, 12.0);
  EXPECT_EQ(Rejected(r, "gnss_front", RejectReason::kMahalanobisGate), 1u);
  EXPECT_EQ(r.diagnostics.sensors.at("gnss_front").TotalRejected(), 1u);
  EXPECT_LT(r.max_position_error, 0.005);
}

TEST(FactorGraphEstimator, RobustKernelBoundsAnOutlierTheGateLetsThrough) {
  ScenarioOptions so;
  so.duration_s = 20.0;
  const Scenario sc = MakeScenario(so);
  const auto stream = WithReplaced(sc.stream, "gnss_front", 15.0,
                                   [](GnssFix& f) { MoveFix(f, Vec3(10.0, 0.0, 0.0)); });
  FactorGraphOptions o = TestOptions();
  o.gnss.gate_chi2 = 1e12;  // gate off
  const RunResult r = RunEstimator(sc, stream, MakeSetup(so), o, 12.0);
  o.gnss.kernel.type = RobustKernelType::kNone;
  const RunResult plain = RunEstimator(sc, stream, MakeSetup(so), o, 12.0);
  std::printf("10 m outlier, no gate: max position error with Huber %.3f m, least squares %.3f m\n",
              r.max_position_error, plain.max_position_error);
  EXPECT_EQ(Rejected(r, "gnss_front", RejectReason::kMahalanobisGate), 0u);
  EXPECT_EQ(r.diagnostics.sensors.at("gnss_front").downweighted, 1u);
  EXPECT_LT(r.max_position_error, 0.5 * plain.max_position_error);
}

TEST(FactorGraphEstimator, FixWithHugeReportedCovarianceIsDiscardedByTheThreshold) {
  ScenarioOptions so;
  so.duration_s = 16.0;
  const Scenario sc = MakeScenario(so);
  const auto stream = WithReplaced(sc.stream, "gnss_front", 14.0, [](GnssFix& f) {
    f.covariance_enu = 100.0 * 100.0 * Mat3::Identity();  // sigma 100 m > max_sigma 5 m
  });
  const RunResult r = RunEstimator(sc, stream, MakeSetup(so), TestOptions(), 12.0);
  EXPECT_EQ(Rejected(r, "gnss_front", RejectReason::kCovarianceThreshold), 1u);
  EXPECT_EQ(r.diagnostics.sensors.at("gnss_front").TotalRejected(), 1u);
}

TEST(FactorGraphEstimator, BadInputIsRejectedAndCountedAndTheOutputStaysFinite) {
  ScenarioOptions so;
  so.duration_s = 16.0;
  const Scenario sc = MakeScenario(so);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<Measurement> stream;
  TimeNs t_prev = 0;
  int imu_count = 0;
  for (const Measurement& m : sc.stream) {
    stream.push_back(m);
    const auto* s = std::get_if<ImuSample>(&m);
    if (s == nullptr) continue;
    ++imu_count;
    ImuSample bad = *s;
    if (imu_count % 200 == 50) {  // NaN gyro
      bad.gyro.x() = nan;
      stream.push_back(bad);
    } else if (imu_count % 200 == 100) {  // infinite accel
      bad.accel.z() = inf;
      stream.push_back(bad);
    } else if (imu_count % 200 == 150) {  // 1000 g
      bad.accel.x() = 1e4;
      stream.push_back(bad);
    } else if (imu_count % 200 == 199) {  // stamp going backwards
      bad.header.stamp_ns = t_prev;
      stream.push_back(bad);
    }
    t_prev = s->header.stamp_ns;
  }
  GnssFix nan_fix = std::get<GnssFix>(*std::find_if(stream.begin(), stream.end(), [](auto& m) {
    return std::holds_alternative<GnssFix>(m) && HeaderOf(m).stamp_ns > FromSeconds(13.0);
  }));
  nan_fix.header.stamp_ns += 1;  // not a repeated stamp
  GnssFix absurd_fix = nan_fix;
  nan_fix.latitude_deg = nan;
  absurd_fix.header.stamp_ns += 1;
  absurd_fix.latitude_deg = 95.0;
  GnssFix no_fix = absurd_fix;
  no_fix.header.stamp_ns += 1;
  no_fix.latitude_deg = testing::kTestOrigin.latitude_deg;
  no_fix.status = GnssFixStatus::kNone;
  GnssFix repeated = std::get<GnssFix>(*std::find_if(stream.begin(), stream.end(), [](auto& m) {
    return std::holds_alternative<GnssFix>(m) && HeaderOf(m).stamp_ns > FromSeconds(14.0);
  }));
  LidarScan scan;
  scan.header.sensor_id = "lidar_roof";
  WheelSpeeds wheels;
  wheels.header.sensor_id = "no_such_sensor";
  const auto at = std::find_if(stream.begin(), stream.end(),
                               [](auto& m) { return HeaderOf(m).arrival_ns > FromSeconds(14.5); });
  stream.insert(at, {nan_fix, absurd_fix, no_fix, repeated, scan, wheels});

  const std::string lidar =
      "  - {type: lidar, id: lidar_roof, rate_hz: 10, latency_s: 0.02, "
      "T_body_sensor: {translation: [0, 0, 1.5]}, model: hesai_xt32}\n";
  const RunResult r = RunEstimator(sc, stream, MakeSetup(so, lidar), TestOptions(), 12.0);
  EXPECT_EQ(r.non_finite_outputs, 0);
  EXPECT_GT(r.outputs, 1000);
  EXPECT_LT(r.max_position_error, 0.005);
  const std::uint64_t n = imu_count / 200;
  EXPECT_EQ(Rejected(r, "imu", RejectReason::kNonFinite), 2 * n);
  EXPECT_EQ(Rejected(r, "imu", RejectReason::kAbsurdValue), n);
  EXPECT_EQ(Rejected(r, "imu", RejectReason::kStampBackwards), n);
  EXPECT_EQ(Rejected(r, "gnss_front", RejectReason::kNonFinite), 1u);
  EXPECT_EQ(Rejected(r, "gnss_front", RejectReason::kAbsurdValue), 1u);
  EXPECT_EQ(Rejected(r, "gnss_front", RejectReason::kNoFix), 1u);
  EXPECT_EQ(Rejected(r, "gnss_front", RejectReason::kStampBackwards), 1u);
  EXPECT_EQ(Rejected(r, "lidar_roof", RejectReason::kAbsurdValue), 1u);  // no point buffer
  EXPECT_EQ(Rejected(r, "no_such_sensor", RejectReason::kUnknownSensor), 1u);
  EXPECT_EQ(r.diagnostics.sensors.at("imu").accepted, static_cast<std::uint64_t>(imu_count));
}

// Seeded garbage: 5 % of the measurements corrupted in every way the checks know of, plus
// duplicates and stamps thrown around. The estimator must neither throw nor output NaN.
TEST(FactorGraphEstimator, SurvivesCorruptedStreams) {
  ScenarioOptions so;
  so.duration_s = 20.0;
  so.antennas.push_back({"gnss_rear", Vec3(-0.8, 0.0, 1.0)});
  const Scenario sc = MakeScenario(so);
  auto rng = MakeRng(7, "garbage");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double values[] = {nan, std::numeric_limits<double>::infinity(), -1e30, 1e30, 0.0};
  std::vector<Measurement> stream;
  for (const Measurement& m : sc.stream) {
    stream.push_back(m);
    if (Uniform01(rng) > 0.05) continue;
    Measurement bad = m;
    const double v = values[rng() % 5];
    const TimeNs jump = static_cast<TimeNs>((Uniform01(rng) - 0.5) * 4e9);
    std::visit(
        [&](auto& x) {
          using T = std::decay_t<decltype(x)>;
          if (rng() % 3 == 0) x.header.stamp_ns += jump;
          if constexpr (std::is_same_v<T, ImuSample>) {
            x.gyro(rng() % 3) = v;
            x.accel(rng() % 3) = rng() % 2 ? v : x.accel(0);
          } else if constexpr (std::is_same_v<T, GnssFix>) {
            switch (rng() % 4) {
              case 0:
                x.latitude_deg = v;
                break;
              case 1:
                x.altitude_m = v;
                break;
              case 2:
                x.covariance_enu(0, 1) = v;
                break;
              default:
                x.covariance_enu *= v;
            }
          }
        },
        bad);
    stream.push_back(bad);
  }
  const RunResult r =
      RunEstimator(sc, stream, MakeSetup(so), TestOptions(), 12.0);  // must not throw
  PrintRun("corrupted stream", r, 12.0);
  std::uint64_t rejected = 0;
  for (const auto& [id, c] : r.diagnostics.sensors) rejected += c.TotalRejected();
  EXPECT_GT(rejected, 50u);
  EXPECT_TRUE(r.diagnostics.initialized);
  EXPECT_EQ(r.non_finite_outputs, 0);
  EXPECT_GT(r.outputs, 1500);
  EXPECT_LT(r.max_position_error, 0.05);
}

TEST(FactorGraphEstimator, StateAtCoversTheWindowAndNothingElse) {
  ScenarioOptions so;
  so.duration_s = 15.0;
  const Scenario sc = MakeScenario(so);
  FactorGraphEstimator estimator(MakeSetup(so), TestOptions());
  EXPECT_FALSE(estimator.StateAt(0).has_value());
  for (const Measurement& m : sc.stream) estimator.Add(m);
  const TimeNs newest = FromSeconds(15.0);
  ASSERT_TRUE(estimator.StateAt(newest).has_value());
  EXPECT_FALSE(estimator.StateAt(newest + 1).has_value());
  EXPECT_FALSE(estimator.StateAt(FromSeconds(12.0)).has_value());  // left the window long ago
  // Inside the window (1 s) and the reorder latency before the newest sample: smoothed states,
  // also between IMU samples, with a covariance no smaller than at the newest stamp's anchor.
  for (const double t_s : {14.0, 14.123456, 14.5, 14.9, 14.995}) {
    const std::optional<StateEstimate> e = estimator.StateAt(FromSeconds(t_s));
    ASSERT_TRUE(e.has_value()) << t_s;
    const NavState truth = sc.Truth(FromSeconds(t_s));
    EXPECT_LT((e->state.p_world - truth.p_world).norm(), 1e-3) << t_s;
    EXPECT_LT(testing::RotationError(e->state, truth), 1e-4) << t_s;
    EXPECT_TRUE(e->covariance.allFinite());
    EXPECT_GT(e->covariance.diagonal().minCoeff(), 0.0);
    const GeodeticPoint g = LocalEnuFrame(testing::kTestOrigin).ToGeodetic(e->state.p_world);
    EXPECT_DOUBLE_EQ(e->latitude_deg, g.latitude_deg);
    EXPECT_DOUBLE_EQ(e->altitude_m, g.altitude_m);
  }
  ASSERT_TRUE(estimator.origin().has_value());
  EXPECT_DOUBLE_EQ(estimator.origin()->latitude_deg, testing::kTestOrigin.latitude_deg);
}

TEST(FactorGraphEstimator, UsesReceiverHeadingsAndGatesABadOne) {
  ScenarioOptions so;
  so.duration_s = 20.0;
  so.antennas.push_back({"gnss_rear", Vec3(-0.8, 0.0, 1.0)});
  Scenario sc = MakeScenario(so);
  // The receiver's heading of the baseline rear -> front at each fix stamp, 0.12 s late; the one
  // at 15 s is 0.2 rad off.
  std::vector<Measurement> stream;
  for (const Measurement& m : sc.stream) {
    stream.push_back(m);
    const auto* f = std::get_if<GnssFix>(&m);
    if (f == nullptr || f->header.sensor_id != "gnss_front") continue;
    const NavState truth = sc.Truth(f->header.stamp_ns);
    const Vec3 b = truth.q_world_imu * Vec3(1.25, 0.0, 0.0);
    DualAntennaHeading h;
    h.header = f->header;
    h.header.sensor_id = "gnss_heading";
    h.header.arrival_ns += 20 * kNsPerMillisecond;
    h.yaw_rad = std::atan2(b.y(), b.x()) + (h.header.stamp_ns == FromSeconds(15.0) ? 0.2 : 0.0);
    h.pitch_rad = std::atan2(-b.z(), b.head<2>().norm());
    h.yaw_sigma_rad = h.pitch_sigma_rad = 0.01;
    stream.push_back(h);
  }
  std::stable_sort(stream.begin(), stream.end(), [](const auto& a, const auto& b) {
    return HeaderOf(a).arrival_ns < HeaderOf(b).arrival_ns;
  });
  const std::string headings =
      "dual_antenna_headings:\n  - {id: gnss_heading, main: gnss_rear, aux: gnss_front}\n";
  const RunResult r = RunEstimator(sc, stream, MakeSetup(so, headings), TestOptions(), 12.0);
  PrintRun("receiver headings", r, 12.0);
  const auto& d = r.diagnostics.sensors;
  EXPECT_EQ(r.diagnostics.initialization, "static (dual antenna)");
  EXPECT_GT(d.at("gnss_heading").accepted, 150u);
  EXPECT_EQ(Rejected(r, "gnss_heading", RejectReason::kMahalanobisGate), 1u);
  EXPECT_EQ(d.at("gnss_heading").TotalRejected(), 1u);
  EXPECT_EQ(d.count("gnss_rear+gnss_front"), 0u);  // no heading of its own from the fixes
  EXPECT_EQ(d.at("gnss_front").TotalRejected(), 0u);
  EXPECT_GE(d.at("gnss_front").accepted + 2, d.at("gnss_front").received);  // 2 still held
  EXPECT_LT(r.max_position_error, 0.005);
  EXPECT_LT(r.max_rotation_error * kRadToDeg, 0.01);
}

}  // namespace
}  // namespace statebench::est
