// Test helper: a cost function's Jacobians against central differences taken on the manifold.
//
// For every parameter block the analytic tangent Jacobian J_ambient * PlusJacobian(x) is
// compared with (r(x [+] h e_k) - r(x [+] -h e_k)) / 2h, where [+] is the block's manifold Plus
// (x * Exp(d) for RightQuaternionManifold) or plain addition for Euclidean blocks.
#pragma once

#include <ceres/cost_function.h>
#include <ceres/manifold.h>

#include <Eigen/Core>
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

namespace statebench::est::testing {

using DynamicMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct JacobianCheck {
  // Per block: max |J - J_num| divided by max(|J_num|_max, 1e-12 * max over blocks).
  std::vector<double> block_relative_error;
  std::vector<double> block_max_entry;
  double worst_relative_error = 0.0;
};

inline JacobianCheck CheckJacobians(const ceres::CostFunction& cost,
                                    std::vector<std::vector<double>> params,
                                    const std::vector<const ceres::Manifold*>& manifolds,
                                    double step = 1e-6, const std::string& label = "") {
  const int num_residuals = cost.num_residuals();
  const std::vector<int32_t>& sizes = cost.parameter_block_sizes();
  const auto evaluate = [&](const std::vector<std::vector<double>>& p, double* r, double** J) {
    std::vector<const double*> ptrs;
    for (const auto& b : p) ptrs.push_back(b.data());
    return cost.Evaluate(ptrs.data(), r, J);
  };

  std::vector<DynamicMatrix> ambient;
  std::vector<double*> jac_ptrs;
  for (int32_t s : sizes) ambient.emplace_back(num_residuals, s);
  for (auto& m : ambient) jac_ptrs.push_back(m.data());
  Eigen::VectorXd r0(num_residuals);
  evaluate(params, r0.data(), jac_ptrs.data());

  JacobianCheck out;
  std::vector<DynamicMatrix> analytic, numeric;
  double overall_max = 0.0;
  for (std::size_t b = 0; b < sizes.size(); ++b) {
    const ceres::Manifold* m = manifolds[b];
    const int tangent = m ? m->TangentSize() : sizes[b];
    DynamicMatrix plus_jacobian = DynamicMatrix::Identity(sizes[b], tangent);
    if (m) m->PlusJacobian(params[b].data(), plus_jacobian.data());
    analytic.push_back(ambient[b] * plus_jacobian);

    DynamicMatrix J_num(num_residuals, tangent);
    for (int k = 0; k < tangent; ++k) {
      Eigen::VectorXd r_plus(num_residuals), r_minus(num_residuals);
      for (double sign : {1.0, -1.0}) {
        auto p = params;
        Eigen::VectorXd delta = Eigen::VectorXd::Zero(tangent);
        delta(k) = sign * step;
        if (m) {
          m->Plus(params[b].data(), delta.data(), p[b].data());
        } else {
          for (int i = 0; i < tangent; ++i) p[b][i] += delta(i);
        }
        evaluate(p, sign > 0 ? r_plus.data() : r_minus.data(), nullptr);
      }
      J_num.col(k) = (r_plus - r_minus) / (2.0 * step);
    }
    overall_max = std::max(overall_max, J_num.cwiseAbs().maxCoeff());
    numeric.push_back(J_num);
  }
  for (std::size_t b = 0; b < sizes.size(); ++b) {
    const double scale = std::max(numeric[b].cwiseAbs().maxCoeff(), 1e-12 * overall_max);
    const double err = (analytic[b] - numeric[b]).cwiseAbs().maxCoeff() / scale;
    out.block_relative_error.push_back(err);
    out.block_max_entry.push_back(numeric[b].cwiseAbs().maxCoeff());
    out.worst_relative_error = std::max(out.worst_relative_error, err);
    if (!label.empty()) {
      std::printf("%s block %zu: relative Jacobian error %.2e (max entry %.2e)\n", label.c_str(), b,
                  err, numeric[b].cwiseAbs().maxCoeff());
    }
  }
  return out;
}

}  // namespace statebench::est::testing
