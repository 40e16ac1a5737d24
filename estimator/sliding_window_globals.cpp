// SlidingWindowSmoother's global parameters (GNSS time offsets, mount rotation corrections): creation with their prior,
// their marginals after a solve, their bound (sliding_window_smoother.hpp).
#include <ceres/sized_cost_function.h>

#include <cmath>

#include "core/error.hpp"
#include "estimator/bordered_chain.hpp"
#include "estimator/gauss_markov_prior.hpp"
#include "estimator/sliding_window_impl.hpp"

namespace statebench::est {
namespace {

// r = (x - 0) / sigma on a scalar block.
class GlobalZeroPrior final : public ceres::SizedCostFunction<1, 1> {
 public:
  explicit GlobalZeroPrior(double sigma) : inv_sigma_(1.0 / sigma) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    residuals[0] = inv_sigma_ * parameters[0][0];
    if (jacobians != nullptr && jacobians[0] != nullptr) jacobians[0][0] = inv_sigma_;
    return true;
  }

 private:
  const double inv_sigma_;
};

}  // namespace

int SlidingWindowSmoother::AddGlobal(const std::string& name, double prior_sigma,
                                     double max_abs, std::optional<double> correlation_time_s) {
  Impl& m = *impl_;
  if (!initialized()) throw InputError("sliding window smoother: global '" + name + "' before initialization");
  if (!(prior_sigma > 0.0) || !std::isfinite(prior_sigma) || !(max_abs > 0.0)) {
    throw InputError("global '" + name + "': prior sigma and bound must be positive");
  }
  if (correlation_time_s && !(*correlation_time_s > 0.0 && std::isfinite(*correlation_time_s))) {
    throw InputError("global '" + name + "': correlation time must be positive");
  }
  if (m.options.solver == WindowSolver::kCeres && m.options.keep_all_states) {
    throw InputError("global '" + name + "': not with the Ceres solver and the batch store");
  }
  Impl::Global g{name, max_abs, std::make_unique<double>(0.0), prior_sigma, 0, prior_sigma,
                 correlation_time_s.value_or(0.0)};
  if (m.problem) m.problem->AddParameterBlock(g.value.get(), 1);
  // Anchored at the oldest state: the prior enters the marginalisation prior when it leaves.
  Impl::Node& anchor = *m.states.front();
  double* block = g.value.get();
  m.globals.push_back(std::move(g));
  m.AddFactor(anchor, Impl::FactorKind::kGlobalPrior, new GlobalZeroPrior(prior_sigma), nullptr,
              {block});
  return static_cast<int>(m.globals.size()) - 1;
}

void SlidingWindowSmoother::SetImuTriad(std::vector<ImuTriadGlobal> terms) {
  for (const ImuTriadGlobal& t : terms) {
    if (!impl_->KnownGlobal(t.global)) {
      throw InputError("sliding window smoother: imu triad term on an unknown global index");
    }
  }
  impl_->imu_triad = std::move(terms);
}

std::vector<SlidingWindowSmoother::GlobalEstimate> SlidingWindowSmoother::Globals() const {
  std::vector<GlobalEstimate> out;
  for (std::size_t i = 0; i < impl_->globals.size(); ++i) {
    out.push_back(Global(static_cast<int>(i)));
  }
  return out;
}

SlidingWindowSmoother::GlobalEstimate SlidingWindowSmoother::Global(int index) const {
  if (!impl_->KnownGlobal(index)) {
    throw InputError("sliding window smoother: unknown global index");
  }
  const Impl::Global& g = impl_->globals[static_cast<std::size_t>(index)];
  return {g.name, *g.value, g.sigma, g.num_clamped};
}

Mat15 SlidingWindowSmoother::Impl::UpdateGlobals(const ChainSystem* system) {
  ChainSystem linearized;
  if (system == nullptr) {
    const std::vector<double*> blocks = GlobalBlocks();
    LinearizeChain(Chain(), manifold, &linearized, blocks);
    system = &linearized;
  }
  const BorderedChainMarginals marginals = MarginalsOfBorderedChain(*system);
  for (std::size_t i = 0; i < globals.size(); ++i) {
    Global& g = globals[i];
    const auto at = static_cast<Eigen::Index>(i);
    g.sigma = std::sqrt(std::max(marginals.global_covariance(at, at), 0.0));
    if (std::abs(*g.value) > g.max_abs) {
      *g.value = std::clamp(*g.value, -g.max_abs, g.max_abs);
      ++g.num_clamped;
    }
  }
  return marginals.newest_information;
}

void SlidingWindowSmoother::Impl::CarryGaussMarkovGlobals(double dt_s, LinearSystem* kept) {
  std::vector<GaussMarkovStep> steps;
  for (std::size_t i = 0; i < globals.size(); ++i) {
    Global& g = globals[i];
    if (g.correlation_time_s <= 0.0) continue;
    const double rho = std::exp(-dt_s / g.correlation_time_s);
    *g.value *= rho;
    steps.push_back({static_cast<Eigen::Index>(15 + i), rho,
                     g.prior_sigma * g.prior_sigma * (1.0 - rho * rho)});
  }
  CarryGaussMarkovPrior(steps, kept);
}

}  // namespace statebench::est
