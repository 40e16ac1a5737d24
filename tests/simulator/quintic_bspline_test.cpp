#include "simulator/quintic_bspline.hpp"

#include <gtest/gtest.h>

namespace statebench::sim {
namespace {

TEST(QuinticBasis, PartitionOfUnityAndReproducesLines) {
  for (double tau : {0.0, 0.3, 0.77, 0.999}) {
    double basis[1][kQuinticOrder];
    QuinticBasis(tau, 0, basis);
    const double* b = basis[0];
    double sum = 0.0;
    double first_moment = 0.0;
    for (int j = 0; j < kQuinticOrder; ++j) {
      EXPECT_GE(b[j], 0.0);
      sum += b[j];
      first_moment += b[j] * j;
    }
    EXPECT_NEAR(sum, 1.0, 1e-15);
    // Control points P_j = j give the line c(tau) = tau + 2.
    EXPECT_NEAR(first_moment, tau + 2.0, 1e-14);
  }
}

TEST(QuinticBasis, FourDerivativesContinuousAcrossKnots) {
  // Basis j at the end of a segment equals basis j + 1 at the start of the next one.
  for (int r = 0; r <= 4; ++r) {
    double end_all[6][kQuinticOrder];
    double start_all[6][kQuinticOrder];
    QuinticBasis(1.0, r, end_all);
    QuinticBasis(0.0, r, start_all);
    const double* end = end_all[r];
    const double* start = start_all[r];
    EXPECT_NEAR(end[0], 0.0, 1e-12) << "derivative " << r;
    for (int j = 1; j < kQuinticOrder; ++j) EXPECT_NEAR(end[j], start[j - 1], 1e-12) << r;
    EXPECT_NEAR(start[kQuinticOrder - 1], 0.0, 1e-12) << "derivative " << r;
  }
}

TEST(QuinticBasis, DerivativesMatchNumericDifferences) {
  const double tau = 0.41;
  const double e = 1e-6;
  for (int r = 0; r < 5; ++r) {
    double b[6][kQuinticOrder];
    double b0[6][kQuinticOrder];
    double b1[6][kQuinticOrder];
    QuinticBasis(tau, r + 1, b);
    QuinticBasis(tau - e, r, b0);
    QuinticBasis(tau + e, r, b1);
    for (int j = 0; j < kQuinticOrder; ++j) {
      EXPECT_NEAR(b[r + 1][j], (b1[r][j] - b0[r][j]) / (2 * e), 1e-6);
    }
  }
}

}  // namespace
}  // namespace statebench::sim
