// A Gaussian prior carried over a time step in which some of its variables are first-order
// Gauss-Markov processes (a GNSS receiver's slowly varying error as globals of the window,
// sliding_window_smoother.hpp): each such variable moves on as x' = rho x + w, w ~ N(0, q).
//
// The prior is 1/2 d^T H d + g^T d in the offsets d from its linearisation point, whose
// Gauss-Markov entries scale by rho too (the caller scales the values). With
// A = diag(1, ..., rho_i, ...) the prior of A d has H_a = A^-T H A^-1, g_a = A^-T g, and the
// noise on the Gauss-Markov columns B gives (Woodbury; no inverse of H, which may be singular)
//   H' = H_a - H_a B K B^T H_a,  g' = g_a - H_a B K B^T g_a,  K = (Q^-1 + B^T H_a B)^-1,
// the information form of the covariance A H^-1 A^T + B Q B^T with the same mean.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "estimator/linear_system.hpp"

namespace statebench::est {

struct GaussMarkovStep {
  Eigen::Index column = 0;  // in the prior's H and g
  double rho = 1.0;         // exp(-dt / tau)
  double noise_variance = 0.0;  // sigma^2 (1 - rho^2), > 0
};

void CarryGaussMarkovPrior(const std::vector<GaussMarkovStep>& steps, LinearSystem* prior);

}  // namespace statebench::est
