#include "simulator/vehicle_simulation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numbers>

#include "core/so3.hpp"
#include "core/state.hpp"
#include "core/strapdown.hpp"
#include "simulator/synthetic_route.hpp"

namespace statebench::sim {
namespace {

VehicleParams LoadVehicle(const std::string& name) {
  const char* root = std::getenv("STATEBENCH_SOURCE_DIR");
  return LoadVehicleParamsFile(std::filesystem::path(root ? root : ".") / "scenarios" / "vehicles" /
                               (name + ".yaml"));
}

std::string Figure(double v) {
  char s[32];
  std::snprintf(s, sizeof(s), "%.3g", v);
  return s;
}

double DistanceToPolyline(const std::vector<Vec3>& line, const Vec2& p) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < line.size(); ++i) {
    const Vec2 a = line[i - 1].head<2>();
    const Vec2 ab = line[i].head<2>() - a;
    const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (a + t * ab - p).norm());
  }
  return best;
}

// The synthetic urban drive (right-angle corners, two stops, hill with grade and cross slope)
// with the vehicle re-driving it at 1 kHz; statistics gathered on the way.
struct Drive {
  SyntheticRoute route;
  std::vector<TruthSample> truth;  // every ms up to keep_truth_s
  double lateral_rms_m = 0.0;      // from the smoothed path the tracker follows
  double lateral_max_m = 0.0;
  double raw_rms_m = 0.0;  // from SUMO's raw lane polyline
  double max_lateral_accel_mps2 = 0.0;
  double max_yaw_rate_times_speed = 0.0;
  double max_yaw_accel_radps2 = 0.0;
  double min_speed_mps = 0.0;
  double distance_m = 0.0;
  std::vector<double> speed_mps;  // every 0.1 s
};

Drive RunDrive(const std::string& vehicle, double duration_s, double keep_truth_s,
               const SyntheticRouteOptions& options) {
  Drive d;
  const VehicleParams params = LoadVehicle(vehicle);
  SyntheticRouteOptions ro = options;
  ro.duration_s = duration_s + 1.0;
  d.route = MakeSyntheticRoute(ro);
  auto terrain = std::make_shared<const Terrain>(Terrain::FitPolylines(d.route.network));
  auto path = std::make_shared<const Path>(Path::Build(d.route.polyline, PathOptionsFor(params)));
  VehicleSimulation sim(params, path, terrain);
  sim.Reset(ro.start_s_m, 0.0);
  const int steps = static_cast<int>(std::lround(duration_s * 1000));
  double lat2 = 0.0;
  double raw2 = 0.0;
  int raw_count = 0;
  d.min_speed_mps = std::numeric_limits<double>::infinity();
  for (int k = 0;; ++k) {
    const TruthSample truth = sim.Truth();
    if (k <= std::lround(keep_truth_s * 1000)) d.truth.push_back(truth);
    const double lat = sim.projection().lateral_m;
    lat2 += lat * lat;
    d.lateral_max_m = std::max(d.lateral_max_m, std::abs(lat));
    const Vec3 a_body = truth.body.T_world_frame.rotation().conjugate() * truth.body.a_world;
    const Vec3 v_body = truth.body.VelocityInFrame();
    d.max_lateral_accel_mps2 = std::max(d.max_lateral_accel_mps2, std::abs(a_body.y()));
    d.max_yaw_rate_times_speed =
        std::max(d.max_yaw_rate_times_speed, std::abs(truth.body.omega_frame.z() * v_body.x()));
    d.max_yaw_accel_radps2 = std::max(d.max_yaw_accel_radps2, std::abs(truth.body.alpha_frame.z()));
    d.min_speed_mps = std::min(d.min_speed_mps, sim.state().u_mps);
    if (k % 100 == 0) {
      d.speed_mps.push_back(sim.state().u_mps);
      const Vec2 p = truth.body.T_world_frame.translation().head<2>();
      raw2 += std::pow(DistanceToPolyline(d.route.polyline, p), 2);
      ++raw_count;
    }
    if (k == steps) break;
    const ReferenceSample ref = SampleProfile(d.route.profile, k * 1e-3);
    sim.Step(ref.s_m, ref.v_mps, ref.a_mps2);
  }
  d.lateral_rms_m = std::sqrt(lat2 / (steps + 1));
  d.raw_rms_m = std::sqrt(raw2 / raw_count);
  d.distance_m = sim.Truth().distance_m;
  return d;
}

struct PoseError {
  double position_m;
  double rotation_deg;
};

