#include "estimator/chain_levenberg_marquardt.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "estimator/bordered_chain.hpp"

namespace statebench::est {
namespace {

// Ceres' defaults (ceres::Solver::Options) for what the smoother did not set.
constexpr double kFunctionTolerance = 1e-6;
constexpr double kGradientTolerance = 1e-10;
constexpr double kParameterTolerance = 1e-8;
constexpr double kMinRelativeDecrease = 1e-3;
constexpr double kMinTrustRegionRadius = 1e-32;
constexpr double kMaxTrustRegionRadius = 1e16;
constexpr double kMinLmDiagonal = 1e-6;
constexpr double kMaxLmDiagonal = 1e32;
constexpr int kMaxConsecutiveInvalidSteps = 5;

constexpr std::array<int, 4> kLmBlockSize{4, 3, 3, 6};
constexpr std::array<int, 4> kLmTangentOffset{0, 3, 6, 9};

// The chain's parameter values, 16 doubles per state, then the globals.
std::vector<double> ReadChainValues(const std::vector<ChainState>& chain,
                                    std::span<double* const> globals) {
  std::vector<double> x;
  x.reserve(16 * chain.size() + globals.size());
  for (const ChainState& s : chain) {
    for (int b = 0; b < 4; ++b) x.insert(x.end(), s.blocks[b], s.blocks[b] + kLmBlockSize[b]);
  }
  for (double* g : globals) x.push_back(*g);
  return x;
}

void WriteChainValues(const std::vector<double>& x, const std::vector<ChainState>& chain,
                      std::span<double* const> globals) {
  const double* from = x.data();
  for (const ChainState& s : chain) {
    for (int b = 0; b < 4; ++b) {
      std::copy(from, from + kLmBlockSize[b], s.blocks[b]);
      from += kLmBlockSize[b];
    }
  }
  for (double* g : globals) *g = *from++;
}

// Writes x (+) delta into the chain's blocks (rotation blocks through the manifold) and globals.
bool PlusIntoChain(const std::vector<double>& x, const std::vector<Vec15>& delta,
                   const Eigen::VectorXd& delta_global, const std::vector<ChainState>& chain,
                   std::span<double* const> globals, const ceres::Manifold& rotation) {
  const double* from = x.data();
  for (std::size_t k = 0; k < chain.size(); ++k) {
    if (!rotation.Plus(from, delta[k].data(), chain[k].blocks[0])) return false;
    for (int b = 1; b < 4; ++b) {
      for (int i = 0; i < kLmBlockSize[b]; ++i) {
        chain[k].blocks[b][i] = from[kLmBlockSize[0] + kLmTangentOffset[b] - 3 + i] +
                                delta[k](kLmTangentOffset[b] + i);
      }
    }
    from += 16;
  }
  for (std::size_t i = 0; i < globals.size(); ++i) *globals[i] = from[i] + delta_global(i);
  return true;
}

// max |x - (x (+) -g)|, Ceres' gradient_max_norm.
double GradientMaxNorm(const std::vector<double>& x, const std::vector<Vec15>& g,
                       const Eigen::VectorXd& g_global, const ceres::Manifold& rotation) {
  double out = 0.0;
  const double* from = x.data();
  for (const Vec15& gk : g) {
    const Vec3 minus_rotation = -gk.head<3>();
    double q[4];
    rotation.Plus(from, minus_rotation.data(), q);
    for (int i = 0; i < 4; ++i) out = std::max(out, std::abs(from[i] - q[i]));
    out = std::max(out, gk.tail<12>().lpNorm<Eigen::Infinity>());
    from += 16;
  }
  if (g_global.size() > 0) out = std::max(out, g_global.lpNorm<Eigen::Infinity>());
  return out;
}

double ChainNorm(const std::vector<Vec15>& v, const Eigen::VectorXd& v_global) {
  double sq = 0.0;
  for (const Vec15& x : v) sq += x.squaredNorm();
  if (v_global.size() > 0) sq += v_global.squaredNorm();
  return std::sqrt(sq);
}

}  // namespace

ChainSolveSummary SolveChainLevenbergMarquardt(const std::vector<ChainState>& chain,
                                               const ceres::Manifold& rotation,
                                               const ChainSolveOptions& options,
                                               std::span<double* const> globals) {
  ChainSolveSummary out;
  if (chain.empty()) return out;
  std::vector<double> x = ReadChainValues(chain, globals);
  ChainSystem& system = out.system;
  if (!LinearizeChain(chain, rotation, &system, globals) || !std::isfinite(system.cost)) {
    WriteChainValues(x, chain, globals);
    return out;  // Ceres: evaluation failed at the start (FAILURE)
  }
  out.initial_cost = system.cost;
  double x_norm = Eigen::Map<const Eigen::VectorXd>(x.data(), x.size()).norm();
  std::vector<Vec15> scaling(chain.size());
  for (std::size_t k = 0; k < chain.size(); ++k) {
    scaling[k] = (1.0 + system.D[k].diagonal().array().sqrt()).inverse();
  }
  const Eigen::VectorXd global_scaling =
      (1.0 + system.E.diagonal().array().sqrt()).inverse().matrix();
  Eigen::VectorXd global_damping(globals.size()), dx_global;
  double radius = options.initial_trust_region_radius;
  double decrease_factor = 2.0;
  int invalid_in_a_row = 0;
  int iteration = 0;
  bool failed = false;
  bool successful = true;  // iteration 0 counts as a successful step
  std::vector<Vec15> damping(chain.size()), dx;

  const auto can_continue = [&] {
    if (iteration >= options.max_iterations) return false;  // NO_CONVERGENCE, usable
    if (successful && GradientMaxNorm(x, system.g, system.g_global, rotation) <=
                          kGradientTolerance) {
      return false;
    }
    return radius > kMinTrustRegionRadius;
  };
  const auto reject = [&] {
    radius /= decrease_factor;
    decrease_factor *= 2.0;
    successful = false;
  };
  while (can_continue()) {
    ++iteration;
    for (std::size_t k = 0; k < chain.size(); ++k) {
      const Vec15 s2 = scaling[k].array().square();
      const Vec15 d = (s2.array() * system.D[k].diagonal().array())
                          .max(kMinLmDiagonal)
                          .min(kMaxLmDiagonal);
      damping[k] = (d.array() / radius / s2.array()).matrix();
    }
    for (Eigen::Index i = 0; i < global_damping.size(); ++i) {
      const double s2 = global_scaling(i) * global_scaling(i);
      const double d = std::clamp(s2 * system.E(i, i), kMinLmDiagonal, kMaxLmDiagonal);
      global_damping(i) = d / radius / s2;
    }
    double model_change = 0.0;
    bool valid = SolveBorderedChain(system, damping, global_damping, &dx, &dx_global);
    if (valid) {
      double g_dx = 0.0;
      for (std::size_t k = 0; k < dx.size(); ++k) g_dx += system.g[k].dot(dx[k]);
      if (dx_global.size() > 0) g_dx += system.g_global.dot(dx_global);
      model_change = -(g_dx + 0.5 * BorderedChainQuadratic(system, dx, dx_global));
      valid = std::isfinite(model_change) && model_change > 0.0;
    }
    if (!valid) {
      if (++invalid_in_a_row >= kMaxConsecutiveInvalidSteps) {
        failed = true;
        break;
      }
      reject();
      continue;
    }
    invalid_in_a_row = 0;
    double candidate_cost = std::numeric_limits<double>::max();
    if (!PlusIntoChain(x, dx, dx_global, chain, globals, rotation) ||
        !ChainCost(chain, &candidate_cost) ||
        !std::isfinite(candidate_cost)) {
      candidate_cost = std::numeric_limits<double>::max();
    }
    if (ChainNorm(dx, dx_global) <= kParameterTolerance * (x_norm + kParameterTolerance)) {
      --iteration;  // Ceres returns before recording this iteration
      break;
    }
    if (std::abs(system.cost - candidate_cost) <= kFunctionTolerance * std::abs(system.cost)) {
      --iteration;
      break;
    }
    const double relative_decrease = (system.cost - candidate_cost) / model_change;
    if (relative_decrease > kMinRelativeDecrease) {
      ChainSystem relinearized;
      if (!LinearizeChain(chain, rotation, &relinearized, globals) ||
          !std::isfinite(relinearized.cost)) {
        failed = true;
        break;
      }
      x = ReadChainValues(chain, globals);
      x_norm = Eigen::Map<const Eigen::VectorXd>(x.data(), x.size()).norm();
      system = std::move(relinearized);
      radius /= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * relative_decrease - 1.0, 3));
      radius = std::min(kMaxTrustRegionRadius, radius);
      decrease_factor = 2.0;
      successful = true;
    } else {
      reject();
    }
  }
  WriteChainValues(x, chain, globals);  // the last accepted values
  out.iterations = iteration;
  out.final_cost = system.cost;
  out.usable = !failed && std::isfinite(system.cost);
  out.has_system = out.usable;
  return out;
}

}  // namespace statebench::est
