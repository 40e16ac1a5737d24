#include "simulator/vehicle_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "core/state.hpp"

namespace statebench::sim {
namespace {

VehicleParams LoadVehicle(const std::string& name) {
  const char* root = std::getenv("STATEBENCH_SOURCE_DIR");
  return LoadVehicleParamsFile(std::filesystem::path(root ? root : ".") / "scenarios" / "vehicles" /
                               (name + ".yaml"));
}

VehicleModel FlatModel(const VehicleParams& params) {
  return VehicleModel(params, std::make_shared<const Terrain>(0.0));
}

VehicleState Rk4(const VehicleModel& model, const VehicleState& x, const VehicleCommand& cmd,
                 double h) {
  const VehicleState k1 = model.Derivative(x, cmd);
  const VehicleState k2 = model.Derivative(x.Plus(k1, h / 2), cmd);
  const VehicleState k3 = model.Derivative(x.Plus(k2, h / 2), cmd);
  const VehicleState k4 = model.Derivative(x.Plus(k3, h), cmd);
  return x.Plus(k1, h / 6).Plus(k2, h / 3).Plus(k3, h / 3).Plus(k4, h / 6);
}

// Algebraic (Kasa) circle fit: radius of the circle through the points.
double FitCircleRadius(const std::vector<Vec2>& pts) {
  Eigen::MatrixXd a(pts.size(), 3);
  Eigen::VectorXd b(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    a.row(i) << 2 * pts[i].x(), 2 * pts[i].y(), 1.0;
    b[i] = pts[i].squaredNorm();
  }
  const Eigen::Vector3d c = a.colPivHouseholderQr().solve(b);
  return std::sqrt(c[2] + c[0] * c[0] + c[1] * c[1]);
}

// Drives at constant steering and (held) speed; returns the radius of the circle described
// by the body point at x = point_x, fitted over the last 20 s of 40 s.
double SteadyCircleRadius(const VehicleModel& model, double steer_rad, double speed_mps,
                          double point_x) {
  VehicleState x;
  x.u_mps = speed_mps;
  x.steer_rad = steer_rad;
  std::vector<Vec2> pts;
  const double h = 1e-3;
  for (int k = 0; k < 40000; ++k) {
    // Speed hold: force = resistance + the drag of the lateral tyre forces, by feedback.
    const VehicleCommand cmd{steer_rad, model.Resistance(x.u_mps) + 2000.0 * (speed_mps - x.u_mps) +
                                            model.params().mass_kg * -x.yaw_rate_radps * x.w_mps};
    x = Rk4(model, x, cmd, h);
    if (k >= 20000 && k % 10 == 0) {
      pts.push_back(Vec2(x.x_m, x.y_m) + point_x * Vec2(std::cos(x.yaw_rad), std::sin(x.yaw_rad)));
    }
  }
  EXPECT_NEAR(x.u_mps, speed_mps, 0.01 * speed_mps);
  return FitCircleRadius(pts);
}

TEST(VehicleModel, KinematicCircleMatchesAckermannRadius) {
  // Acceptance: constant speed and steering on flat ground, kinematic regime:
  // the rear axle describes R = L / tan(delta).
  const VehicleParams params = LoadVehicle("quadricycle");
  const VehicleModel model = FlatModel(params);
  for (double steer : {0.1, 0.3, 0.5}) {
    const double radius = SteadyCircleRadius(model, steer, 0.8, -params.cg_to_rear_axle_m);
    const double expected = params.wheelbase_m() / std::tan(steer);
    char figure[32];
    std::snprintf(figure, sizeof(figure), "%.2e", radius / expected - 1);
    RecordProperty("relative_radius_error_steer_" + std::to_string(steer), figure);
    EXPECT_NEAR(radius / expected, 1.0, 0.01) << "steer " << steer;
    EXPECT_NEAR(radius / expected, 1.0, 1e-5) << "steer " << steer;  // in fact exact
  }
}

TEST(VehicleModel, FourWheelSteeringTurnsAboutTheCentre) {
  // Shuttle, rear = -front: the centre (reference point) describes R = L / (2 tan(delta)).
  const VehicleParams params = LoadVehicle("shuttle");
  const VehicleModel model = FlatModel(params);
  EXPECT_NEAR(model.ReferencePointX(), 0.0, 1e-12);
  const double steer = 0.3;
  const double radius = SteadyCircleRadius(model, steer, 0.8, 0.0);
  EXPECT_NEAR(radius / (params.wheelbase_m() / (2.0 * std::tan(steer))), 1.0, 1e-5);
  EXPECT_NEAR(model.KinematicCurvature(steer) * radius, 1.0, 1e-5);
  EXPECT_NEAR(model.SteerForCurvature(model.KinematicCurvature(0.2)), 0.2, 1e-12);
}

TEST(VehicleModel, DynamicRegimeUndersteersAsTheLinearTheoryPredicts) {
  // Steady state of the linear single-track model: delta = L / R + K a_y,
  // K = m (lr / Cf - lf / Cr) / L (understeer gradient, rad per m/s^2).
  const VehicleParams params = LoadVehicle("quadricycle");
  const VehicleModel model = FlatModel(params);
  const double steer = 0.02;
  const double speed = 10.0;
  const double radius = SteadyCircleRadius(model, steer, speed, 0.0);
  const double l = params.wheelbase_m();
  const double k_us = params.mass_kg *
                      (params.cg_to_rear_axle_m / params.cornering_stiffness_front_npr -
                       params.cg_to_front_axle_m / params.cornering_stiffness_rear_npr) /
                      l;
  ASSERT_GT(k_us, 0.0);
  const double predicted = (l + k_us * speed * speed) / steer;
  RecordProperty("radius_m", std::to_string(radius));
  RecordProperty("predicted_m", std::to_string(predicted));
  EXPECT_GT(radius, 1.05 * l / std::tan(steer));  // wider than the kinematic circle
  EXPECT_NEAR(radius / predicted, 1.0, 0.03);

  // Swapping the tyres makes it oversteer: a tighter circle than the kinematic one.
  VehicleParams swapped = params;
  std::swap(swapped.cornering_stiffness_front_npr, swapped.cornering_stiffness_rear_npr);
  const double radius_over = SteadyCircleRadius(FlatModel(swapped), steer, speed, 0.0);
  EXPECT_LT(radius_over, 0.95 * l / std::tan(steer));
}

TEST(VehicleModel, LateralAccelerationSaturatesAtTheFrictionLimit) {
  const VehicleParams params = LoadVehicle("quadricycle");
  const VehicleModel model = FlatModel(params);
  // Far too much steering for 12 m/s: the tyres slide, a_y stays below mu g.
  VehicleState x;
  x.u_mps = 12.0;
  const VehicleCommand cmd{0.3, 0.0};
  double max_ay = 0.0;
  for (int k = 0; k < 3000; ++k) {
    const VehicleState dx = model.Derivative(x, cmd);
    max_ay = std::max(max_ay, std::abs(dx.w_mps + x.yaw_rate_radps * x.u_mps));
    x = Rk4(model, x, cmd, 1e-3);
  }
  EXPECT_LE(max_ay, params.friction_coefficient * kGravity * 1.001);
  EXPECT_GT(max_ay, 0.8 * params.friction_coefficient * kGravity);
}

TEST(VehicleModel, StandstillIsWellPosed) {
  const VehicleModel model = FlatModel(LoadVehicle("quadricycle"));
  VehicleState x;
  // Steering while parked: the car turns its wheels but does not move.
  for (int k = 0; k < 2000; ++k) x = Rk4(model, x, VehicleCommand{0.4, 0.0}, 1e-3);
  EXPECT_NEAR(x.steer_rad, 0.4, 1e-3);
  EXPECT_EQ(x.u_mps, 0.0);
  EXPECT_EQ(x.x_m, 0.0);
  EXPECT_EQ(x.yaw_rad, 0.0);
  // Creeping backwards with left steering is kinematic: the car yaws to the right.
  x.u_mps = -0.2;
  const VehicleState dx = model.Derivative(x, VehicleCommand{0.4, 0.0});
  EXPECT_TRUE(std::isfinite(dx.yaw_rate_radps));
  EXPECT_LT(dx.yaw_rate_radps, 0.0);
}

TEST(VehicleModel, SteeringActuatorIsRateLimitedLag) {
  const VehicleParams params = LoadVehicle("quadricycle");
  const VehicleModel model = FlatModel(params);
  VehicleState x;
  // Large step: the rate saturates at the limit.
  const VehicleState dx = model.Derivative(x, VehicleCommand{0.5, 0.0});
  EXPECT_NEAR(dx.steer_rad, params.max_steering_rate_radps, 1e-6 * params.max_steering_rate_radps);
  // Small step: a first-order lag with the configured time constant.
  const VehicleState small = model.Derivative(x, VehicleCommand{1e-4, 0.0});
  EXPECT_NEAR(small.steer_rad, 1e-4 / params.steering_time_constant_s, 1e-8);
  // The force lag.
  const VehicleState force = model.Derivative(x, VehicleCommand{0.0, 100.0});
  EXPECT_NEAR(force.force_n, 100.0 / params.drive_time_constant_s, 1e-9);
}

TEST(VehicleModel, RollsDownhill) {
  // 5 % grade rising to the east; a car facing east with no force accelerates westward with
  // the horizontal part of gravity along the slope, g * 0.05 / (1 + 0.05^2).
  const VehicleParams params = LoadVehicle("quadricycle");
  std::vector<Vec3> plane;
  for (double x = -200; x <= 200; x += 10) {
    for (double y = -200; y <= 200; y += 50) plane.emplace_back(x, y, 0.05 * x);
  }
  const VehicleModel model(params, std::make_shared<const Terrain>(Terrain::Fit(plane)));
  VehicleState x;
  const VehicleState dx = model.Derivative(x, VehicleCommand{});
  EXPECT_NEAR(dx.u_mps, -kGravity * 0.05 / (1 + 0.05 * 0.05), 1e-4);
  EXPECT_NEAR(model.SlopeGravity(x).y(), 0.0, 1e-6);
  // Facing north, the slope is a cross slope.
  x.yaw_rad = M_PI / 2;
  EXPECT_NEAR(model.SlopeGravity(x).y(), kGravity * 0.05 / (1 + 0.05 * 0.05), 1e-4);
}

TEST(VehicleModel, AckermannWheelAngles) {
  const VehicleParams params = LoadVehicle("quadricycle");
  const VehicleModel model = FlatModel(params);
  const auto straight = model.WheelAngles(0.0);
  for (double a : straight) EXPECT_EQ(a, 0.0);
  const auto turn = model.WheelAngles(0.3);
  // Left turn: inner (left) front wheel steers more; rear wheels straight; Ackermann
  // condition cot(outer) - cot(inner) = track / wheelbase.
  EXPECT_GT(turn[0], 0.3);
  EXPECT_LT(turn[1], 0.3);
  EXPECT_NEAR(1 / std::tan(turn[1]) - 1 / std::tan(turn[0]),
              params.track_width_m / params.wheelbase_m(), 1e-12);
  EXPECT_NEAR(turn[2], 0.0, 1e-15);
  EXPECT_NEAR(turn[3], 0.0, 1e-15);
  // Shuttle: rear wheels counter-steer.
  const VehicleModel shuttle = FlatModel(LoadVehicle("shuttle"));
  const auto four = shuttle.WheelAngles(0.3);
  EXPECT_GT(four[0], 0.0);
  EXPECT_LT(four[2], 0.0);
  EXPECT_NEAR(four[0], -four[2], 1e-12);
}

TEST(VehicleModel, BlendIsSmoothAndSpansTheConfiguredSpeeds) {
  const VehicleModel model = FlatModel(LoadVehicle("quadricycle"));
  EXPECT_EQ(model.BlendWeight(0.0), 0.0);
  EXPECT_EQ(model.BlendWeight(-2.0), 0.0);
  EXPECT_EQ(model.BlendWeight(1.0), 0.0);
  EXPECT_EQ(model.BlendWeight(3.0), 1.0);
  EXPECT_NEAR(model.BlendWeight(2.0), 0.5, 1e-12);
  // Slope at the ends is zero (C1 and better): accelerations stay continuous.
  const double e = 1e-6;
  EXPECT_NEAR((model.BlendWeight(1.0 + e) - model.BlendWeight(1.0)) / e, 0.0, 1e-6);
  EXPECT_NEAR((model.BlendWeight(3.0) - model.BlendWeight(3.0 - e)) / e, 0.0, 1e-6);
}

}  // namespace
}  // namespace statebench::sim
