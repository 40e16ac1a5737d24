#include "core/strapdown.hpp"

#include "core/state.hpp"

namespace statebench {
namespace {

struct Rate {
  Vec4 dq;  // quaternion coefficients (x, y, z, w), Eigen's storage order
  Vec3 dv;
  Vec3 dp;
};

struct Point {
  Vec4 q;
  Vec3 v;
  Vec3 p;
};

Rate Derivative(const Point& x, const InertialRates& r) {
  const Quat q(x.q);  // Quat(const Vec4&) reads (x, y, z, w)
  const Quat omega(0.0, r.omega_body.x(), r.omega_body.y(), r.omega_body.z());
  Rate d;
  d.dq = 0.5 * (q * omega).coeffs();
  d.dv = q.normalized() * r.specific_force_body + kGravityWorld;
  d.dp = x.v;
  return d;
}

Point Advance(const Point& x, const Rate& d, double h) {
  return {x.q + h * d.dq, x.v + h * d.dv, x.p + h * d.dp};
}

InertialRates Combine(const InertialRates* r, const double w[4]) {
  InertialRates out;
  for (int i = 0; i < 4; ++i) {
    out.omega_body += w[i] * r[i].omega_body;
    out.specific_force_body += w[i] * r[i].specific_force_body;
  }
  return out;
}

}  // namespace

StrapdownState StrapdownStep(const StrapdownState& x, const InertialRates& start,
                             const InertialRates& middle, const InertialRates& end, double h_s) {
  const Point x0{x.q_world_body.coeffs(), x.v_world, x.p_world};
  const Rate k1 = Derivative(x0, start);
  const Rate k2 = Derivative(Advance(x0, k1, 0.5 * h_s), middle);
  const Rate k3 = Derivative(Advance(x0, k2, 0.5 * h_s), middle);
  const Rate k4 = Derivative(Advance(x0, k3, h_s), end);
  const double w = h_s / 6.0;
  StrapdownState out;
  out.q_world_body =
      Quat(Vec4(x0.q + w * (k1.dq + 2.0 * k2.dq + 2.0 * k3.dq + k4.dq))).normalized();
  out.v_world = x0.v + w * (k1.dv + 2.0 * k2.dv + 2.0 * k3.dv + k4.dv);
  out.p_world = x0.p + w * (k1.dp + 2.0 * k2.dp + 2.0 * k3.dp + k4.dp);
  return out;
}

std::vector<StrapdownState> IntegrateStrapdown(const StrapdownState& initial,
                                               const std::vector<InertialRates>& samples,
                                               double dt_s) {
  std::vector<StrapdownState> out{initial};
  const std::size_t n = samples.size();
  out.reserve(n);
  // Lagrange weights for the value at the middle of an interval from 4 neighbouring samples:
  // centred (k-1, k, k+1, k+2), first interval (0..3), last interval (n-4..n-1).
  constexpr double kCentred[4] = {-1.0 / 16, 9.0 / 16, 9.0 / 16, -1.0 / 16};
  constexpr double kFirst[4] = {5.0 / 16, 15.0 / 16, -5.0 / 16, 1.0 / 16};
  constexpr double kLast[4] = {1.0 / 16, -5.0 / 16, 15.0 / 16, 5.0 / 16};
  for (std::size_t k = 0; k + 1 < n; ++k) {
    InertialRates middle;
    if (n < 4) {
      middle.omega_body = 0.5 * (samples[k].omega_body + samples[k + 1].omega_body);
      middle.specific_force_body =
          0.5 * (samples[k].specific_force_body + samples[k + 1].specific_force_body);
    } else if (k == 0) {
      middle = Combine(&samples[0], kFirst);
    } else if (k + 2 >= n) {
      middle = Combine(&samples[n - 4], kLast);
    } else {
      middle = Combine(&samples[k - 1], kCentred);
    }
    out.push_back(StrapdownStep(out.back(), samples[k], middle, samples[k + 1], dt_s));
  }
  return out;
}

}  // namespace statebench
