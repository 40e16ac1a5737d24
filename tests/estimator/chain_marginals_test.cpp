// ChainMarginalCovariances against the dense inverse of the same block-tridiagonal system.
#include <gtest/gtest.h>

#include <random>

#include "estimator/chain_system.hpp"

namespace statebench::est {
namespace {

TEST(ChainMarginalCovariances, AreTheDiagonalBlocksOfTheInverse) {
  constexpr int kStates = 7;
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  const auto random = [&] {
    Mat15 m;
    for (int i = 0; i < 15; ++i)
      for (int j = 0; j < 15; ++j) m(i, j) = normal(rng);
    return m;
  };
  // H = J^T J for a chain of factors touching one state or two neighbours, scales spread over
  // six orders of magnitude as the smoother's are.
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(15 * kStates, 15 * kStates);
  for (int k = 0; k < kStates; ++k) {
    Mat15 J = random();
    J.col(4) *= 1e3;
    H.block<15, 15>(15 * k, 15 * k) += J.transpose() * J;
    if (k + 1 < kStates) {
      Eigen::Matrix<double, 15, 30> Jp;
      Jp << random(), random();
      H.block<30, 30>(15 * k, 15 * k) += Jp.transpose() * Jp;
    }
  }
  ChainSystem system;
  for (int k = 0; k < kStates; ++k) {
    system.D.push_back(H.block<15, 15>(15 * k, 15 * k));
    system.g.push_back(Vec15::Zero());
    if (k + 1 < kStates) system.B.push_back(H.block<15, 15>(15 * k, 15 * (k + 1)));
  }
  const Eigen::MatrixXd P = H.inverse();
  const std::vector<Mat15> marginals = ChainMarginalCovariances(system);
  ASSERT_EQ(marginals.size(), static_cast<std::size_t>(kStates));
  for (int k = 0; k < kStates; ++k) {
    const Mat15 expected = P.block<15, 15>(15 * k, 15 * k);
    EXPECT_LT((marginals[k] - expected).norm(), 1e-9 * expected.norm()) << "state " << k;
    EXPECT_EQ(marginals[k], marginals[k].transpose());
  }
  // The newest marginal is the inverse of the newest marginal information.
  EXPECT_LT((marginals.back() * NewestMarginalInformation(system) - Mat15::Identity()).norm(),
            1e-8);
}

}  // namespace
}  // namespace statebench::est
