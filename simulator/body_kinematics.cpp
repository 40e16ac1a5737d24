#include "simulator/body_kinematics.hpp"

#include <cmath>

namespace statebench::sim {
namespace {

// A unit vector n = m / |m| and its first two time derivatives from those of m.
struct UnitVector {
  Vec3 n, dn, ddn;
};

UnitVector Normalize(const Vec3& m, const Vec3& dm, const Vec3& ddm) {
  const double l = m.norm();
  UnitVector out;
  out.n = m / l;
  const double dl = out.n.dot(dm);
  out.dn = (dm - out.n * dl) / l;
  const double ddl = out.dn.dot(dm) + out.n.dot(ddm);
  out.ddn = (ddm - 2.0 * out.dn * dl - out.n * ddl) / l;
  return out;
}

}  // namespace

FrameKinematics BodyKinematics(const Terrain& terrain, const VehicleState& x,
                               const VehicleState& x_dot) {
  const TerrainSample ground = terrain.Evaluate(x.x_m, x.y_m, 3);
  const Vec2& g = ground.gradient;
  const Mat2& hess = ground.hessian;
  const double c = std::cos(x.yaw_rad);
  const double s = std::sin(x.yaw_rad);
  const double r = x.yaw_rate_radps;
  const double dr = x_dot.yaw_rate_radps;

  // Horizontal velocity and acceleration: d/dt of R(yaw) (u, w).
  const Vec2 v(x_dot.x_m, x_dot.y_m);
  const double a_u = x_dot.u_mps - r * x.w_mps;
  const double a_w = x_dot.w_mps + r * x.u_mps;
  const Vec2 a(c * a_u - s * a_w, s * a_u + c * a_w);

  // Gradient rates: d/dt grad h = H v, d2/dt2 grad h = H' v + H a.
  const Vec4& t3 = ground.third;  // h_xxx, h_xxy, h_xyy, h_yyy
  Mat2 hess_dot;
  hess_dot << t3[0] * v.x() + t3[1] * v.y(), t3[1] * v.x() + t3[2] * v.y(),
      t3[1] * v.x() + t3[2] * v.y(), t3[2] * v.x() + t3[3] * v.y();
  const Vec2 dg = hess * v;
  const Vec2 ddg = hess_dot * v + hess * a;

  FrameKinematics out;
  const Vec3 p(x.x_m, x.y_m, ground.h);
  out.v_world = Vec3(v.x(), v.y(), g.dot(v));
  out.a_world = Vec3(a.x(), a.y(), g.dot(a) + v.dot(hess * v));

  // Body z: terrain normal.
  const UnitVector z = Normalize(Vec3(-g.x(), -g.y(), 1.0), Vec3(-dg.x(), -dg.y(), 0.0),
                                 Vec3(-ddg.x(), -ddg.y(), 0.0));
  // Body x: road tangent above the heading e = (c, s); e' = r e_perp, e_perp' = -r e.
  const Vec2 e(c, s);
  const Vec2 e_perp(-s, c);
  const double grade = g.dot(e);
  const double d_grade = dg.dot(e) + r * g.dot(e_perp);
  const double dd_grade =
      ddg.dot(e) + 2.0 * r * dg.dot(e_perp) - r * r * grade + dr * g.dot(e_perp);
  const UnitVector xb = Normalize(Vec3(c, s, grade), Vec3(-s * r, c * r, d_grade),
                                  Vec3(-c * r * r - s * dr, -s * r * r + c * dr, dd_grade));
  // Body y = z x x.
  const Vec3 y = z.n.cross(xb.n);
  const Vec3 dy = z.dn.cross(xb.n) + z.n.cross(xb.dn);

  Mat3 rot;
  rot.col(0) = xb.n;
  rot.col(1) = y;
  rot.col(2) = z.n;
  out.T_world_frame = SE3(rot, p);
  out.omega_frame = Vec3(-y.dot(z.dn), xb.n.dot(z.dn), y.dot(xb.dn));
  out.alpha_frame = Vec3(-(dy.dot(z.dn) + y.dot(z.ddn)), xb.dn.dot(z.dn) + xb.n.dot(z.ddn),
                         dy.dot(xb.dn) + y.dot(xb.ddn));
  return out;
}

}  // namespace statebench::sim
