// Ceres manifold for rotations stored as Eigen quaternions (x, y, z, w), perturbed on the right
// with the full rotation vector, the convention of the state covariance (core/state.hpp):
//   Plus(q, d)  = q * Exp(d)
//   Minus(y, x) = Log(x^-1 * y)
// (ceres::EigenQuaternionManifold perturbs on the left and with half the rotation vector.)
//
// At d = 0, with q = (v, w):
//   PlusJacobian  = 1/2 [w I + [v]x ; -v^T]          (4x3)
//   MinusJacobian = 2   [w I - [v]x , -v ]            (3x4)
// and MinusJacobian * PlusJacobian = I for a unit q. Analytic cost functions therefore return
// their Jacobian w.r.t. the rotation tangent J_tangent as the ambient Jacobian
//   J_ambient = J_tangent * MinusJacobian(q),
// so that the J_ambient * PlusJacobian Ceres forms is exactly J_tangent.
#pragma once

#include <ceres/manifold.h>

#include "core/eigen_types.hpp"

namespace statebench::est {

using Mat34 = Eigen::Matrix<double, 3, 4, Eigen::RowMajor>;
using Mat43 = Eigen::Matrix<double, 4, 3, Eigen::RowMajor>;

class RightQuaternionManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 4; }
  int TangentSize() const override { return 3; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

// PlusJacobian and MinusJacobian of RightQuaternionManifold at q (coefficients x, y, z, w).
Mat43 QuaternionPlusJacobian(const double* q_xyzw);
Mat34 QuaternionMinusJacobian(const double* q_xyzw);

}  // namespace statebench::est