// Strapdown integration of the truth's angular rate and specific force of `frame` (every ms)
// from its initial pose and velocity; error against the truth pose at the end.
PoseError StrapdownError(const std::vector<FrameKinematics>& frame) {
  std::vector<InertialRates> rates;
  for (const FrameKinematics& f : frame) rates.push_back({f.omega_frame, f.SpecificForce()});
  const StrapdownState initial{frame.front().T_world_frame.rotation(),
                               frame.front().T_world_frame.translation(), frame.front().v_world};
  const StrapdownState end = IntegrateStrapdown(initial, rates, 1e-3).back();
  const SE3& truth = frame.back().T_world_frame;
  return {
      (end.p_world - truth.translation()).norm(),
      so3::Log(truth.rotation().conjugate() * end.q_world_body).norm() * 180.0 / std::numbers::pi};
}

class VehicleSimulationTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    quadricycle_ = new Drive(RunDrive("quadricycle", 120.0, 60.0, SyntheticRouteOptions{}));
  }
  static void TearDownTestSuite() {
    delete quadricycle_;
    quadricycle_ = nullptr;
  }
  static Drive* quadricycle_;
};

Drive* VehicleSimulationTest::quadricycle_ = nullptr;

TEST_F(VehicleSimulationTest, StrapdownOfTruthRatesReproducesTruthPose) {
  // Acceptance: 60 s of urban driving (corners, stops, hill), rates sampled at 1 kHz.
  const Drive& d = *quadricycle_;
  ASSERT_EQ(d.truth.size(), 60001u);
  ASSERT_GT(d.truth.back().distance_m, 200.0);
  std::vector<FrameKinematics> body;
  std::vector<FrameKinematics> imu;
  // An IMU off the CG and rotated: exercises the lever-arm terms (angular acceleration).
  const SE3 T_body_imu(so3::FromRollPitchYaw(0.03, -0.05, 1.6), Vec3(0.8, 0.3, 1.2));
  for (const TruthSample& t : d.truth) {
    body.push_back(t.body);
    imu.push_back(t.body.AtMount(T_body_imu));
  }
  const PoseError body_error = StrapdownError(body);
  const PoseError imu_error = StrapdownError(imu);
  RecordProperty("body_position_error_m", Figure(body_error.position_m));
  RecordProperty("body_rotation_error_deg", Figure(body_error.rotation_deg));
  RecordProperty("imu_position_error_m", Figure(imu_error.position_m));
  EXPECT_LT(body_error.position_m, 0.01);
  EXPECT_LT(body_error.rotation_deg, 0.01);
  EXPECT_LT(imu_error.position_m, 0.01);
  EXPECT_LT(imu_error.rotation_deg, 0.01);
}

TEST_F(VehicleSimulationTest, FollowsTheRouteWithinTyreLimits) {
  const Drive& d = *quadricycle_;
  const VehicleParams params = LoadVehicle("quadricycle");
  const double mu_g = params.friction_coefficient * kGravity;
  RecordProperty("lateral_rms_m", Figure(d.lateral_rms_m));
  RecordProperty("lateral_max_m", Figure(d.lateral_max_m));
  RecordProperty("raw_polyline_rms_m", Figure(d.raw_rms_m));
  RecordProperty("max_lateral_accel_mps2", Figure(d.max_lateral_accel_mps2));
  RecordProperty("max_yaw_accel_radps2", Figure(d.max_yaw_accel_radps2));
  RecordProperty("distance_m", Figure(d.distance_m));
  EXPECT_GT(d.distance_m, 500.0);  // all six corners and both stops
  EXPECT_LT(d.lateral_rms_m, 0.3);
  EXPECT_LT(d.lateral_max_m, 1.0);
  // The raw polyline has sharp right-angle corners that the path cuts by ~2.5 m (a real SUMO
  // route turns on curved junction lanes); on the straights the car sits on the lane.
  EXPECT_LT(d.raw_rms_m, 0.6);
  EXPECT_LT(d.max_lateral_accel_mps2, mu_g);
  EXPECT_LT(d.max_yaw_rate_times_speed, mu_g);
  // No spikes at the polyline corners: SUMO's own heading would jump by 90 deg there.
  EXPECT_LT(d.max_yaw_accel_radps2, 2.0);
  // It stops (twice) and never reverses.
  EXPECT_GT(d.min_speed_mps, -1e-3);
  int stopped = 0;
  for (std::size_t i = 1; i < d.speed_mps.size(); ++i) {
    stopped += d.speed_mps[i] < 0.01 && d.speed_mps[i - 1] >= 0.01;
  }
  EXPECT_EQ(stopped, 2);
}

