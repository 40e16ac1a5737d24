// The fixed-size kernels of the IMU propagation and the chain solver against Eigen's dense
// products and factorisations: Mat3Blocks (mat3_blocks.hpp) and SmallCholesky
// (small_cholesky.hpp).
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <limits>
#include <random>

#include "estimator/mat3_blocks.hpp"
#include "estimator/small_cholesky.hpp"

namespace statebench::est {
namespace {

template <int N>
Eigen::Matrix<double, N, N> RandomSpd(std::mt19937_64& rng, double conditioning) {
  std::normal_distribution<double> normal;
  Eigen::Matrix<double, N, N> A;
  for (int i = 0; i < N * N; ++i) A(i) = normal(rng);
  Eigen::Matrix<double, N, N> S = A * A.transpose();
  for (int i = 0; i < N; ++i) S(i, i) += conditioning;
  return S;
}

Mat3 RandomMat3(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Mat3 m;
  for (int i = 0; i < 9; ++i) m(i) = normal(rng);
  return m;
}

// The IMU transition's pattern: identity diagonal, general and scaled-identity blocks, zeros.
TEST(Mat3Blocks, CongruenceEqualsTheDenseProduct) {
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    Mat3Blocks<5, 5> F;
    for (int b = 0; b < 5; ++b) F.SetIdentity(b, b);
    F.SetGeneral(0, 0, RandomMat3(rng));
    F.SetGeneral(0, 3, RandomMat3(rng));
    F.SetGeneral(1, 0, RandomMat3(rng));
    F.SetScaledIdentity(1, 2, 0.1 * (trial + 1));
    F.SetGeneral(1, 4, RandomMat3(rng));
    F.SetGeneral(2, 3, RandomMat3(rng));
    const Mat15 P = RandomSpd<15>(rng, 1.0);
    const Mat15 Fd = F.ToDense();
    const Mat15 expected = Fd * P * Fd.transpose();
    const Mat15 C = F.Congruence(P);
    EXPECT_LT((C - expected).norm(), 1e-12 * expected.norm());
    EXPECT_EQ(C, C.transpose());  // exactly symmetric
  }
}

TEST(Mat3Blocks, RectangularCongruenceAndScaledGram) {
  std::mt19937_64 rng(8);
  Mat3Blocks<5, 3> G;  // preintegration noise into the state: zero rows for the biases
  G.SetIdentity(0, 0);
  G.SetGeneral(2, 1, RandomMat3(rng));
  G.SetGeneral(1, 2, RandomMat3(rng));
  const Mat9 Q = RandomSpd<9>(rng, 0.5);
  const auto Gd = G.ToDense();
  const Mat15 expected = Gd * Q * Gd.transpose();
  EXPECT_LT((G.Congruence(Q) - expected).norm(), 1e-12 * expected.norm());
  const Mat15 GQG = G.Congruence(Q);
  EXPECT_TRUE(GQG.bottomRightCorner(6, 6).isZero(0.0));

  Mat3Blocks<3, 1> B;  // a noise input: one zero block
  B.SetGeneral(1, 0, RandomMat3(rng));
  B.SetGeneral(2, 0, RandomMat3(rng));
  const auto Bd = B.ToDense();
  const Mat9 gram = 0.37 * Bd * Bd.transpose();
  EXPECT_LT((B.ScaledGram(0.37) - gram).norm(), 1e-12 * gram.norm());
  EXPECT_TRUE(B.ScaledGram(0.37).topRows<3>().isZero(0.0));
}

TEST(SmallCholesky, FactorAndSolvesAgreeWithEigen) {
  std::mt19937_64 rng(9);
  for (double conditioning : {1e-6, 1.0, 1e3}) {
    const Mat15 A = RandomSpd<15>(rng, conditioning);
    const SmallCholesky<15> chol(A);
    ASSERT_TRUE(chol.ok());
    const Eigen::LLT<Mat15> llt(A);
    const Mat15 L_eigen = llt.matrixL();
    EXPECT_LT((chol.L() - L_eigen).norm(), 1e-12 * L_eigen.norm());
    EXPECT_TRUE(chol.L().triangularView<Eigen::StrictlyUpper>().toDenseMatrix().isZero(0.0));
    const Mat15 B = RandomSpd<15>(rng, 1.0);
    const Mat15 lower = L_eigen.triangularView<Eigen::Lower>().solve(B);
    EXPECT_LT((chol.SolveLower(B) - lower).norm(), 1e-9 * lower.norm());
    const Mat15 upper = L_eigen.transpose().triangularView<Eigen::Upper>().solve(B);
    EXPECT_LT((chol.SolveUpper(B) - upper).norm(), 1e-9 * upper.norm());
    const Vec15 b = B.col(3);
    const Vec15 x = llt.solve(b);
    EXPECT_LT((chol.Solve(b) - x).norm(), 1e-9 * x.norm());
    const Eigen::Matrix<double, 15, Eigen::Dynamic> Bd = B.leftCols(4);
    const Eigen::MatrixXd X = llt.solve(Bd);
    EXPECT_LT((chol.Solve(Bd) - X).norm(), 1e-9 * X.norm());
  }
}

// Compute writes each column on and below the diagonal only: a factor computed again (after a
// success or a refusal) is the one a fresh object gives, its upper triangle still zero.
TEST(SmallCholesky, ComputedAgainEqualsAFreshFactor) {
  std::mt19937_64 rng(10);
  SmallCholesky<15> reused(RandomSpd<15>(rng, 1.0));
  ASSERT_TRUE(reused.ok());
  Mat15 bad = RandomSpd<15>(rng, 1.0);
  bad(9, 9) = -1.0;
  EXPECT_FALSE(reused.Compute(bad));
  const Mat15 A = RandomSpd<15>(rng, 1e-3);
  ASSERT_TRUE(reused.Compute(A));
  EXPECT_EQ(reused.L(), SmallCholesky<15>(A).L());
  EXPECT_TRUE(reused.L().triangularView<Eigen::StrictlyUpper>().toDenseMatrix().isZero(0.0));
  EXPECT_LT((reused.L() * reused.L().transpose() - A).norm(), 1e-12 * A.norm());
}

TEST(SmallCholesky, RefusesWhatIsNotPositiveDefinite) {
  Mat3 A = Mat3::Identity();
  A(1, 1) = -1.0;
  EXPECT_FALSE(SmallCholesky<3>(A).ok());
  A(1, 1) = 0.0;
  EXPECT_FALSE(SmallCholesky<3>(A).ok());
  A(1, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(SmallCholesky<3>(A).ok());
  EXPECT_TRUE(SmallCholesky<3>(Mat3::Identity()).ok());
}

}  // namespace
}  // namespace statebench::est
