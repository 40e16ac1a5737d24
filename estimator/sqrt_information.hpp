// Square-root information of a covariance: S with S^T S = Cov^-1, so that ||S r||^2 is the
// squared Mahalanobis distance of r. With Cov = L L^T (Cholesky), S = L^-1 (lower triangular).
#pragma once

#include <Eigen/Cholesky>
#include <string>

#include "core/error.hpp"

namespace statebench::est {

template <int N>
Eigen::Matrix<double, N, N> SqrtInformation(const Eigen::Matrix<double, N, N>& covariance,
                                            const std::string& what) {
  if (!covariance.allFinite()) throw InputError(what + ": covariance is not finite");
  const Eigen::LLT<Eigen::Matrix<double, N, N>> llt(covariance);
  if (llt.info() != Eigen::Success) {
    throw InputError(what + ": covariance is not positive definite");
  }
  const Eigen::Matrix<double, N, N> L = llt.matrixL();
  return L.template triangularView<Eigen::Lower>().solve(
      Eigen::Matrix<double, N, N>::Identity().eval());
}

}  // namespace statebench::est