TEST(VehicleSimulation, ShuttleFollowsTheRoute) {
  SyntheticRouteOptions options;
  options.cruise_speed_mps = 6.5;
  options.corner_speed_mps = 3.0;
  const Drive d = RunDrive("shuttle", 100.0, 0.0, options);
  const VehicleParams params = LoadVehicle("shuttle");
  RecordProperty("lateral_rms_m", Figure(d.lateral_rms_m));
  RecordProperty("distance_m", Figure(d.distance_m));
  EXPECT_GT(d.distance_m, 350.0);
  EXPECT_LT(d.lateral_rms_m, 0.3);
  EXPECT_LT(d.max_lateral_accel_mps2, params.friction_coefficient * kGravity);
  EXPECT_LT(d.max_yaw_accel_radps2, 2.0);
  EXPECT_GT(d.min_speed_mps, -1e-3);
}

TEST(VehicleSimulation, SameInputsSameBits) {
  const Drive a = RunDrive("quadricycle", 8.0, 8.0, SyntheticRouteOptions{});
  const Drive b = RunDrive("quadricycle", 8.0, 8.0, SyntheticRouteOptions{});
  ASSERT_EQ(a.truth.size(), b.truth.size());
  for (std::size_t i = 0; i < a.truth.size(); ++i) {
    const TruthSample& x = a.truth[i];
    const TruthSample& y = b.truth[i];
    const Vec3 px = x.body.T_world_frame.translation();
    const Vec3 py = y.body.T_world_frame.translation();
    ASSERT_EQ(std::memcmp(px.data(), py.data(), sizeof(double) * 3), 0) << i;
    ASSERT_EQ(std::memcmp(x.body.T_world_frame.rotation().coeffs().data(),
                          y.body.T_world_frame.rotation().coeffs().data(), sizeof(double) * 4),
              0);
    ASSERT_EQ(std::memcmp(x.body.a_world.data(), y.body.a_world.data(), sizeof(double) * 3), 0);
    ASSERT_EQ(std::memcmp(x.body.alpha_frame.data(), y.body.alpha_frame.data(), sizeof(double) * 3),
              0);
    ASSERT_EQ(
        std::memcmp(x.wheel_omega_radps.data(), y.wheel_omega_radps.data(), sizeof(double) * 4), 0);
  }
}

TEST(VehicleSimulation, TruthAtRestAndOnAStraight) {
  const VehicleParams params = LoadVehicle("quadricycle");
  std::vector<Vec3> line{Vec3(0, 0, 0), Vec3(200, 0, 0)};
  auto path = std::make_shared<const Path>(Path::Build(line, PathOptionsFor(params)));
  VehicleSimulation sim(params, path, std::make_shared<const Terrain>(5.0));
  sim.Reset(10.0, 0.0, 3 * kNsPerSecond);
  TruthSample t = sim.Truth();
  EXPECT_EQ(t.t_ns, 3 * kNsPerSecond);
  EXPECT_NEAR((t.body.T_world_frame.translation() - Vec3(10, 0, 5)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((t.body.SpecificForce() - Vec3(0, 0, kGravity)).norm(), 0.0, 1e-9);
  for (double w : t.wheel_omega_radps) EXPECT_EQ(w, 0.0);
  // Drive 10 m/s along the straight for 5 s: every wheel rolls at v / r.
  sim.Reset(10.0, 10.0, 3 * kNsPerSecond);
  for (int k = 0; k < 5000; ++k) sim.Step(10.0 + 10.0 * k * 1e-3, 10.0, 0.0);
  t = sim.Truth();
  EXPECT_EQ(t.t_ns, 8 * kNsPerSecond);
  EXPECT_NEAR(t.body.v_world.x(), 10.0, 0.01);
  EXPECT_NEAR(std::abs(sim.projection().lateral_m), 0.0, 1e-6);
  for (double w : t.wheel_omega_radps)
    EXPECT_NEAR(w, t.body.v_world.x() / params.wheel_radius_m, 1e-6);
  EXPECT_NEAR(t.distance_m, sim.projection().s_m - 10.0, 1e-6);
  EXPECT_NEAR(t.distance_m, 50.0, 0.05);
  EXPECT_NEAR(sim.projection().s_m, sim.reference().s_m, 0.05);
}

}  // namespace
}  // namespace statebench::sim
