// SlidingWindowSmoother's IMU between states: the preintegration from a state (the newest one's
// kept as the samples arrive), new states with their IMU and bias factors, the raw gyro at a
// stamp (sliding_window_impl.hpp).
#include <iterator>
#include <span>
#include <utility>
#include <vector>

#include "estimator/bias_random_walk_factor.hpp"
#include "estimator/imu_factor.hpp"
#include "estimator/imu_triad_factor.hpp"
#include "estimator/sliding_window_impl.hpp"

namespace statebench::est {

ImuPreintegration SlidingWindowSmoother::Impl::Preintegrate(const Node& from,
                                                            TimeNs t_end_ns) const {
  if (const ImuPreintegration* p = FromNewestTo(from, t_end_ns)) return *p;
  return PreintegrateSamples(from, t_end_ns);
}

ImuPreintegration SlidingWindowSmoother::Impl::PreintegrateSamples(const Node& from,
                                                                   TimeNs t_end_ns) const {
  const NavState s = from.State();
  return ImuPreintegration::FromSamples(std::span<const ImuSample>(imu), from.t_ns, t_end_ns,
                                        options.imu_noise, ImuBias{s.gyro_bias, s.accel_bias});
}

const ImuPreintegration* SlidingWindowSmoother::Impl::FromNewestTo(const Node& from,
                                                                   TimeNs t_end_ns) const {
  if (!from_newest || &from != states.back().get() || from_newest->end_ns() != t_end_ns ||
      !FromNewestCurrent()) {
    return nullptr;
  }
  return &*from_newest;
}

bool SlidingWindowSmoother::Impl::FromNewestCurrent() const {
  const Node& n = *states.back();
  const ImuBias bias{Eigen::Map<const Vec3>(n.x.bias.data()),
                     Eigen::Map<const Vec3>(n.x.bias.data() + 3)};
  return from_newest->StartsAs(n.t_ns, options.imu_noise, bias);
}

void SlidingWindowSmoother::Impl::ExtendFromNewest() {
  const TimeNs t_ns = imu.back().header.stamp_ns;
  if (from_newest && imu.size() >= 2 &&
      from_newest->end_ns() == imu[imu.size() - 2].header.stamp_ns && FromNewestCurrent()) {
    from_newest->Integrate(imu.back());
  } else {
    from_newest = PreintegrateSamples(*states.back(), t_ns);
  }
}

void SlidingWindowSmoother::Impl::CreateState(TimeNs t_ns) {
  Node& prev = *states.back();
  ImuPreintegration pim = FromNewestTo(prev, t_ns) != nullptr ? std::move(*from_newest)
                                                              : PreintegrateSamples(prev, t_ns);
  from_newest.reset();
  auto node = std::make_unique<Node>();
  node->t_ns = t_ns;
  node->x = StateParameters::FromNavState(pim.Predict(prev.State()));
  AddBlocks(*node);
  const double dt = pim.dt();
  std::vector<double*> blocks{
      prev.x.q_world_imu.data(),  prev.x.p_world.data(),  prev.x.v_world.data(), prev.x.bias.data(),
      node->x.q_world_imu.data(), node->x.p_world.data(), node->x.v_world.data()};
  if (imu_triad.empty()) {
    AddFactor(prev, FactorKind::kImu, new ImuFactor(std::move(pim)), nullptr, blocks);
  } else {
    std::vector<ImuTriadTerm> terms;
    for (const ImuTriadGlobal& g : imu_triad) {
      terms.push_back(g.term);
      blocks.push_back(globals[static_cast<std::size_t>(g.global)].value.get());
    }
    AddFactor(prev, FactorKind::kImu, new ImuTriadFactor(std::move(pim), std::move(terms)), nullptr,
              blocks);
  }
  AddFactor(prev, FactorKind::kBias, new BiasRandomWalkFactor(options.imu_noise, dt), nullptr,
            {prev.x.bias.data(), node->x.bias.data()});
  states.push_back(std::move(node));
}

Vec3 SlidingWindowSmoother::Impl::GyroAt(TimeNs t_ns) const {
  auto it = std::lower_bound(imu.begin(), imu.end(), t_ns,
                             [](const ImuSample& s, TimeNs t) { return s.header.stamp_ns < t; });
  if (it == imu.end()) return imu.back().gyro;
  if (it->header.stamp_ns == t_ns || it == imu.begin()) return it->gyro;
  return InterpolateImuSample(*std::prev(it), *it, t_ns).gyro;
}

}  // namespace statebench::est
