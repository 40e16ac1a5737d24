// Smooth road elevation field z = h(x, y) in the local ENU world frame.
//
//   h(x, y) = h0 + sum_ij c_ij N((x - x0) / d - i) N((y - y0) / d - j)
//
// a tensor-product uniform quintic B-spline (N, see quintic_bspline.hpp) on a grid of spacing d,
// plus the mean road height h0. It is C4: height, gradient, Hessian and third derivatives are
// continuous and analytic, which is what the vehicle truth needs (velocity uses the gradient,
// acceleration and angular rate the Hessian, angular acceleration the third derivatives). It
// reproduces planes exactly, and an evaluation touches 6 x 6 coefficients whatever the size of
// the network. Coefficients outside the fitted grid are zero, so far from the roads the field
// returns smoothly to h0.
//
// The coefficients are a penalised least-squares fit (P-spline, Eilers and Marx 1996) to the 3D
// points of the road network (SUMO lane shapes): data term plus a penalty on second differences
// of neighbouring coefficients (zero for planes) and a tiny ridge that fixes coefficients no
// point sees.
#pragma once

#include <vector>

#include "core/eigen_types.hpp"

namespace statebench::sim {

struct TerrainOptions {
  double grid_spacing_m = 20.0;     // d, knot spacing of the B-spline in x and y
  double curvature_penalty = 1e-2;  // second differences of coefficients, relative to the
                                    // mean diagonal of the data normal matrix
  double ridge = 1e-8;              // coefficient decay, same scale
  double polyline_step_m = 2.0;     // resampling step of FitPolylines
};

// h and its partial derivatives at one point; fields beyond the requested order are zero.
struct TerrainSample {
  double h = 0.0;
  Vec2 gradient = Vec2::Zero();  // (h_x, h_y)
  Mat2 hessian = Mat2::Zero();   // [[h_xx, h_xy], [h_xy, h_yy]]
  Vec4 third = Vec4::Zero();     // (h_xxx, h_xxy, h_xyy, h_yyy)
};

class Terrain {
 public:
  // Flat road at height z_m.
  explicit Terrain(double z_m = 0.0) : base_m_(z_m) {}

  // Fits the field to road points (x, y, z in ENU metres). When every z is the same the
  // terrain is exactly flat. Throws InputError when `points` is empty or not finite.
  static Terrain Fit(const std::vector<Vec3>& points, const TerrainOptions& options = {});
  // Same, from lane centre lines resampled every options.polyline_step_m.
  static Terrain FitPolylines(const std::vector<std::vector<Vec3>>& polylines,
                              const TerrainOptions& options = {});

  double Height(double x_m, double y_m) const { return Evaluate(x_m, y_m, 0).h; }
  // order 0: h; 1: + gradient; 2: + Hessian; 3: + third derivatives.
  TerrainSample Evaluate(double x_m, double y_m, int order) const;
  // Upward unit normal (-h_x, -h_y, 1) / |.|.
  Vec3 Normal(double x_m, double y_m) const;

  bool IsFlat() const { return coefficients_.empty(); }
  double base_height_m() const { return base_m_; }
  int coefficient_count() const { return static_cast<int>(coefficients_.size()); }

 private:
  double base_m_ = 0.0;
  double spacing_m_ = 1.0;
  double x0_m_ = 0.0;  // segment (k, l) covers [x0 + k d, x0 + (k+1) d) x [y0 + l d, ...)
  double y0_m_ = 0.0;
  int nx_ = 0;  // coefficients per row; segment k uses coefficients k .. k + 5
  int ny_ = 0;
  std::vector<double> coefficients_;  // nx * ny, index j * nx + i; empty when flat
};

}  // namespace statebench::sim
