// Levenberg-Marquardt on the sliding window's chain of states (chain_system.hpp), the
// algorithm of ceres::Solve with the options the smoother used (trust region, LEVENBERG_MARQUARDT,
// Jacobi scaling, default tolerances) but with the linear system solved by block elimination in
// O(N) instead of a general sparse Cholesky: no per-solve preprocessing, ordering or symbolic
// analysis, and the newest state's marginal information comes from the final linearisation.
//
// Each iteration, as Ceres' TrustRegionMinimizer:
//   step      (H + D / radius) dx = -g, D = clamp(diag(S H S), 1e-6, 1e32) / s^2 with the Jacobi
//             scaling s = 1 / (1 + sqrt(diag H)) of the first linearisation
//   model     m = -(g^T dx + 1/2 dx^T H dx); a step with m <= 0 is invalid (radius / 2, ...)
//   candidate x (+) dx, its cost c'; stop (x kept) when |dx| <= 1e-8 (|x| + 1e-8) or
//             |c - c'| <= 1e-6 c
//   accept    when (c - c') / m > 1e-3: x = candidate, relinearise,
//             radius /= max(1/3, 1 - (2 rho - 1)^3); else radius /= factor, factor *= 2
//   stop      at max_iterations (usable), gradient max-norm <= 1e-10 (converged), six invalid
//             steps in a row, a radius below 1e-32 or a failed evaluation at x (not usable)
// The floating-point sums differ from Ceres' (another elimination order), so the results agree
// with a Ceres solve to its tolerances, not bit for bit.
#pragma once

#include <vector>

#include "estimator/chain_system.hpp"

namespace statebench::est {

struct ChainSolveOptions {
  int max_iterations = 10;
  double initial_trust_region_radius = 1e4;
};

struct ChainSolveSummary {
  bool usable = false;  // as ceres::Solver::Summary::IsSolutionUsable, and a finite cost
  int iterations = 0;   // as Ceres counts them (summary.iterations.size() - 1)
  double initial_cost = 0.0;
  double final_cost = 0.0;
  // The linearisation at the returned values (valid when usable): the newest state's marginal
  // information without a second linearisation.
  bool has_system = false;
  ChainSystem system;
};

// Optimises the chain's blocks and the global scalars in place (rotation blocks on `rotation`;
// with globals the step is the bordered solve of bordered_chain.hpp, each global damped and
// scaled as a state's coordinate is).
ChainSolveSummary SolveChainLevenbergMarquardt(const std::vector<ChainState>& chain,
                                               const ceres::Manifold& rotation,
                                               const ChainSolveOptions& options,
                                               std::span<double* const> globals = {});

}  // namespace statebench::est
