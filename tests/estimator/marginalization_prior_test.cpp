#include "estimator/marginalization_prior.hpp"

#include <gtest/gtest.h>

#include <memory>

#include "core/error.hpp"
#include "core/random.hpp"
#include "core/so3.hpp"
#include "estimator/so3_manifold.hpp"
#include "jacobian_check.hpp"

namespace statebench::est {
namespace {

NavState MarginalizedTestState() {
  NavState s;
  s.q_world_imu = so3::FromRollPitchYaw(0.1, -0.05, 2.0);
  s.p_world = Vec3(10, 20, 1);
  s.v_world = Vec3(3, -1, 0.1);
  s.gyro_bias = Vec3(1e-3, -2e-3, 5e-4);
  s.accel_bias = Vec3(0.05, 0.02, -0.03);
  return s;
}

std::vector<std::vector<double>> MarginalizedBlocks(const NavState& s) {
  const auto p = StateParameters::FromNavState(s);
  auto v = [](const auto& a) { return std::vector<double>(a.begin(), a.end()); };
  return {v(p.q_world_imu), v(p.p_world), v(p.v_world), v(p.bias)};
}

Vec15 Evaluate(const ceres::CostFunction& f, const NavState& s) {
  const auto blocks = MarginalizedBlocks(s);
  const double* ptrs[] = {blocks[0].data(), blocks[1].data(), blocks[2].data(), blocks[3].data()};
  Vec15 r;
  f.Evaluate(ptrs, r.data(), nullptr);
  return r;
}

Mat15 RandomInformation(std::mt19937_64& rng, int rank) {
  NormalSampler normal;
  Eigen::Matrix<double, Eigen::Dynamic, 15> A(rank, 15);
  for (int i = 0; i < rank; ++i) {
    for (int j = 0; j < 15; ++j) A(i, j) = normal(rng) * (1.0 + j);
  }
  return A.transpose() * A;
}

TEST(MarginalizationPrior, ReproducesInformationAndGradientAtTheLinearisationPoint) {
  auto rng = MakeRng(61, "marg_prior");
  NormalSampler normal;
  for (int rank : {15, 9}) {  // full and rank-deficient
    const Mat15 H = RandomInformation(rng, rank);
    Vec15 g;
    for (int i = 0; i < 15; ++i) g(i) = normal(rng);
    // A gradient the information can explain (in its range), as a Schur complement gives.
    g = H * g;
    const NavState x0 = MarginalizedTestState();
    const MarginalizationPrior prior(StateParameters::FromNavState(x0), H, g);
    const auto blocks = MarginalizedBlocks(x0);
    const double* ptrs[] = {blocks[0].data(), blocks[1].data(), blocks[2].data(), blocks[3].data()};
    Vec15 r0;
    Eigen::Matrix<double, 15, 4, Eigen::RowMajor> Jq;
    Eigen::Matrix<double, 15, 3, Eigen::RowMajor> Jp, Jv;
    Eigen::Matrix<double, 15, 6, Eigen::RowMajor> Jb;
    double* jac[] = {Jq.data(), Jp.data(), Jv.data(), Jb.data()};
    prior.Evaluate(ptrs, r0.data(), jac);
    Mat15 J;
    J << Jq * QuaternionPlusJacobian(blocks[0].data()), Jp, Jv, Jb;
    EXPECT_LT((J.transpose() * J - H).cwiseAbs().maxCoeff(), 1e-9 * H.cwiseAbs().maxCoeff());
    EXPECT_LT((J.transpose() * r0 - g).cwiseAbs().maxCoeff(), 1e-8 * g.cwiseAbs().maxCoeff());
  }
}

TEST(MarginalizationPrior, FromCovarianceWhitensByTheCovariance) {
  Mat15 P = Mat15::Zero();
  P.diagonal() << 1e-4, 1e-4, 4e-4, 0.01, 0.01, 0.04, 1e-3, 1e-3, 1e-3, 1e-6, 1e-6, 1e-6, 1e-3,
      1e-3, 1e-3;
  P(3, 4) = P(4, 3) = 0.005;
  const NavState mean = MarginalizedTestState();
  const std::unique_ptr<MarginalizationPrior> prior(MarginalizationPrior::FromCovariance(mean, P));
  EXPECT_LT(Evaluate(*prior, mean).norm(), 1e-12);
  NavState x = mean;
  Vec15 dx = Vec15::Zero();
  dx << 0.01, -0.02, 0.01, 0.1, -0.05, 0.2, 0.01, 0.02, -0.03, 1e-3, 0, 0, 0.01, 0, 0;
  x.q_world_imu = mean.q_world_imu * so3::Exp<double>(Vec3(dx.segment<3>(0)));
  x.p_world += dx.segment<3>(3);
  x.v_world += dx.segment<3>(6);
  x.gyro_bias += dx.segment<3>(9);
  x.accel_bias += dx.segment<3>(12);
  EXPECT_NEAR(Evaluate(*prior, x).squaredNorm(), dx.dot(P.inverse() * dx), 1e-6);
  Mat15 bad = P;
  bad(0, 0) = -1.0;
  EXPECT_THROW(MarginalizationPrior::FromCovariance(mean, bad), InputError);
}

TEST(MarginalizationPrior, JacobiansMatchNumericDifferencesOnTheManifold) {
  auto rng = MakeRng(62, "marg_prior_jacobians");
  NormalSampler normal;
  const RightQuaternionManifold manifold;
  const NavState x0 = MarginalizedTestState();
  const MarginalizationPrior prior(StateParameters::FromNavState(x0), RandomInformation(rng, 15),
                                   Vec15::Constant(0.3));
  double worst = 0.0;
  for (int trial = 0; trial < 5; ++trial) {
    NavState x = x0;
    x.q_world_imu =
        x0.q_world_imu * so3::Exp<double>(0.5 * Vec3(normal(rng), normal(rng), normal(rng)));
    x.p_world += Vec3(normal(rng), normal(rng), normal(rng));
    x.gyro_bias += 0.01 * Vec3(normal(rng), normal(rng), normal(rng));
    const auto check = testing::CheckJacobians(prior, MarginalizedBlocks(x),
                                               {&manifold, nullptr, nullptr, nullptr});
    worst = std::max(worst, check.worst_relative_error);
  }
  std::printf("marginalization prior: worst relative Jacobian error %.2e\n", worst);
  EXPECT_LT(worst, 1e-7);
}

}  // namespace
}  // namespace statebench::est
