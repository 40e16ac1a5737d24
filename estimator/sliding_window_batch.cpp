// SlidingWindowSmoother::SolveBatch: the full-batch smoother over the batch store and the window
// (sliding_window_smoother.hpp).
#include "core/error.hpp"
#include "estimator/chain_levenberg_marquardt.hpp"
#include "estimator/sliding_window_impl.hpp"

namespace statebench::est {

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
  // The globals (time offsets) are solved with the states; their initial priors are in the
  // store, anchored where they were created.
  const std::vector<double*> globals = m.GlobalBlocks();
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
  if (solve.usable && solve.has_system) out.covariances = ChainMarginalCovariances(solve.system);
  out.imu = m.all_imu;
  return out;
}

}  // namespace statebench::est
