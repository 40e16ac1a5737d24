#include "simulator/vehicle_model.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/state.hpp"

namespace statebench::sim {
namespace {

// C2 step: 0 below 0, 1 above 1, 6t^5 - 15t^4 + 10t^3 between.
double SmootherStep(double t) {
  if (t <= 0.0) return 0.0;
  if (t >= 1.0) return 1.0;
  return t * t * t * (t * (6.0 * t - 15.0) + 10.0);
}

double Sec2(double a) {
  const double c = std::cos(a);
  return 1.0 / (c * c);
}

// Saturating lateral tyre force of one axle.
double TyreForce(double stiffness, double slip_rad, double mu_fz) {
  return mu_fz * std::tanh(stiffness * slip_rad / mu_fz);
}

}  // namespace

VehicleModel::VehicleModel(VehicleParams params, std::shared_ptr<const Terrain> terrain,
                           VehicleModelOptions options)
    : params_(std::move(params)), terrain_(std::move(terrain)), options_(options) {
  if (!terrain_) throw InputError("vehicle model: no terrain");
  if (!(options_.kinematic_below_mps >= 0.0) ||
      !(options_.dynamic_above_mps > options_.kinematic_below_mps) ||
      !(options_.relaxation_time_s > 0.0)) {
    throw InputError(
        "vehicle model options: need 0 <= kinematic_below < dynamic_above and a "
        "positive relaxation time");
  }
  // With tan(dr) ~ -k tan(df): tan(delta(x)) = tan(df) ((lr - k lf) + (1 + k) x) / L = 0 at x_c.
  const double k = params_.rear_steering_ratio;
  reference_x_m_ = -(params_.cg_to_rear_axle_m - k * params_.cg_to_front_axle_m) / (1.0 + k);
  const double half = 0.5 * params_.track_width_m;
  const double lf = params_.cg_to_front_axle_m;
  const double lr = params_.cg_to_rear_axle_m;
  wheel_contacts_ = {Vec3(lf, half, 0.0), Vec3(lf, -half, 0.0), Vec3(-lr, half, 0.0),
                     Vec3(-lr, -half, 0.0)};
}

double VehicleModel::KinematicCurvature(double front_steer_rad) const {
  return (std::tan(front_steer_rad) - std::tan(RearSteer(front_steer_rad))) / params_.wheelbase_m();
}

double VehicleModel::SteerForCurvature(double kappa_1pm) const {
  // Solve tan(d) + tan(k d) = L kappa by Newton; the left side is odd and increasing.
  const double k = params_.rear_steering_ratio;
  const double target = params_.wheelbase_m() * kappa_1pm;
  double d = std::atan(target / (1.0 + k));
  for (int i = 0; i < 20; ++i) {
    const double f = std::tan(d) + std::tan(k * d) - target;
    const double step = f / (Sec2(d) + k * Sec2(k * d));
    d = std::clamp(d - step, -1.5, 1.5);
    if (std::abs(step) < 1e-14) break;
  }
  return d;
}

std::array<double, 4> VehicleModel::WheelAngles(double front_steer_rad) const {
  // Instantaneous centre of rotation of the steering geometry: tan(delta(x, y)) =
  // (A + B x) / (1 - B y) for a wheel at (x, y) (no singularity when driving straight).
  const double tf = std::tan(front_steer_rad);
  const double tr = std::tan(RearSteer(front_steer_rad));
  const double l = params_.wheelbase_m();
  const double a = (params_.cg_to_rear_axle_m * tf + params_.cg_to_front_axle_m * tr) / l;
  const double b = (tf - tr) / l;
  std::array<double, 4> out{};
  for (int i = 0; i < 4; ++i) {
    const Vec3& c = wheel_contacts_[i];
    out[i] = std::atan2(a + b * c.x(), 1.0 - b * c.y());
  }
  return out;
}

double VehicleModel::BlendWeight(double u_mps) const {
  return SmootherStep((u_mps - options_.kinematic_below_mps) /
                      (options_.dynamic_above_mps - options_.kinematic_below_mps));
}

double VehicleModel::Resistance(double u_mps) const {
  // Rolling resistance fades in over 0.1 m/s so that it is smooth through standstill.
  const double rolling =
      params_.rolling_resistance_coefficient * params_.mass_kg * kGravity * std::tanh(u_mps / 0.1);
  const double aero =
      0.5 * options_.air_density_kgpm3 * params_.drag_area_m2 * u_mps * std::abs(u_mps);
  return rolling + aero;
}

Vec2 VehicleModel::SlopeGravity(double yaw_rad, const Vec2& terrain_gradient) {
  // Gravity projected on the road plane, horizontal part: -g grad h / (1 + |grad h|^2).
  const Vec2& g = terrain_gradient;
  const Vec2 a_world = -kGravity * g / (1.0 + g.squaredNorm());
  const double c = std::cos(yaw_rad);
  const double s = std::sin(yaw_rad);
  return Vec2(c * a_world.x() + s * a_world.y(), -s * a_world.x() + c * a_world.y());
}

Vec2 VehicleModel::SlopeGravity(const VehicleState& x) const {
  return SlopeGravity(x.yaw_rad, terrain_->Evaluate(x.x_m, x.y_m, 1).gradient);
}

VehicleState VehicleModel::Derivative(const VehicleState& x, const VehicleCommand& command) const {
  return Derivative(x, command, terrain_->Evaluate(x.x_m, x.y_m, 1).gradient);
}

VehicleState VehicleModel::Derivative(const VehicleState& x, const VehicleCommand& command,
                                      const Vec2& terrain_gradient) const {
  const VehicleParams& p = params_;
  const double m = p.mass_kg;
  const double lf = p.cg_to_front_axle_m;
  const double lr = p.cg_to_rear_axle_m;
  const double l = lf + lr;
  const double c = std::cos(x.yaw_rad);
  const double s = std::sin(x.yaw_rad);
  const double u = x.u_mps;
  const double w = x.w_mps;
  const double r = x.yaw_rate_radps;

  VehicleState dx;
  dx.x_m = c * u - s * w;
  dx.y_m = s * u + c * w;
  dx.yaw_rad = r;
  const double rate_max = p.max_steering_rate_radps;
  dx.steer_rad = rate_max * std::tanh((command.steer_rad - x.steer_rad) /
                                      (p.steering_time_constant_s * rate_max));
  dx.force_n = (command.force_n - x.force_n) / p.drive_time_constant_s;

  const Vec2 slope = SlopeGravity(x.yaw_rad, terrain_gradient);
  const double g_u = slope.x();
  const double g_w = slope.y();
  const double resistance = Resistance(u);

  // Kinematic branch.
  const double df = x.steer_rad;
  const double dr = RearSteer(df);
  const double ddf = dx.steer_rad;
  const double ddr = RearSteer(ddf);
  const double a_coef = (lr * std::tan(df) + lf * std::tan(dr)) / l;
  const double b_coef = (std::tan(df) - std::tan(dr)) / l;
  const double a_rate = (lr * Sec2(df) * ddf + lf * Sec2(dr) * ddr) / l;
  const double b_rate = (Sec2(df) * ddf - Sec2(dr) * ddr) / l;
  const double tau = options_.relaxation_time_s;
  const double du_kin = (x.force_n - resistance) / m + g_u + r * w;
  const double dw_kin = du_kin * a_coef + u * a_rate + (u * a_coef - w) / tau;
  const double dr_kin = du_kin * b_coef + u * b_rate + (u * b_coef - r) / tau;

  const double lambda = BlendWeight(u);
  if (lambda == 0.0) {
    dx.u_mps = du_kin;
    dx.w_mps = dw_kin;
    dx.yaw_rate_radps = dr_kin;
  } else {
    // Dynamic branch.
    const double fz_min = 0.05 * m * kGravity;
    const double transfer = x.force_n * p.cg_height_m / l;
    const double fz_f = std::max(fz_min, m * kGravity * lr / l - transfer);
    const double fz_r = std::max(fz_min, m * kGravity * lf / l + transfer);
    const double mu = p.friction_coefficient;
    const double alpha_f = df - std::atan2(w + lf * r, u);
    const double alpha_r = dr - std::atan2(w - lr * r, u);
    const double fy_f = TyreForce(p.cornering_stiffness_front_npr, alpha_f, mu * fz_f);
    const double fy_r = TyreForce(p.cornering_stiffness_rear_npr, alpha_r, mu * fz_r);
    const double static_front = lr / l;
    const double front_share =
        x.force_n >= 0.0 ? (p.drive == DriveLayout::kFront ? 1.0 : static_front) : static_front;
    const double fx_f = front_share * x.force_n;
    const double fx_r = x.force_n - fx_f;
    const double cf = std::cos(df), sf = std::sin(df);
    const double cr = std::cos(dr), sr = std::sin(dr);
    const double front_y = fx_f * sf + fy_f * cf;
    const double rear_y = fx_r * sr + fy_r * cr;
    const double force_u = fx_f * cf - fy_f * sf + fx_r * cr - fy_r * sr - resistance + m * g_u;
    const double force_w = front_y + rear_y + m * g_w;
    const double du_dyn = force_u / m + r * w;
    const double dw_dyn = force_w / m - r * u;
    const double dr_dyn = (lf * front_y - lr * rear_y) / p.yaw_inertia_kgm2;
    dx.u_mps = lambda * du_dyn + (1.0 - lambda) * du_kin;
    dx.w_mps = lambda * dw_dyn + (1.0 - lambda) * dw_kin;
    dx.yaw_rate_radps = lambda * dr_dyn + (1.0 - lambda) * dr_kin;
  }

  const double v_up = terrain_gradient.dot(Vec2(dx.x_m, dx.y_m));
  dx.distance_m = std::sqrt(u * u + w * w + v_up * v_up);
  return dx;
}

}  // namespace statebench::sim
