// The route centre line the vehicle drives: SUMO's lane polyline smoothed into a curve with
// continuous heading, curvature and curvature rate, parameterised by arc length.
//
// Construction. The raw polyline (x, y; z is ignored, the terrain gives height) is cleaned of
// duplicate points and sampled every sample_spacing_m in its own arc length u (SUMO's s). A
// uniform quintic B-spline r(u) (knots every ~knot_spacing_m of u) is fitted to the samples by
// penalised least squares,
//   min sum_i w_i |r(u_i) - p_i|^2 + lambda int |r''(u)|^2 du,
// with lambda = rho l^4 (rho samples per metre, l = smoothing_length_m: the fit follows a
// straight lane exactly and averages small kinks over ~l). Where the curvature exceeds
// max_curvature_1pm (a corner sharper than the vehicle can drive), the samples around it get
// a ~zero weight and the fit is repeated, the gap widening by gap_growth_m per side each time
// until the curvature fits: across the gap the spline is the smoothest bridge between the lanes
// on either side, which cuts the corner the way a driver does, and only there. Because the
// data are parameterised by raw
// arc length, r(u) is the smoothed counterpart of the raw point at SUMO's s = u; the smoothed
// arc length S(u) = int_0^u |r'| is tabulated, so SUMO positions map to path positions.
//
// Beyond either end the path continues as a straight line along the end tangent.
#pragma once

#include <array>
#include <vector>

#include "core/eigen_types.hpp"
#include "simulator/quintic_bspline.hpp"

namespace statebench::sim {

struct PathOptions {
  double knot_spacing_m = 1.0;
  double sample_spacing_m = 0.25;
  double smoothing_length_m = 1.0;
  double max_curvature_1pm = 0.25;  // ~ 0.7 of the vehicle's tightest kinematic curvature
  double gap_growth_m = 0.5;
  int max_iterations = 100;
};

struct PathPoint {
  Vec2 position = Vec2::Zero();      // ENU x, y (m)
  double heading_rad = 0.0;          // of the tangent, from east, counter-clockwise
  double curvature_1pm = 0.0;        // positive to the left
  double curvature_rate_1pm2 = 0.0;  // d curvature / ds
};

struct PathProjection {
  double s_m = 0.0;        // arc length of the closest point (may be < 0 or > length)
  double lateral_m = 0.0;  // signed distance of the point from the path, left positive
  double raw_s_m = 0.0;    // SUMO (raw polyline) arc length of the closest point, in
                           // [0, raw length]; a cheap warm start for the next projection
};

// SUMO arc length mapped to the path: s and its first two derivatives in s_raw.
struct RawToPath {
  double s_m = 0.0;
  double ds_draw = 1.0;
  double d2s_draw2 = 0.0;  // 1/m
};

class Path {
 public:
  // Throws InputError when the polyline has fewer than two distinct points.
  static Path Build(const std::vector<Vec3>& polyline, const PathOptions& options = {});

  double length_m() const { return arc_.back(); }
  double raw_length_m() const { return raw_length_m_; }
  const std::vector<Vec2>& raw_polyline() const { return raw_; }

  PathPoint At(double s_m) const;
  Vec2 Position(double s_m) const;
  // Point of the path that corresponds to SUMO arc length s_raw (cheaper than Position).
  Vec2 PositionAtRaw(double s_raw_m) const;
  // Closest point, by Newton iterations started at a previous answer (see HintAt); converges
  // to the local minimum of the distance near the hint.
  PathProjection Project(const Vec2& p, const PathProjection& hint) const;
  // Closest point over the whole path (scans the path: for initialisation only).
  PathProjection Project(const Vec2& p) const;
  // A projection hint at path arc length s.
  PathProjection HintAt(double s_m) const;
  RawToPath FromRaw(double s_raw_m) const;

 private:
  struct Derivatives {
    Vec2 r, d1, d2, d3;  // r(u) and its derivatives in u
  };
  Derivatives Eval(double u, int order) const;
  double SpeedAt(double u) const { return Eval(u, 1).d1.norm(); }
  double ArcAt(double u) const;    // S(u) for u in [0, raw length]
  double ParamAt(double s) const;  // inverse of ArcAt for s in [0, length]
  PathProjection ProjectFrom(const Vec2& p, double u) const;

  std::vector<Vec2> raw_;
  double raw_length_m_ = 0.0;
  double knot_m_ = 1.0;  // knot spacing h in u
  int segments_ = 0;
  // Segment k in the power basis: r(u) = sum_i poly_[k][i] tau^i, tau = u / h - k.
  std::vector<std::array<Vec2, kQuinticOrder>> poly_;
  double table_step_m_ = 0.125;  // u step of the arc-length table
  std::vector<double> arc_;      // S at u = k * table_step_m_
};

}  // namespace statebench::sim
