// The bordered chain (block-tridiagonal states plus global scalars) against dense solves of the
// same random SPD arrowhead system.
#include "estimator/bordered_chain.hpp"

#include <gtest/gtest.h>

#include <random>

namespace statebench::est {
namespace {

constexpr int kBorderStates = 6;
constexpr int kBorderGlobals = 2;

struct Arrowhead {
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  ChainSystem system;
};

// H = J^T J for factors on one state, two neighbours, a state and the globals, and the globals
// alone; scales spread as the smoother's are (a stiff column, a weak global).
Arrowhead RandomArrowhead(unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  const auto random = [&](int rows, int cols) {
    Eigen::MatrixXd m(rows, cols);
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j) m(i, j) = normal(rng);
    return m;
  };
  const int n = 15 * kBorderStates + kBorderGlobals;
  const int at_globals = 15 * kBorderStates;
  Arrowhead a;
  a.H = Eigen::MatrixXd::Zero(n, n);
  for (int k = 0; k < kBorderStates; ++k) {
    Eigen::MatrixXd J = random(15, 15);
    J.col(4) *= 1e3;
    a.H.block(15 * k, 15 * k, 15, 15) += J.transpose() * J;
    if (k + 1 < kBorderStates) {
      const Eigen::MatrixXd Jp = random(15, 30);
      a.H.block(15 * k, 15 * k, 30, 30) += Jp.transpose() * Jp;
    }
    // A GNSS-like factor: 3 rows on the state's position and the globals.
    Eigen::MatrixXd Jg = Eigen::MatrixXd::Zero(3, n);
    Jg.block(0, 15 * k + 3, 3, 3) = random(3, 3);
    Jg.rightCols(kBorderGlobals) = 0.1 * random(3, kBorderGlobals);
    a.H += Jg.transpose() * Jg;
  }
  a.H.bottomRightCorner(kBorderGlobals, kBorderGlobals) +=
      25.0 * Eigen::MatrixXd::Identity(kBorderGlobals, kBorderGlobals);
  a.g = random(n, 1);
  ChainSystem& s = a.system;
  for (int k = 0; k < kBorderStates; ++k) {
    s.D.push_back(a.H.block(15 * k, 15 * k, 15, 15));
    s.g.push_back(a.g.segment(15 * k, 15));
    s.C.push_back(a.H.block(15 * k, at_globals, 15, kBorderGlobals));
    if (k + 1 < kBorderStates) s.B.push_back(a.H.block(15 * k, 15 * (k + 1), 15, 15));
  }
  s.E = a.H.bottomRightCorner(kBorderGlobals, kBorderGlobals);
  s.g_global = a.g.tail(kBorderGlobals);
  return a;
}

TEST(BorderedChain, SolvesAsTheDenseSystem) {
  const Arrowhead a = RandomArrowhead(7);
  const int n = static_cast<int>(a.H.rows());
  std::vector<Vec15> damping(kBorderStates);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(0.0, 2.0);
  Eigen::VectorXd diagonal(n);
  for (int k = 0; k < kBorderStates; ++k) {
    for (int i = 0; i < 15; ++i) damping[k](i) = diagonal(15 * k + i) = uniform(rng);
  }
  Eigen::VectorXd global_damping(kBorderGlobals);
  for (int i = 0; i < kBorderGlobals; ++i) {
    global_damping(i) = diagonal(15 * kBorderStates + i) = uniform(rng);
  }
  Eigen::MatrixXd damped = a.H;
  damped.diagonal() += diagonal;
  const Eigen::VectorXd expected = damped.ldlt().solve(-a.g);

  std::vector<Vec15> dx;
  Eigen::VectorXd dx_global;
  ASSERT_TRUE(SolveBorderedChain(a.system, damping, global_damping, &dx, &dx_global));
  Eigen::VectorXd solved(n);
  for (int k = 0; k < kBorderStates; ++k) solved.segment(15 * k, 15) = dx[k];
  solved.tail(kBorderGlobals) = dx_global;
  EXPECT_LT((solved - expected).norm(), 1e-9 * expected.norm());
  // The model's quadratic term is the dense one (undamped H).
  EXPECT_NEAR(BorderedChainQuadratic(a.system, dx, dx_global), solved.dot(a.H * solved),
              1e-9 * std::abs(solved.dot(a.H * solved)));
}

TEST(BorderedChain, MarginalsAreTheDenseOnes) {
  const Arrowhead a = RandomArrowhead(11);
  const int n = static_cast<int>(a.H.rows());
  const Eigen::MatrixXd P = a.H.inverse();
  const BorderedChainMarginals m = MarginalsOfBorderedChain(a.system);
  const Eigen::MatrixXd global_expected = P.bottomRightCorner(kBorderGlobals, kBorderGlobals);
  EXPECT_LT((m.global_covariance - global_expected).norm(), 1e-9 * global_expected.norm());
  const Mat15 newest_expected = P.block(n - kBorderGlobals - 15, n - kBorderGlobals - 15, 15, 15);
  const Mat15 newest = m.newest_information.inverse();
  EXPECT_LT((newest - newest_expected).norm(), 1e-8 * newest_expected.norm());
  EXPECT_EQ(NewestMarginalInformation(a.system), m.newest_information);
}

// Each state's covariance with the globals' uncertainty in it (the lagged output's), against the
// dense inverse; it is larger than the chain's covariance given the globals.
TEST(BorderedChain, StateMarginalsWithTheGlobalsAreTheDenseOnes) {
  const Arrowhead a = RandomArrowhead(13);
  const Eigen::MatrixXd P = a.H.inverse();
  const std::vector<Mat15> bordered = BorderedChainMarginalCovariances(a.system);
  const std::vector<Mat15> given_globals = ChainMarginalCovariances(a.system);
  ASSERT_EQ(bordered.size(), static_cast<std::size_t>(kBorderStates));
  for (int k = 0; k < kBorderStates; ++k) {
    const Mat15 expected = P.block(15 * k, 15 * k, 15, 15);
    EXPECT_LT((bordered[k] - expected).norm(), 1e-8 * expected.norm()) << k;
    EXPECT_GT(bordered[k].trace(), given_globals[k].trace()) << k;
  }
}

TEST(BorderedChain, WithoutGlobalsIsTheChain) {
  Arrowhead a = RandomArrowhead(13);
  a.system.C.clear();
  a.system.E.resize(0, 0);
  a.system.g_global.resize(0);
  const std::vector<Vec15> damping(kBorderStates, Vec15::Constant(0.5));
  std::vector<Vec15> bordered, plain;
  Eigen::VectorXd dx_global;
  ASSERT_TRUE(SolveBorderedChain(a.system, damping, Eigen::VectorXd(), &bordered, &dx_global));
  ASSERT_TRUE(SolveChain(a.system, damping, &plain));
  EXPECT_EQ(dx_global.size(), 0);
  for (int k = 0; k < kBorderStates; ++k) EXPECT_EQ(bordered[k], plain[k]);  // bit for bit
}

}  // namespace
}  // namespace statebench::est
