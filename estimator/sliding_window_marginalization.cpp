// SlidingWindowSmoother's marginalisation of the oldest state into a prior on the next (and the
// globals), the batch store, and the window's marginal covariances and newest information
// (sliding_window_impl.hpp).
#include <algorithm>
#include <limits>
#include <utility>
#include <vector>

#include "estimator/bordered_chain.hpp"
#include "estimator/bordered_marginalization_prior.hpp"
#include "estimator/marginalization_prior.hpp"
#include "estimator/sliding_window_impl.hpp"

namespace statebench::est {

BlockLayout SlidingWindowSmoother::Impl::Layout(std::initializer_list<Node*> nodes) const {
  BlockLayout layout;
  for (Node* n : nodes) {
    const auto blocks = n->Blocks();
    layout.Add(blocks[0], 4, &manifold);
    layout.Add(blocks[1], 3, nullptr);
    layout.Add(blocks[2], 3, nullptr);
    layout.Add(blocks[3], 6, nullptr);
  }
  for (const Global& g : globals) layout.Add(g.value.get(), 1, nullptr);
  return layout;
}

void SlidingWindowSmoother::Impl::AddMarginalizationPrior(Node& next, const LinearSystem& kept) {
  if (globals.empty()) {
    AddFactor(next, FactorKind::kPrior, new MarginalizationPrior(next.x, kept.H, kept.g), nullptr,
              next.Blocks());
    return;
  }
  Eigen::VectorXd values(globals.size());
  std::vector<double*> blocks = next.Blocks();
  for (std::size_t i = 0; i < globals.size(); ++i) {
    values(static_cast<Eigen::Index>(i)) = *globals[i].value;
    blocks.push_back(globals[i].value.get());
  }
  AddFactor(next, FactorKind::kPrior,
            new BorderedMarginalizationPrior(next.x, values, kept.H, kept.g), nullptr,
            std::move(blocks));
}

void SlidingWindowSmoother::Impl::MarginalizeOldest(const LinearSystem* linearized) {
  Node& old = *states[0];
  Node& next = *states[1];
  LinearSystem system;
  if (linearized != nullptr) {
    system = *linearized;
  } else {
    const BlockLayout layout = Layout({&old, &next});
    std::vector<const FactorRecord*> records;
    for (const Factor& f : old.factors) records.push_back(&f.record);
    Linearize(records, layout, &system);
    num_left_out += system.num_skipped;
  }
  LinearSystem kept = SchurComplement(system, 15);
  CarryGaussMarkovGlobals(ToSeconds(next.t_ns - old.t_ns), &kept);

  AddMarginalizationPrior(next, kept);
  // The old state's factors go first, in the order they were added: removing a parameter
  // block removes its residual blocks in the order of a hash set of pointers, which would
  // reorder the rest of the problem (and the floating-point sums of every later solve) by
  // heap addresses.
  if (problem) {
    for (const Factor& f : old.factors) problem->RemoveResidualBlock(f.id);
    for (double* block : old.Blocks()) problem->RemoveParameterBlock(block);
  }
  marginalized.push_back(old.State());
  if (options.keep_all_states) Keep(std::move(states.front()));
  states.pop_front();
  const TimeNs t_oldest = states.front()->t_ns;
  // Keep the samples before the oldest state that preintegration from it uses as context
  // for its cubic interpolant (ImuPreintegration::FromSamples).
  auto first_kept =
      std::lower_bound(imu.begin(), imu.end(), t_oldest,
                       [](const ImuSample& s, TimeNs t) { return s.header.stamp_ns < t; });
  first_kept -= std::min<std::ptrdiff_t>(kPreintegrationContextSamples, first_kept - imu.begin());
  imu.erase(imu.begin(), first_kept);
}

void SlidingWindowSmoother::Impl::Keep(std::unique_ptr<Node> node) {
  if (!kept.empty()) {
    std::erase_if(node->factors, [](const Factor& f) { return f.kind == FactorKind::kPrior; });
  }
  kept.push_back(std::move(node));
}

std::vector<ChainState> SlidingWindowSmoother::Impl::Chain() const {
  std::vector<ChainState> chain(states.size());
  for (std::size_t k = 0; k < states.size(); ++k) {
    const std::vector<double*> blocks = states[k]->Blocks();
    std::copy(blocks.begin(), blocks.end(), chain[k].blocks.begin());
    for (const Factor& f : states[k]->factors) chain[k].factors.push_back(&f.record);
  }
  return chain;
}

std::vector<Mat15> SlidingWindowSmoother::Impl::WindowMarginals() const {
  ChainSystem system;
  if (!LinearizeChain(Chain(), manifold, &system, GlobalBlocks())) {
    return std::vector<Mat15>(states.size(),
                              Mat15::Constant(std::numeric_limits<double>::quiet_NaN()));
  }
  return BorderedChainMarginalCovariances(system);
}

Mat15 SlidingWindowSmoother::Impl::NewestInformation() const {
  if (!globals.empty()) {
    ChainSystem system;
    const std::vector<double*> blocks = GlobalBlocks();
    LinearizeChain(Chain(), manifold, &system, blocks);
    return NewestMarginalInformation(system);
  }
  Mat15 carried = Mat15::Zero();
  for (std::size_t k = 0; k < states.size(); ++k) {
    Node& n = *states[k];
    const bool last = k + 1 == states.size();
    const BlockLayout layout = last ? Layout({&n}) : Layout({&n, states[k + 1].get()});
    std::vector<const FactorRecord*> records;
    for (const Factor& f : n.factors) records.push_back(&f.record);
    LinearSystem system;
    Linearize(records, layout, &system);
    system.H.topLeftCorner<15, 15>() += carried;
    if (last) return system.H;
    carried = SchurComplement(system, 15).H;
  }
  return carried;
}

}  // namespace statebench::est
