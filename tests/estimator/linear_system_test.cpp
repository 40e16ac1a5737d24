#include "estimator/linear_system.hpp"

#include <ceres/sized_cost_function.h>
#include <gtest/gtest.h>

#include <memory>

#include "core/random.hpp"
#include "core/so3.hpp"
#include "estimator/gnss_position_factor.hpp"
#include "estimator/so3_manifold.hpp"

namespace statebench::est {
namespace {

// r = A [x1; x2] - b with x1 in R^2, x2 in R^3.
class LinearFactor final : public ceres::SizedCostFunction<4, 2, 3> {
 public:
  LinearFactor(const Eigen::Matrix<double, 4, 5>& A, const Eigen::Vector4d& b) : A_(A), b_(b) {}
  bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
    Eigen::Matrix<double, 5, 1> v;
    v << x[0][0], x[0][1], x[1][0], x[1][1], x[1][2];
    Eigen::Map<Eigen::Vector4d>{residuals} = A_ * v - b_;
    if (jacobians != nullptr) {
      using RowMajor = Eigen::Matrix<double, 4, Eigen::Dynamic, Eigen::RowMajor>;
      if (jacobians[0]) Eigen::Map<RowMajor>(jacobians[0], 4, 2) = A_.leftCols<2>();
      if (jacobians[1]) Eigen::Map<RowMajor>(jacobians[1], 4, 3) = A_.rightCols<3>();
    }
    return true;
  }

 private:
  Eigen::Matrix<double, 4, 5> A_;
  Eigen::Vector4d b_;
};

Eigen::MatrixXd RandomMatrix(int rows, int cols, std::mt19937_64& rng) {
  NormalSampler normal;
  Eigen::MatrixXd m(rows, cols);
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) m(i, j) = normal(rng);
  }
  return m;
}

TEST(Linearize, AccumulatesNormalEquationsOfLinearFactors) {
  auto rng = MakeRng(51, "linearize");
  const Eigen::Matrix<double, 4, 5> A1 = RandomMatrix(4, 5, rng), A2 = RandomMatrix(4, 5, rng);
  const Eigen::Vector4d b1 = RandomMatrix(4, 1, rng), b2 = RandomMatrix(4, 1, rng);
  LinearFactor f1(A1, b1), f2(A2, b2);
  std::vector<double> x1 = {0.3, -0.2}, x2 = {1.0, 0.5, -0.7};
  BlockLayout layout;
  layout.Add(x2.data(), 3, nullptr);  // order differs from the factor's on purpose
  layout.Add(x1.data(), 2, nullptr);
  const FactorRecord r1{&f1, nullptr, {x1.data(), x2.data()}};
  const FactorRecord r2{&f2, nullptr, {x1.data(), x2.data()}};
  LinearSystem system;
  ASSERT_TRUE(Linearize({&r1, &r2}, layout, &system));

  // Expected in the layout order (x2, x1).
  Eigen::Matrix<double, 5, 5> P = Eigen::Matrix<double, 5, 5>::Zero();
  P.block<3, 3>(0, 2).setIdentity();
  P.block<2, 2>(3, 0).setIdentity();
  Eigen::Matrix<double, 5, 1> v;
  v << 0.3, -0.2, 1.0, 0.5, -0.7;
  const Eigen::MatrixXd H = P * (A1.transpose() * A1 + A2.transpose() * A2) * P.transpose();
  const Eigen::VectorXd g = P * (A1.transpose() * (A1 * v - b1) + A2.transpose() * (A2 * v - b2));
  EXPECT_LT((system.H - H).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((system.g - g).cwiseAbs().maxCoeff(), 1e-12);

  // A robust loss weights residual and Jacobian by sqrt(rho'(|r|^2)).
  ceres::HuberLoss huber(0.5);
  const FactorRecord robust{&f1, &huber, {x1.data(), x2.data()}};
  LinearSystem weighted;
  ASSERT_TRUE(Linearize({&robust}, layout, &weighted));
  const double s = (A1 * v - b1).squaredNorm();
  double rho[3];
  huber.Evaluate(s, rho);
  EXPECT_LT(rho[1], 1.0);
  EXPECT_LT((weighted.H - rho[1] * P * A1.transpose() * A1 * P.transpose()).cwiseAbs().maxCoeff(),
            1e-12);
}

TEST(Linearize, UsesTheTangentSpaceOfManifoldBlocks) {
  const RightQuaternionManifold manifold;
  const Vec3 lever(1.0, 0.5, 1.5);
  Mat3 cov = Mat3::Identity() * 0.01;
  const GnssPositionFactor f(Vec3(1, 2, 3), cov, lever);
  Quat q = so3::FromRollPitchYaw(0.1, 0.2, 0.3);
  Vec3 p(0.5, 1.0, 2.0);
  BlockLayout layout;
  layout.Add(q.coeffs().data(), 4, &manifold);
  layout.Add(p.data(), 3, nullptr);
  EXPECT_EQ(layout.dimension(), 6);
  const FactorRecord r{&f, nullptr, {q.coeffs().data(), p.data()}};
  LinearSystem system;
  ASSERT_TRUE(Linearize({&r}, layout, &system));
  Eigen::Matrix<double, 3, 6> J;
  J << -10.0 * q.toRotationMatrix() * so3::Hat<double>(lever), 10.0 * Mat3::Identity();
  EXPECT_LT((system.H - J.transpose() * J).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(SchurComplement, GivesTheMarginalInformationAndTheSameSolution) {
  auto rng = MakeRng(52, "schur");
  const Eigen::MatrixXd A = RandomMatrix(12, 8, rng);
  LinearSystem system;
  system.H = A.transpose() * A;
  system.g = RandomMatrix(8, 1, rng);
  const LinearSystem kept = SchurComplement(system, 3);
  ASSERT_EQ(kept.H.rows(), 5);
  const Eigen::MatrixXd covariance = system.H.inverse();
  EXPECT_LT((kept.H.inverse() - covariance.bottomRightCorner(5, 5)).cwiseAbs().maxCoeff(), 1e-9);
  const Eigen::VectorXd x_full = system.H.ldlt().solve(-system.g);
  const Eigen::VectorXd x_kept = kept.H.ldlt().solve(-kept.g);
  EXPECT_LT((x_full.tail(5) - x_kept).cwiseAbs().maxCoeff(), 1e-9);
}

// A marginalised variable no factor observes (zero row and column) carries no information:
// the result is the Schur complement without it (pseudo-inverse path).
TEST(SchurComplement, IgnoresUnobservedMarginalisedDirections) {
  auto rng = MakeRng(53, "schur_singular");
  Eigen::MatrixXd A = RandomMatrix(12, 8, rng);
  A.col(1).setZero();
  LinearSystem system;
  system.H = A.transpose() * A;
  system.g = A.transpose() * RandomMatrix(12, 1, rng);
  const LinearSystem kept = SchurComplement(system, 3);

  std::vector<int> keep_idx = {0, 2, 3, 4, 5, 6, 7};
  LinearSystem reduced;
  reduced.H.resize(7, 7);
  reduced.g.resize(7);
  for (int i = 0; i < 7; ++i) {
    reduced.g(i) = system.g(keep_idx[i]);
    for (int j = 0; j < 7; ++j) reduced.H(i, j) = system.H(keep_idx[i], keep_idx[j]);
  }
  const LinearSystem expected = SchurComplement(reduced, 2);
  EXPECT_LT((kept.H - expected.H).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((kept.g - expected.g).cwiseAbs().maxCoeff(), 1e-9);
}

}  // namespace
}  // namespace statebench::est
