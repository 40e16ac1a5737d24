#include "estimator/chain_levenberg_marquardt.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

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

// The chain's parameter values, 16 doubles per state.
std::vector<double> ReadChainValues(const std::vector<ChainState>& chain) {
  std::vector<double> x;
  x.reserve(16 * chain.size());
  for (const ChainState& s : chain) {
    for (int b = 0; b < 4; ++b) x.insert(x.end(), s.blocks[b], s.blocks[b] + kLmBlockSize[b]);
  }
  return x;
}

void WriteChainValues(const std::vector<double>& x, const std::vector<ChainState>& chain) {
  const double* from = x.data();
  for (const ChainState& s : chain) {
    for (int b = 0; b < 4; ++b) {
      std::copy(from, from + kLmBlockSize[b], s.blocks[b]);
      from += kLmBlockSize[b];
    }
  }
}

// Writes x (+) delta into the chain's blocks (rotation blocks through the manifold).
bool PlusIntoChain(const std::vector<double>& x, const std::vector<Vec15>& delta,
                   const std::vector<ChainState>& chain, const ceres::Manifold& rotation) {
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
  return true;
}

// max |x - (x (+) -g)|, Ceres' gradient_max_norm.
double GradientMaxNorm(const std::vector<double>& x, const std::vector<Vec15>& g,
                       const ceres::Manifold& rotation) {
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
  return out;
}

double ChainQuadratic(const ChainSystem& s, const std::vector<Vec15>& dx) {
  double out = 0.0;  // dx^T H dx
  for (std::size_t k = 0; k < dx.size(); ++k) {
    out += dx[k].dot(s.D[k] * dx[k]);
    if (k + 1 < dx.size()) out += 2.0 * dx[k].dot(s.B[k] * dx[k + 1]);
  }
  return out;
}

double ChainNorm(const std::vector<Vec15>& v) {
  double sq = 0.0;
  for (const Vec15& x : v) sq += x.squaredNorm();
  return std::sqrt(sq);
}

}  // namespace

ChainSolveSummary SolveChainLevenbergMarquardt(const std::vector<ChainState>& chain,
                                               const ceres::Manifold& rotation,
                                               const ChainSolveOptions& options) {
  ChainSolveSummary out;
  if (chain.empty()) return out;
  std::vector<double> x = ReadChainValues(chain);
  ChainSystem& system = out.system;
  if (!LinearizeChain(chain, rotation, &system) || !std::isfinite(system.cost)) {
    WriteChainValues(x, chain);
    return out;  // Ceres: evaluation failed at the start (FAILURE)
  }
  out.initial_cost = system.cost;
  double x_norm = Eigen::Map<const Eigen::VectorXd>(x.data(), x.size()).norm();
  std::vector<Vec15> scaling(chain.size());
  for (std::size_t k = 0; k < chain.size(); ++k) {
    scaling[k] = (1.0 + system.D[k].diagonal().array().sqrt()).inverse();
  }
  double radius = options.initial_trust_region_radius;
  double decrease_factor = 2.0;
  int invalid_in_a_row = 0;
  int iteration = 0;
  bool failed = false;
  bool successful = true;  // iteration 0 counts as a successful step
  std::vector<Vec15> damping(chain.size()), dx;

  const auto can_continue = [&] {
    if (iteration >= options.max_iterations) return false;  // NO_CONVERGENCE, usable
    if (successful && GradientMaxNorm(x, system.g, rotation) <= kGradientTolerance) return false;
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
    double model_change = 0.0;
    bool valid = SolveChain(system, damping, &dx);
    if (valid) {
      double g_dx = 0.0;
      for (std::size_t k = 0; k < dx.size(); ++k) g_dx += system.g[k].dot(dx[k]);
      model_change = -(g_dx + 0.5 * ChainQuadratic(system, dx));
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
    if (!PlusIntoChain(x, dx, chain, rotation) || !ChainCost(chain, &candidate_cost) ||
        !std::isfinite(candidate_cost)) {
      candidate_cost = std::numeric_limits<double>::max();
    }
    if (ChainNorm(dx) <= kParameterTolerance * (x_norm + kParameterTolerance)) {
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
      if (!LinearizeChain(chain, rotation, &relinearized) || !std::isfinite(relinearized.cost)) {
        failed = true;
        break;
      }
      x = ReadChainValues(chain);
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
  WriteChainValues(x, chain);  // the last accepted values
  out.iterations = iteration;
  out.final_cost = system.cost;
  out.usable = !failed && std::isfinite(system.cost);
  out.has_system = out.usable;
  return out;
}

}  // namespace statebench::est
