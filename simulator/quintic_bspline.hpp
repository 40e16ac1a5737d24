// Uniform quintic B-spline basis (C4 continuous), shared by the road terrain and the smoothed
// route path.
//
// On a uniform knot grid of spacing h, the curve segment k covers parameter t in [k, k + 1)
// (t = u / h) and is c(t) = sum_{j=0..5} B_j(tau) P_{k+j}, tau = t - k, with
//   [B_0 .. B_5](tau) = [1 tau tau^2 tau^3 tau^4 tau^5] M / 120
// (M the standard uniform quintic basis matrix). The basis is a partition of unity that
// reproduces polynomials up to degree 5, so lines and planes are represented exactly.
#pragma once

namespace statebench::sim {

inline constexpr int kQuinticOrder = 6;  // number of basis functions per segment

// M / 120: rows are powers of tau, columns basis functions. The power-basis coefficients of a
// segment are c_i = sum_j kQuinticPowerMatrix[i][j] P_{k+j}.
inline constexpr double kQuinticPowerMatrix[6][6] = {
    {1 / 120.0, 26 / 120.0, 66 / 120.0, 26 / 120.0, 1 / 120.0, 0.0},
    {-5 / 120.0, -50 / 120.0, 0.0, 50 / 120.0, 5 / 120.0, 0.0},
    {10 / 120.0, 20 / 120.0, -60 / 120.0, 20 / 120.0, 10 / 120.0, 0.0},
    {-10 / 120.0, 20 / 120.0, 0.0, -20 / 120.0, 10 / 120.0, 0.0},
    {5 / 120.0, -20 / 120.0, 30 / 120.0, -20 / 120.0, 5 / 120.0, 0.0},
    {-1 / 120.0, 5 / 120.0, -10 / 120.0, 10 / 120.0, -5 / 120.0, 1 / 120.0}};

// b[r][j] = d^r B_j / d tau^r at tau, for j = 0..5 and r = 0..max_derivative (<= 5).
void QuinticBasis(double tau, int max_derivative, double b[][kQuinticOrder]);

}  // namespace statebench::sim
