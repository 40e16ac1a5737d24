// The sliding window's normal equations with global parameters: the block-tridiagonal chain
// (chain_system.hpp) bordered by G scalars any factor may touch (a GNSS receiver's time offset):
//
//   | T    C | | dx   |     | g        |       T = the chain's D_k, B_k (15N x 15N)
//   | C^T  E | | dx_g | = - | g_global |       C = [C_0; ...; C_{N-1}] (15N x G)
//
// Solved by eliminating the chain with G extra right-hand sides, X = T^-1 C and y = -T^-1 g,
// then the G x G Schur complement of the globals:
//   (E - C^T X) dx_g = -g_global - C^T y,   dx = y - X dx_g,
// O(N G^2 + G^3) on top of the chain's O(N) elimination.
#pragma once

#include <vector>

#include "estimator/chain_system.hpp"

namespace statebench::est {

// (H + diag(damping, global_damping)) [dx; dx_global] = -[g; g_global]. False if an eliminated
// block or the globals' Schur complement is not positive definite. Without globals this is
// SolveChain.
bool SolveBorderedChain(const ChainSystem& system, const std::vector<Vec15>& damping,
                        const Eigen::VectorXd& global_damping, std::vector<Vec15>* dx,
                        Eigen::VectorXd* dx_global);

// dx^T H dx with the border.
double BorderedChainQuadratic(const ChainSystem& system, const std::vector<Vec15>& dx,
                              const Eigen::VectorXd& dx_global);

struct BorderedChainMarginals {
  Mat15 newest_information;           // the newest state's, every other state and global gone
  Eigen::MatrixXd global_covariance;  // G x G, the globals' marginal covariance
};

// Eliminates the states oldest first carrying the border (each 15x15 block inverted as
// NewestMarginalInformation does): S_0 = D_0, C'_0 = C_0, E' = E, then for each state k
//   [X_B X_C] = S_k^-1 [B_k C'_k],  S_{k+1} = D_{k+1} - B_k^T X_B,
//   C'_{k+1} = C_{k+1} - B_k^T X_C,  E' -= C'_k^T X_C,
// which leaves the joint information of (newest state, globals) [S_{N-1} C'; C'^T E']. Its
// Schur complements give the two marginals (pseudo-inverses where nearly singular).
BorderedChainMarginals MarginalsOfBorderedChain(const ChainSystem& system);

// Every state's marginal covariance with the globals' uncertainty in it: the diagonal blocks of
// the bordered H^-1, P_k = (T^-1)_kk + X_k Sigma_g X_k^T with X = T^-1 C (G solves with the
// chain's factorisation) and Sigma_g the globals' marginal covariance (above). Without globals,
// or when the chain does not factor, ChainMarginalCovariances (the covariances given the globals).
std::vector<Mat15> BorderedChainMarginalCovariances(const ChainSystem& system);

}  // namespace statebench::est
