#include "estimator/gauss_markov_prior.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "core/random.hpp"

namespace statebench::est {
namespace {

// The information form against the dense covariance computation: Sigma' = A Sigma A^T + B Q B^T,
// mean' = A mean, for a random positive definite prior of 8 variables, two of them
// Gauss-Markov.
TEST(GaussMarkovPrior, MatchesTheDenseCovarianceStep) {
  auto rng = MakeRng(46, "gauss_markov_prior");
  NormalSampler normal;
  const int n = 8;
  Eigen::MatrixXd M(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) M(i, j) = normal(rng);
  }
  LinearSystem prior;
  prior.H = M * M.transpose() + 0.5 * Eigen::MatrixXd::Identity(n, n);
  prior.g = Eigen::VectorXd::NullaryExpr(n, [&] { return normal(rng); });
  const std::vector<GaussMarkovStep> steps{{5, 0.999, 0.02}, {7, 0.98, 0.3}};

  const Eigen::MatrixXd Sigma = prior.H.inverse();
  const Eigen::VectorXd mean = -Sigma * prior.g;
  Eigen::MatrixXd A = Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXd Q = Eigen::MatrixXd::Zero(n, n);
  for (const GaussMarkovStep& s : steps) {
    A(s.column, s.column) = s.rho;
    Q(s.column, s.column) = s.noise_variance;
  }
  const Eigen::MatrixXd Sigma_next = A * Sigma * A.transpose() + Q;
  const Eigen::VectorXd mean_next = A * mean;

  CarryGaussMarkovPrior(steps, &prior);
  const Eigen::MatrixXd Sigma_carried = prior.H.inverse();
  EXPECT_LT((Sigma_carried - Sigma_next).norm() / Sigma_next.norm(), 1e-10);
  EXPECT_LT((-Sigma_carried * prior.g - mean_next).norm() / mean_next.norm(), 1e-10);
}

// A Gauss-Markov variable the prior holds no information on yet leaves the prior unchanged
// (its noise adds to an infinite variance), even though H is singular.
TEST(GaussMarkovPrior, NoInformationStaysNone) {
  LinearSystem prior;
  prior.H = Eigen::MatrixXd::Zero(3, 3);
  prior.H.topLeftCorner<2, 2>() << 4.0, 1.0, 1.0, 3.0;
  prior.g = Eigen::Vector3d(0.5, -0.2, 0.0);
  const LinearSystem before = prior;
  CarryGaussMarkovPrior({{2, 0.99, 0.1}}, &prior);
  EXPECT_LT((prior.H - before.H).norm(), 1e-14);
  EXPECT_LT((prior.g - before.g).norm(), 1e-14);
}

}  // namespace
}  // namespace statebench::est
