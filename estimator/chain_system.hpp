// The sliding window's Gauss-Newton system as a chain: states 0..N-1, each with a 15-dim tangent
// (rotation, position, velocity, gyro bias, accel bias: core/state.hpp), and factors that touch
// one state or two neighbouring ones (the smoother anchors every factor at the oldest state it
// touches, and a factor reaches at most the next state). The normal equations are therefore
// block-tridiagonal:
//
//   H = | D_0    B_0                 |      g = | g_0 |
//       | B_0^T  D_1    B_1          |          | g_1 |
//       |        B_1^T  D_2   ...    |          | ... |
//
// with D_k = sum J_k^T J_k over the factors touching state k, B_k = sum J_k^T J_{k+1} and
// g_k = sum J_k^T r. A robust loss enters as Ceres applies it (ceres::internal::Corrector: the
// residual and Jacobian are rescaled with rho' and, where rho'' > 0, the Triggs correction), so
// the system is the one Ceres' Levenberg-Marquardt builds for the same factors.
//
// Solving H dx = -g (with an optional diagonal added to each D_k) is a block elimination oldest
// first in O(N) 15x15 operations; the last block of the undamped elimination is the newest state's
// marginal information, the Schur complement of every older state.
//
// Global parameters (scalars any factor may touch, e.g. a GNSS receiver's time offset:
// bordered_chain.hpp) border the chain: H gains C_k (15 x G) coupling state k with the globals,
// E (G x G) and the gradient g_global. Without globals these are empty and nothing changes.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "core/eigen_types.hpp"
#include "estimator/linear_system.hpp"
#include "estimator/small_cholesky.hpp"

namespace statebench::est {

// One state of the chain: its parameter blocks (q_world_imu 4 on `rotation`, p 3, v 3, bias 6)
// and the factors anchored at it (they use its blocks and possibly the next state's).
struct ChainState {
  std::array<double*, 4> blocks{};
  std::vector<const FactorRecord*> factors;
};

struct ChainSystem {
  std::vector<Mat15> D;  // diagonal blocks
  std::vector<Mat15> B;  // B[k] couples state k (rows) with state k+1 (columns); N-1 of them
  std::vector<Vec15> g;
  double cost = 0.0;     // 1/2 sum rho(|r|^2), as ceres::Problem::Evaluate gives it
  // What the oldest state's own factors add (30 dims: state 0's tangent, then state 1's), when
  // the chain has two states or more: the system that marginalising state 0 eliminates
  // (SlidingWindowSmoother: no relinearisation of those factors at the same values).
  Eigen::Matrix<double, 30, 30> first_pair_H = Eigen::Matrix<double, 30, 30>::Zero();
  Eigen::Matrix<double, 30, 1> first_pair_g = Eigen::Matrix<double, 30, 1>::Zero();
  // The border (empty without globals): C[k] couples state k (rows) with the globals.
  std::vector<Eigen::Matrix<double, 15, Eigen::Dynamic>> C;
  Eigen::MatrixXd E;
  Eigen::VectorXd g_global;

  int num_globals() const { return static_cast<int>(E.rows()); }
};

// Cost of every factor at the current block values; false if a factor fails to evaluate.
bool ChainCost(const std::vector<ChainState>& chain, double* cost);

// Residuals, Jacobians, H and g at the current block values. False (system unspecified) if a
// factor fails to evaluate or a block of a factor belongs neither to its anchor, nor to the next
// state, nor to `globals` (scalar Euclidean blocks, the border's columns in this order).
bool LinearizeChain(const std::vector<ChainState>& chain, const ceres::Manifold& rotation,
                    ChainSystem* system, std::span<double* const> globals = {});

// Solves (H + diag(damping)) dx = -g by block elimination, the border ignored. False if an
// eliminated block is not positive definite (dx unspecified).
bool SolveChain(const ChainSystem& system, const std::vector<Vec15>& damping,
                std::vector<Vec15>* dx);

// The Cholesky factors of SolveChain's forward elimination, reusable for several right-hand
// sides: S_k = L_k L_k^T = D_k + diag(damping_k) - V_{k-1}^T V_{k-1}, V_k = L_k^-1 B_k.
struct ChainFactorization {
  std::vector<SmallCholesky<15>> L;
  std::vector<Mat15> V;
};
bool FactorChain(const ChainSystem& system, const std::vector<Vec15>& damping,
                 ChainFactorization* f);
// x = T^-1 rhs, T the factored block-tridiagonal matrix.
void SolveFactoredChain(const ChainFactorization& f, const std::vector<Vec15>& rhs,
                        std::vector<Vec15>* x);

// S^-1 * rhs for a block being eliminated, as SchurComplement inverts H_mm: Cholesky, or the
// eigen pseudo-inverse when nearly singular.
Eigen::Matrix<double, 15, Eigen::Dynamic> EliminateChainBlock(
    const Mat15& S, const Eigen::Matrix<double, 15, Eigen::Dynamic>& rhs);

// The newest state's information, H's last block after eliminating every older state (each
// eliminated block inverted as SchurComplement does: Cholesky, or the eigen pseudo-inverse when
// nearly singular) and, with a border, the globals (bordered_chain.hpp).
Mat15 NewestMarginalInformation(const ChainSystem& system);

// Every state's marginal covariance, the diagonal blocks of H^-1, in O(N): eliminating oldest
// first leaves S_0 = D_0, S_{k+1} = D_{k+1} - B_k^T G_k with G_k = S_k^-1 B_k (the information
// of state k given the newer ones is S_k, its conditional mean moves by -G_k dx_{k+1}); then
// newest first P_{N-1} = S_{N-1}^-1, P_k = S_k^-1 + G_k P_{k+1} G_k^T (a Rauch-Tung-Striebel
// sweep). Each S_k is inverted as NewestMarginalInformation does (the pseudo-inverse when
// nearly singular: an unobserved direction gets no variance rather than an infinite one).
// The border is ignored: with globals these are the covariances given the globals' values.
std::vector<Mat15> ChainMarginalCovariances(const ChainSystem& system);

}  // namespace statebench::est
