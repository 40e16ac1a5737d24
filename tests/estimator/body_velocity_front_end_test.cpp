// The body-velocity front end: a generic velocity odometry (wheel odometry of a robot) as a
// velocity factor, each component weighted by its own variance. Also the proof that a new
// measurement kind needs no change to the factor graph's orchestrator: this front end is
// registered only in front_end_set.cpp.
#include <gtest/gtest.h>

#include "core/random.hpp"
#include "estimator/factor_graph_estimator.hpp"
#include "estimator_scenario.hpp"

namespace statebench::est {
namespace {

using testing::DriftingImuRtkOptions;
using testing::MakeScenario;
using testing::MakeSetup;
using testing::Scenario;
using testing::ScenarioOptions;

const std::string kOdometrySetup =
    "  - {type: body_velocity, id: wheel_odom, rate_hz: 10, latency_s: 0.05,"
    " T_body_sensor: {translation: [-0.5, 0.0, 0.2]}}\n";
const Vec3 kP_imu_odom(-0.5, 0.0, 0.2);

// Velocity of the odometry frame (the IMU axes, at kP_imu_odom) from the truth, with white noise
// of sigma_mps on x and y; z reported unmeasured (variance 1e6) and off by 5 m/s.
std::vector<Measurement> WithOdometry(const Scenario& sc, double sigma_mps, std::uint64_t seed) {
  std::vector<Measurement> stream = sc.stream;
  auto rng = MakeRng(seed, "wheel_odom");
  NormalSampler normal;
  for (int k = 0; k <= static_cast<int>(sc.options.duration_s * 10.0); ++k) {
    const TimeNs t = FromSeconds(sc.options.start_s + 0.1 * k);
    const NavState x = sc.Truth(t);
    BodyVelocity v;
    v.header.sensor_id = "wheel_odom";
    v.header.stamp_ns = t;
    v.header.arrival_ns = t + 50 * kNsPerMillisecond;
    const Vec3 omega = sc.trajectory.Gyro(ToSeconds(t));
    v.velocity = x.q_world_imu.conjugate() * x.v_world + omega.cross(kP_imu_odom);
    v.velocity += Vec3(sigma_mps * normal(rng), sigma_mps * normal(rng), 5.0);
    v.covariance = Mat6::Identity() * 1e6;
    v.covariance(0, 0) = v.covariance(1, 1) = sigma_mps * sigma_mps;
    stream.push_back(v);
  }
  std::stable_sort(stream.begin(), stream.end(), [](const Measurement& a, const Measurement& b) {
    return HeaderOf(a).arrival_ns < HeaderOf(b).arrival_ns;
  });
  return stream;
}

struct Drift {
  double max_position_error_m = 0.0;  // horizontal
  double max_vertical_error_m = 0.0;
  EstimatorDiagnostics diagnostics;
};

Drift RunOutage(const Scenario& sc, const std::vector<Measurement>& stream,
                const EstimatorSensorSetup& setup) {
  FactorGraphOptions o;
  o.origin = testing::kTestOrigin;
  o.gnss_calibration = {0.0, 0.0, 0.0};  // exact mounts and clocks in this simulation
  FactorGraphEstimator estimator(setup, o);
  Drift d;
  for (const Measurement& m : stream) {
    estimator.Add(m);
    const TimeNs t = HeaderOf(m).stamp_ns;
    if (!std::holds_alternative<ImuSample>(m) || ToSeconds(t) < sc.options.outage_begin_s) continue;
    if (const auto e = estimator.StateAt(t)) {
      EXPECT_TRUE(e->state.p_world.allFinite());
      const Vec3 err = e->state.p_world - sc.Truth(t).p_world;
      d.max_position_error_m = std::max(d.max_position_error_m, err.head<2>().norm());
      d.max_vertical_error_m = std::max(d.max_vertical_error_m, std::abs(err.z()));
    }
  }
  d.diagnostics = estimator.diagnostics();
  return d;
}

ScenarioOptions OutageScenario() {
  ScenarioOptions so = DriftingImuRtkOptions(45.0);
  so.outage_begin_s = 15.0;  // GNSS silent to the end
  so.seed = 7;
  return so;
}

TEST(BodyVelocityFrontEnd, OdometryBoundsTheDriftOfAGnssOutage) {
  const ScenarioOptions so = OutageScenario();
  const Scenario sc = MakeScenario(so);
  const Drift imu_only = RunOutage(sc, sc.stream, MakeSetup(so));
  const Drift with_odometry =
      RunOutage(sc, WithOdometry(sc, 0.05, 3), MakeSetup(so, kOdometrySetup));
  std::printf(
      "30 s GNSS outage: max horizontal / vertical error IMU only %.3f / %.3f m, with odometry "
      "%.3f / %.3f m\n",
      imu_only.max_position_error_m, imu_only.max_vertical_error_m,
      with_odometry.max_position_error_m, with_odometry.max_vertical_error_m);
  for (const Drift* d : {&imu_only, &with_odometry}) {
    const EstimatorDiagnostics& g = d->diagnostics;
    std::printf("  started %s at %.2f s, into ENU at %.2f s, GNSS covariance scale %.2f\n",
                g.initialization.c_str(), ToSeconds(g.initialized_at_ns),
                g.enu_switches.empty() ? -1.0 : ToSeconds(g.enu_switches.front().at_ns),
                g.sensors.at("gnss_front").covariance_scale.value_or(1.0));
  }
  const SensorCounters& c = with_odometry.diagnostics.sensors.at("wheel_odom");
  EXPECT_GT(c.events.at("body_velocity_factors"), 400u);
  // Every sample became a factor but those the initialiser took before the first state (a setup
  // with odometry may start in a local frame from them).
  std::uint64_t before_start = 0;
  for (const Measurement& m : WithOdometry(sc, 0.05, 3)) {
    before_start += std::holds_alternative<BodyVelocity>(m) &&
                    HeaderOf(m).stamp_ns < with_odometry.diagnostics.initialized_at_ns;
  }
  EXPECT_EQ(c.events.at("body_velocity_factors") + before_start, c.accepted);
  // Measured (seed 7): 0.787 m with the IMU and the non-holonomic constraint, 0.326 m with the
  // odometry; what remains is the heading drift, which a velocity cannot observe.
  EXPECT_GT(imu_only.max_position_error_m, 0.5);  // the outage is long enough to drift
  EXPECT_LT(with_odometry.max_position_error_m, 0.6 * imu_only.max_position_error_m);
  EXPECT_LT(with_odometry.max_vertical_error_m, 0.1);
}

TEST(BodyVelocityFrontEnd, UnknownOrBadOdometryIsRejectedAndCounted) {
  ScenarioOptions so = OutageScenario();
  so.duration_s = 12.0;
  const Scenario sc = MakeScenario(so);
  std::vector<Measurement> stream = WithOdometry(sc, 0.05, 3);
  int edited = 0;
  for (Measurement& m : stream) {
    auto* v = std::get_if<BodyVelocity>(&m);
    if (v == nullptr || ToSeconds(v->header.stamp_ns) < 6.0 || edited >= 3) continue;
    if (edited == 0) v->velocity.x() = std::nan("");
    if (edited == 1) v->covariance(1, 1) = -1.0;
    if (edited == 2) v->velocity.x() = 500.0;
    ++edited;
  }
  // Not in the setup: unknown.
  const Drift unknown = RunOutage(sc, stream, MakeSetup(so));
  EXPECT_EQ(unknown.diagnostics.sensors.at("wheel_odom").rejected.at(RejectReason::kUnknownSensor),
            121u);
  const Drift known = RunOutage(sc, stream, MakeSetup(so, kOdometrySetup));
  const SensorCounters& c = known.diagnostics.sensors.at("wheel_odom");
  EXPECT_EQ(c.rejected.at(RejectReason::kNonFinite), 1u);
  EXPECT_EQ(c.rejected.at(RejectReason::kInvalidCovariance), 1u);
  EXPECT_EQ(c.rejected.at(RejectReason::kAbsurdValue), 1u);
  EXPECT_GT(c.accepted, 60u);
}

}  // namespace
}  // namespace statebench::est
