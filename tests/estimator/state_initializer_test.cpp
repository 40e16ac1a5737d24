#include "estimator/state_initializer.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstdio>

#include "estimator/measurement_gate.hpp"
#include "estimator_scenario.hpp"

namespace statebench::est {
namespace {

using testing::Antenna;
using testing::MakeScenario;
using testing::Scenario;
using testing::ScenarioOptions;
using testing::VehicleTrajectory;

TEST(VehicleTrajectory, DerivativesMatchFiniteDifferences) {
  const VehicleTrajectory traj(2.0);
  for (double t : {1.0, 2.5, 3.7, 11.0, 23.4}) {
    const double h = 1e-5;
    const Vec3 w_num =
        so3::Log<double>(traj.Orientation(t - h).conjugate() * traj.Orientation(t + h)) / (2 * h);
    EXPECT_LT((w_num - traj.Gyro(t)).norm(), 1e-7) << t;
    EXPECT_LT(((traj.Position(t + h) - traj.Position(t - h)) / (2 * h) - traj.Velocity(t)).norm(),
              1e-6);
    EXPECT_LT(
        ((traj.Velocity(t + h) - traj.Velocity(t - h)) / (2 * h) - traj.Acceleration(t)).norm(),
        1e-6);
    // Vehicle-like: the velocity lies along the body x axis.
    const Vec3 v_body = traj.Orientation(t).conjugate() * traj.Velocity(t);
    EXPECT_LT(v_body.tail<2>().norm(), 1e-9 + 1e-9 * v_body.norm());
  }
}

struct InitRun {
  std::optional<InitialState> init;
  TimeNs fed_until_ns = 0;
};

// Feeds the scenario in stamp order (as the reorder buffer releases it) until the initializer
// returns a state. Two antennas: their fixes of one stamp also give a heading.
InitRun Initialize(const Scenario& sc, const InitializationOptions& options) {
  std::vector<Measurement> stream = sc.stream;
  std::stable_sort(stream.begin(), stream.end(), [](const auto& a, const auto& b) {
    return HeaderOf(a).stamp_ns < HeaderOf(b).stamp_ns;
  });
  StateInitializer initializer(options, ImuNoise{}, Vec3::UnitX());
  const LocalEnuFrame frame(testing::kTestOrigin);
  std::map<TimeNs, std::map<std::string, GnssPositionEnu>> fixes;
  InitRun run;
  for (const Measurement& m : stream) {
    if (const auto* s = std::get_if<ImuSample>(&m)) {
      initializer.AddImu(*s);
      run.fed_until_ns = s->header.stamp_ns;
      if ((run.init = initializer.TryInitialize())) return run;
    } else if (const auto* f = std::get_if<GnssFix>(&m)) {
      const auto enu = GnssFixToEnu(*f, frame);
      const Antenna& a =
          *std::find_if(sc.options.antennas.begin(), sc.options.antennas.end(),
                        [&](const Antenna& x) { return x.id == f->header.sensor_id; });
      auto& group = fixes[f->header.stamp_ns];
      group[a.id] = *enu;
      if (group.size() == 2) {  // main = first antenna, as EstimatorSensorSetup pairs them
        const auto& [p0, p1] = std::pair(sc.options.antennas[0], sc.options.antennas[1]);
        initializer.AddHeading(HeadingFromFixes(group[p0.id], group[p1.id], "pair"),
                               p1.p_imu - p0.p_imu);
      }
      if (a.id == sc.options.antennas[0].id) initializer.AddPosition(*enu, a.p_imu);
    }
  }
  return run;
}

// Squared Mahalanobis distances of the rotation, position and velocity errors.
Vec3 BlockNees(const InitialState& init, const NavState& truth) {
  const NavState& x = init.state;
  const Vec3 e[3] = {so3::Log<double>(x.q_world_imu.conjugate() * truth.q_world_imu),
                     truth.p_world - x.p_world, truth.v_world - x.v_world};
  Vec3 out;
  for (int i = 0; i < 3; ++i) {
    const Mat3 P = init.covariance.block<3, 3>(3 * i, 3 * i);
    out(i) = e[i].dot(P.inverse() * e[i]);
  }
  return out;
}

void CheckInit(const Scenario& sc, const InitRun& run, const std::string& method,
               double max_rotation_error) {
  ASSERT_TRUE(run.init.has_value()) << method;
  const InitialState& init = *run.init;
  const NavState truth = sc.Truth(init.state.t_ns);
  const double rot = testing::RotationError(init.state, truth);
  const double pos = (init.state.p_world - truth.p_world).norm();
  const double vel = (init.state.v_world - truth.v_world).norm();
  const Vec3 nees = BlockNees(init, truth);
  std::printf(
      "%-24s at %.2f s: rotation error %.2e rad, position %.3f m, velocity %.3f m/s; "
      "NEES rot %.2f pos %.2f vel %.2f\n",
      init.method.c_str(), ToSeconds(init.state.t_ns), rot, pos, vel, nees(0), nees(1), nees(2));
  EXPECT_EQ(init.method, method);
  EXPECT_EQ(init.state.t_ns, run.fed_until_ns);
  EXPECT_LT(rot, max_rotation_error);
  EXPECT_LT(nees.maxCoeff(), 16.27);  // chi-square(3) at 0.999: the prior covers the error
  EXPECT_TRUE(init.covariance.allFinite());
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Mat15>(init.covariance).eigenvalues().minCoeff(), 0.0);
}

ScenarioOptions Base() {
  ScenarioOptions so;
  so.duration_s = 20.0;
  so.motion_start_s = 3.0;
  so.gyro_bias = Vec3(1e-3, -5e-4, 2e-3);
  so.accel_bias = Vec3(0.02, -0.01, 0.03);
  return so;
}

TEST(StateInitializer, StaticAlignmentThenCourseOnceMoving) {
  const Scenario sc = MakeScenario(Base());
  const InitRun run = Initialize(sc, InitializationOptions{});
  CheckInit(sc, run, "static (gnss course)", 0.02);
  // Gyro bias is the mean rate of the still period (noise-free: exact).
  EXPECT_LT((run.init->state.gyro_bias - sc.options.gyro_bias).norm(), 1e-9);
  EXPECT_GT(ToSeconds(run.init->state.t_ns), sc.options.motion_start_s);
}

TEST(StateInitializer, StaticAlignmentWithDualAntennaHeadingWhileStill) {
  ScenarioOptions so = Base();
  so.antennas.push_back({"gnss_rear", Vec3(-0.8, 0.0, 1.0)});
  const Scenario sc = MakeScenario(so);
  const InitRun run = Initialize(sc, InitializationOptions{});
  CheckInit(sc, run, "static (dual antenna)", 0.01);
  EXPECT_LT(ToSeconds(run.init->state.t_ns), so.motion_start_s);
  EXPECT_EQ(run.init->state.v_world, Vec3::Zero());
}

TEST(StateInitializer, MovingWithGnssCourse) {
  ScenarioOptions so = Base();
  so.start_s = 10.0;  // the data starts while driving
  so.duration_s = 15.0;
  const Scenario sc = MakeScenario(so);
  const InitRun run = Initialize(sc, InitializationOptions{});
  CheckInit(sc, run, "moving (gnss course)", 0.1);
}

TEST(StateInitializer, MovingWithDualAntennaHeading) {
  ScenarioOptions so = Base();
  so.start_s = 10.0;
  so.duration_s = 15.0;
  so.antennas.push_back({"gnss_rear", Vec3(-0.8, 0.0, 1.0)});
  const Scenario sc = MakeScenario(so);
  const InitRun run = Initialize(sc, InitializationOptions{});
  CheckInit(sc, run, "moving (dual antenna)", 0.1);
}

TEST(StateInitializer, NoisyStaticAlignmentIsCoveredByItsCovariance) {
  for (std::uint64_t seed : {1, 2, 3}) {
    ScenarioOptions so = Base();
    so.seed = seed;
    so.imu_noisy = true;
    so.gnss_sigma_h = so.reported_sigma_h = 0.05;
    so.gnss_sigma_v = so.reported_sigma_v = 0.08;
    const Scenario sc = MakeScenario(so);
    const InitRun run = Initialize(sc, InitializationOptions{});
    CheckInit(sc, run, "static (gnss course)", 0.1);
    const Vec3 bg_error = run.init->state.gyro_bias - sc.options.gyro_bias;
    const double sigma = std::sqrt(run.init->covariance(kGyroBiasIndex, kGyroBiasIndex));
    EXPECT_LT(bg_error.cwiseAbs().maxCoeff(), 4 * sigma);
  }
}

TEST(StateInitializer, StaticModeWaitsForAStillPeriod) {
  ScenarioOptions so = Base();
  so.start_s = 10.0;
  so.duration_s = 10.0;
  const Scenario sc = MakeScenario(so);
  InitializationOptions options;
  options.mode = InitializationMode::kStatic;
  EXPECT_FALSE(Initialize(sc, options).init.has_value());
  options.mode = InitializationMode::kMoving;  // and moving mode ignores one
  const InitRun run = Initialize(MakeScenario(Base()), options);
  ASSERT_TRUE(run.init.has_value());
  EXPECT_EQ(run.init->method, "moving (gnss course)");
}

}  // namespace
}  // namespace statebench::est
