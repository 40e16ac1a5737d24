// SlidingWindowSmoother::SolveBatch: the full-batch smoother over the batch store and the window
// (sliding_window_smoother.hpp).
#include "core/error.hpp"
#include "estimator/bordered_chain.hpp"
#include "estimator/chain_levenberg_marquardt.hpp"
#include "estimator/gauss_markov_segments.hpp"
#include "estimator/sliding_window_impl.hpp"

namespace statebench::est {
namespace {

// Segments per Gauss-Markov global (each a global of the bordered solve: its cost grows with
// their number squared): 32 keeps a tenth of a 100 s correlation time up to a 320 s run.
constexpr int kMaxGaussMarkovSegments = 32;

}  // namespace

SmootherBatch SlidingWindowSmoother::SolveBatch(int max_iterations) {
  Impl& m = *impl_;
  if (!m.options.keep_all_states) {
    throw InputError("sliding window smoother: SolveBatch without keep_all_states");
  }
  if (!initialized()) throw InputError("sliding window smoother: SolveBatch before Initialize");
  // Every state, oldest first: the store, then the window. The first state keeps its initial
  // prior; the window's marginalisation prior (on its oldest state when states left) does not
  // enter: the factors it summarised are in the store.
  std::vector<Impl::Node*> nodes;
  for (const auto& n : m.kept) nodes.push_back(n.get());
  for (const auto& n : m.states) nodes.push_back(n.get());
  std::vector<ChainState> chain(nodes.size());
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const std::vector<double*> blocks = nodes[k]->Blocks();
    std::copy(blocks.begin(), blocks.end(), chain[k].blocks.begin());
    for (const Impl::Factor& f : nodes[k]->factors) {
      if (f.kind == Impl::FactorKind::kPrior && k > 0) continue;
      chain[k].factors.push_back(&f.record);
    }
  }
  // The globals (time offsets, mount corrections, a receiver's slow error) are solved with the
  // states; their initial priors are in the store, anchored where they were created. A
  // Gauss-Markov global becomes one value per segment of the run (gauss_markov_segments.hpp).
  std::vector<double*> globals = m.GlobalBlocks();
  std::vector<TimeNs> times;
  for (const Impl::Node* n : nodes) times.push_back(n->t_ns);
  std::vector<GaussMarkovGlobal> processes;
  for (const Impl::Global& g : m.globals) {
    if (g.correlation_time_s > 0.0) {
      processes.push_back({g.value.get(), g.prior_sigma, g.correlation_time_s});
    }
  }
  const GaussMarkovSegments segments(times, processes, kMaxGaussMarkovSegments, &chain, &globals);
  const ChainSolveSummary solve = SolveChainLevenbergMarquardt(
      chain, m.manifold, ChainSolveOptions{max_iterations, m.options.initial_trust_region_radius},
      globals);
  m.newest_information.reset();  // the window's values changed
  SmootherBatch out;
  out.usable = solve.usable;
  out.iterations = solve.iterations;
  out.initial_cost = solve.initial_cost;
  out.final_cost = solve.final_cost;
  for (const Impl::Node* n : nodes) out.states.push_back(n->State());
  // Each state's marginal with the globals' uncertainty in it (a receiver's slow error is not
  // known better than its prior where no other measurement separates it from the position).
  if (solve.usable && solve.has_system) {
    out.covariances = BorderedChainMarginalCovariances(solve.system);
  }
  out.imu = m.all_imu;
  return out;
}

}  // namespace statebench::est
