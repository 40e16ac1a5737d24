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

// b[j] = d^derivative B_j / d tau^derivative at tau, j = 0..5; derivative in 0..5.
void QuinticBasis(double tau, int derivative, double b[kQuinticOrder]);

}  // namespace statebench::sim
