// Internal to SlidingWindowSmoother (not part of the estimator's API): the window of states as
// Ceres parameter blocks, the factors anchored at each state, the raw IMU buffer they are
// preintegrated from, the factors waiting for the IMU, marginalisation of the oldest state and
// the newest state's information.
#pragma once

#include <ceres/problem.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>
#include <initializer_list>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "estimator/bias_random_walk_factor.hpp"
#include "estimator/bordered_chain.hpp"
#include "estimator/bordered_marginalization_prior.hpp"
#include "estimator/chain_system.hpp"
#include "estimator/dual_antenna_factor.hpp"
#include "estimator/gnss_error_state_factor.hpp"
#include "estimator/gnss_propagated_position_factor.hpp"
#include "estimator/gnss_time_offset_factor.hpp"
#include "estimator/imu_factor.hpp"
#include "estimator/imu_preintegration.hpp"
#include "estimator/imu_triad_factor.hpp"
#include "estimator/linear_system.hpp"
#include "estimator/marginalization_prior.hpp"
#include "estimator/sliding_window_smoother.hpp"
#include "estimator/so3_manifold.hpp"
#include "estimator/sqrt_information.hpp"
#include "estimator/state_parameters.hpp"
#include "estimator/zero_rate_factor.hpp"

namespace statebench::est {

struct SlidingWindowSmoother::Impl {
  static constexpr std::ptrdiff_t kPreintegrationContextSamples = 3;

  enum class FactorKind {
    kPrior,
    kImu,
    kBias,
    kGnss,
    kHeading,
    kRelativePose,
    kVelocity,
    kZeroRate,
    kGlobalPrior  // on a global alone (the time offset's initial prior)
  };

  // The node owns its factors' cost and loss functions (the problem does not): a state that
  // leaves the window keeps them when the batch store holds it (keep_all_states).
  struct Factor {
    FactorKind kind;
    FactorRecord record;
    ceres::ResidualBlockId id = nullptr;  // null without the Ceres solver
    std::unique_ptr<const ceres::CostFunction> cost_owner;
    std::unique_ptr<const ceres::LossFunction> loss_owner;
  };

  // One state; held by unique_ptr so the parameter block addresses never move. Factors are
  // anchored at the oldest state they touch, so marginalising a state involves exactly its own.
  struct Node {
    TimeNs t_ns = 0;
    StateParameters x;
    std::vector<Factor> factors;

    std::vector<double*> Blocks() {
      return {x.q_world_imu.data(), x.p_world.data(), x.v_world.data(), x.bias.data()};
    }
    NavState State() const { return x.ToNavState(t_ns); }
  };

  explicit Impl(const SlidingWindowOptions& o)
      : options(o),
        problem(o.solver == WindowSolver::kCeres
                    ? std::make_unique<ceres::Problem>(ProblemOptions())
                    : nullptr) {}

  static ceres::Problem::Options ProblemOptions() {
    ceres::Problem::Options p;
    p.enable_fast_removal = true;
    p.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;       // one shared manifold
    p.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;  // Factor owns them
    p.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    return p;
  }

  SlidingWindowOptions options;
  RightQuaternionManifold manifold;
  // The window as Ceres sees it, kept only for the Ceres solver: the chain solver reads the
  // nodes' factor records, and adding and removing Ceres's residual blocks (hash sets, an error
  // message formatted for every removal) cost it about 4 % of a plain IMU + GNSS run.
  std::unique_ptr<ceres::Problem> problem;
  std::deque<std::unique_ptr<Node>> states;
  std::vector<ImuSample> imu;  // raw samples from the oldest state's stamp on
  // The newest state's preintegration to the newest sample, at the state's values when it was
  // integrated: the next IMU factor and the factors on the newest state at the newest sample's
  // stamp (velocity, GNSS) share its steps instead of each integrating them again.
  std::optional<ImuPreintegration> from_newest;
  int samples_since_state = 0;
  // A factor whose measurement is newer than the newest IMU sample: it waits until the IMU
  // reaches ready_ns, then hangs on the latest state at or before anchor_ns.
  struct Pending {
    FactorKind kind;
    TimeNs anchor_ns;
    TimeNs ready_ns;
    std::function<void(Node& anchor)> attach;
  };
  std::vector<Pending> pending;
  std::vector<NavState> marginalized;
  // The batch store (options.keep_all_states): every state that left the window, oldest first,
  // with its factors but without its marginalisation prior, and every IMU sample since the
  // first state (the window's buffer forgets them).
  std::vector<std::unique_ptr<Node>> kept;
  std::vector<ImuSample> all_imu;  // keep_all_states or keep_lagged_states
  // The lagged store (options.keep_lagged_states): states that left the window, oldest first,
  // and their marginal covariances in the window they left.
  std::vector<NavState> lagged_states;
  std::vector<Mat15> lagged_covariances;
  int num_dropped = 0;   // pending measurements found too old, since the last Solve
  int num_left_out = 0;  // factors non-finite at marginalisation (Linearize), since the last Solve
  // The newest state's information from the last chain solve's final linearisation; cleared by
  // any change of the window's factors.
  std::optional<Mat15> newest_information;
  // Global scalars (GNSS time offsets, mount rotation corrections): values at stable addresses, in
  // the border's order.
  struct Global {
    std::string name;
    double max_abs = 0.0;
    std::unique_ptr<double> value;
    double sigma = 0.0;   // marginal, from the last solve (0 before one)
    int num_clamped = 0;  // solves after which it was held at +-max_abs
    double prior_sigma = 0.0;
    double correlation_time_s = 0.0;  // > 0: Gauss-Markov (AddGlobal), else constant
  };
  std::vector<Global> globals;
  // The IMU factors created from now on carry these triad errors (SetImuTriad).
  std::vector<ImuTriadGlobal> imu_triad;

  bool KnownGlobal(int index) const {
    return index >= 0 && index < static_cast<int>(globals.size());
  }
  std::vector<double*> GlobalBlocks() const {
    std::vector<double*> out;
    for (const Global& g : globals) out.push_back(g.value.get());
    return out;
  }
  // After a usable solve: the globals' marginal sigmas from the solve's final linearisation
  // (`system`, or a new one when null), then each global held within its bound. Returns the
  // newest state's marginal information of that linearisation.
  Mat15 UpdateGlobals(const ChainSystem* system);

  void AddBlocks(Node& n) {
    if (!problem) return;
    problem->AddParameterBlock(n.x.q_world_imu.data(), 4, &manifold);
    problem->AddParameterBlock(n.x.p_world.data(), 3);
    problem->AddParameterBlock(n.x.v_world.data(), 3);
    problem->AddParameterBlock(n.x.bias.data(), 6);
  }

  void AddFactor(Node& anchor, FactorKind kind, ceres::CostFunction* cost,
                 ceres::LossFunction* loss, std::vector<double*> blocks) {
    newest_information.reset();
    const ceres::ResidualBlockId id =
        problem ? problem->AddResidualBlock(cost, loss, blocks) : nullptr;
    anchor.factors.push_back({kind, FactorRecord{cost, loss, std::move(blocks)}, id,
                              std::unique_ptr<const ceres::CostFunction>(cost),
                              std::unique_ptr<const ceres::LossFunction>(loss)});
  }

  // Latest state with t_ns <= t, or nullptr if t is before the window.
  Node* Anchor(TimeNs t_ns) {
    if (states.empty() || t_ns < states.front()->t_ns) return nullptr;
    auto it = std::upper_bound(states.begin(), states.end(), t_ns,
                               [](TimeNs t, const auto& n) { return t < n->t_ns; });
    return std::prev(it)->get();
  }

  ImuPreintegration Preintegrate(const Node& from, TimeNs t_end_ns) const {
    if (const ImuPreintegration* p = FromNewestTo(from, t_end_ns)) return *p;
    return PreintegrateSamples(from, t_end_ns);
  }

  ImuPreintegration PreintegrateSamples(const Node& from, TimeNs t_end_ns) const {
    const NavState s = from.State();
    return ImuPreintegration::FromSamples(std::span<const ImuSample>(imu), from.t_ns, t_end_ns,
                                          options.imu_noise, ImuBias{s.gyro_bias, s.accel_bias});
  }

  // from_newest, when it is the preintegration FromSamples would give from `from` to t_end_ns:
  // `from` is the newest state, at the values and noise it was integrated with.
  const ImuPreintegration* FromNewestTo(const Node& from, TimeNs t_end_ns) const {
    if (!from_newest || &from != states.back().get() || from_newest->end_ns() != t_end_ns ||
        !FromNewestCurrent()) {
      return nullptr;
    }
    return &*from_newest;
  }

  bool FromNewestCurrent() const {
    const Node& n = *states.back();
    const ImuBias bias{Eigen::Map<const Vec3>(n.x.bias.data()),
                       Eigen::Map<const Vec3>(n.x.bias.data() + 3)};
    return from_newest->StartsAs(n.t_ns, options.imu_noise, bias);
  }

  // After a sample joined the buffer: from_newest extended to it (the same integration steps as
  // FromSamples from the newest state, as ImuRateOutput's cursor), or integrated again from the
  // newest state when that moved (a solve), the noise changed or a sample was skipped.
  void ExtendFromNewest() {
    const TimeNs t_ns = imu.back().header.stamp_ns;
    if (from_newest && imu.size() >= 2 &&
        from_newest->end_ns() == imu[imu.size() - 2].header.stamp_ns && FromNewestCurrent()) {
      from_newest->Integrate(imu.back());
    } else {
      from_newest = PreintegrateSamples(*states.back(), t_ns);
    }
  }

  void CreateState(TimeNs t_ns) {
    Node& prev = *states.back();
    ImuPreintegration pim = FromNewestTo(prev, t_ns) != nullptr ? std::move(*from_newest)
                                                                : PreintegrateSamples(prev, t_ns);
    from_newest.reset();
    auto node = std::make_unique<Node>();
    node->t_ns = t_ns;
    node->x = StateParameters::FromNavState(pim.Predict(prev.State()));
    AddBlocks(*node);
    const double dt = pim.dt();
    std::vector<double*> blocks{prev.x.q_world_imu.data(),  prev.x.p_world.data(),
                                prev.x.v_world.data(),      prev.x.bias.data(),
                                node->x.q_world_imu.data(), node->x.p_world.data(),
                                node->x.v_world.data()};
    if (imu_triad.empty()) {
      AddFactor(prev, FactorKind::kImu, new ImuFactor(std::move(pim)), nullptr, blocks);
    } else {
      std::vector<ImuTriadTerm> terms;
      for (const ImuTriadGlobal& g : imu_triad) {
        terms.push_back(g.term);
        blocks.push_back(globals[static_cast<std::size_t>(g.global)].value.get());
      }
      AddFactor(prev, FactorKind::kImu, new ImuTriadFactor(std::move(pim), std::move(terms)),
                nullptr, blocks);
    }
    AddFactor(prev, FactorKind::kBias, new BiasRandomWalkFactor(options.imu_noise, dt), nullptr,
              {prev.x.bias.data(), node->x.bias.data()});
    states.push_back(std::move(node));
  }

  void AttachGnss(Node& anchor, const GnssPositionEnu& fix, const Vec3& p_imu_antenna,
                  std::optional<int> time_offset, std::optional<std::array<int, 3>> error) {
    std::vector<double*> blocks{anchor.x.q_world_imu.data(), anchor.x.p_world.data(),
                                anchor.x.v_world.data(), anchor.x.bias.data()};
    std::unique_ptr<ceres::CostFunction> cost;
    Mat3 S;
    if (time_offset) {
      auto f = std::make_unique<GnssTimeOffsetFactor>(
          fix.p_enu, fix.covariance, p_imu_antenna, Preintegrate(anchor, fix.header.stamp_ns),
          anchor.State().q_world_imu, GyroAt(fix.header.stamp_ns));
      S = f->sqrt_information();
      cost = std::move(f);
      blocks.push_back(globals[*time_offset].value.get());
    } else {
      auto f = std::make_unique<GnssPropagatedPositionFactor>(
          fix.p_enu, fix.covariance, p_imu_antenna, Preintegrate(anchor, fix.header.stamp_ns),
          anchor.State().q_world_imu);
      S = f->sqrt_information();
      cost = std::move(f);
    }
    if (error) {
      cost = std::make_unique<GnssErrorStateFactor>(std::move(cost), S);
      for (int index : *error) blocks.push_back(globals[index].value.get());
    }
    AddFactor(anchor, FactorKind::kGnss, cost.release(),
              options.gnss_kernel.MakeLossFunction().release(), std::move(blocks));
  }

  void AttachHeading(Node& anchor, const DualAntennaHeading& heading, const Vec3& p_imu_main,
                     const Vec3& p_imu_aux, std::optional<std::array<int, 2>> baseline) {
    const Quat dR = Preintegrate(anchor, heading.header.stamp_ns).delta_q();
    if (!baseline) {
      AddFactor(anchor, FactorKind::kHeading,
                DualAntennaFactor::Create(heading, p_imu_main, p_imu_aux, dR),
                options.heading_kernel.MakeLossFunction().release(), {anchor.x.q_world_imu.data()});
      return;
    }
    AddFactor(anchor, FactorKind::kHeading,
              DualAntennaFactor::CreateWithBaselineCorrection(heading, p_imu_main, p_imu_aux, dR),
              options.heading_kernel.MakeLossFunction().release(),
              {anchor.x.q_world_imu.data(), globals[(*baseline)[0]].value.get(),
               globals[(*baseline)[1]].value.get()});
  }

  // InputError unless the mount's indices are globals (pitch and yaw required; roll only where
  // allowed).
  void CheckMount(const SlidingWindowSmoother::MountCorrection& mount, const char* what,
                  bool roll_allowed) const {
    if (!KnownGlobal(mount.pitch) || !KnownGlobal(mount.yaw) ||
        (mount.roll != -1 && (!roll_allowed || !KnownGlobal(mount.roll)))) {
      throw InputError(std::string(what) + ": unknown mount correction index");
    }
  }
  // The blocks of a mount correction's estimated axes (roll, pitch, yaw order), appended.
  void AppendMountBlocks(const std::optional<SlidingWindowSmoother::MountCorrection>& mount,
                         std::vector<double*>* blocks) const {
    if (!mount) return;
    for (int index : {mount->roll, mount->pitch, mount->yaw}) {
      if (index >= 0) blocks->push_back(globals[index].value.get());
    }
  }

  struct RelativePose {
    TimeNs t1_ns;
    TimeNs t2_ns;
    RelativePoseMeasurement m;
    RobustKernel kernel;
    std::optional<SlidingWindowSmoother::MountCorrection> mount;
  };
  void AttachRelativePose(Node& a, const RelativePose& r) {
    // The state after a, when it is not after t2, carries t2 (neighbouring states only).
    Node* b = nullptr;
    for (std::size_t k = 0; k + 1 < states.size(); ++k) {
      if (states[k].get() == &a) {
        if (states[k + 1]->t_ns <= r.t2_ns) b = states[k + 1].get();
        break;
      }
    }
    MountAxes axes;
    if (r.mount) axes = {r.mount->roll >= 0, r.mount->pitch >= 0, r.mount->yaw >= 0};
    ceres::LossFunction* loss = r.kernel.MakeLossFunction().release();
    std::vector<double*> blocks = a.Blocks();
    ceres::CostFunction* cost = nullptr;
    if (b == nullptr) {
      cost = CreateRelativePoseFactorOneAnchor(r.m, Preintegrate(a, r.t1_ns),
                                               Preintegrate(a, r.t2_ns), axes);
    } else {
      for (double* block : b->Blocks()) blocks.push_back(block);
      cost =
          CreateRelativePoseFactor(r.m, Preintegrate(a, r.t1_ns), Preintegrate(*b, r.t2_ns), axes);
    }
    AppendMountBlocks(r.mount, &blocks);
    AddFactor(a, FactorKind::kRelativePose, cost, loss, std::move(blocks));
  }

  // Raw gyro at t_ns, linearly interpolated in the buffer (which covers the window).
  Vec3 GyroAt(TimeNs t_ns) const {
    auto it = std::lower_bound(imu.begin(), imu.end(), t_ns,
                               [](const ImuSample& s, TimeNs t) { return s.header.stamp_ns < t; });
    if (it == imu.end()) return imu.back().gyro;
    if (it->header.stamp_ns == t_ns || it == imu.begin()) return it->gyro;
    return InterpolateImuSample(*std::prev(it), *it, t_ns).gyro;
  }

  void AttachVelocity(Node& a, TimeNs t_ns, BodyVelocityMeasurement m, const RobustKernel& kernel,
                      std::optional<SlidingWindowSmoother::MountCorrection> mount) {
    m.gyro_raw = GyroAt(t_ns);
    std::vector<double*> blocks{a.x.q_world_imu.data(), a.x.v_world.data(), a.x.bias.data()};
    AppendMountBlocks(mount, &blocks);  // pitch and yaw (no roll: CheckMount)
    ceres::CostFunction* cost =
        mount ? CreateMountCorrectedBodyVelocityFactor(m, Preintegrate(a, t_ns))
              : CreateBodyVelocityFactor(m, Preintegrate(a, t_ns));
    AddFactor(a, FactorKind::kVelocity, cost, kernel.MakeLossFunction().release(),
              std::move(blocks));
  }

  // A factor at its anchor now, or pending until the IMU reaches ready_ns; kTooOld (and
  // nothing added) when anchor_ns is before the window.
  AddResult Add(Pending p) {
    Node* anchor = Anchor(p.anchor_ns);
    if (anchor == nullptr) return AddResult::kTooOld;
    if (p.ready_ns > imu.back().header.stamp_ns) {
      pending.push_back(std::move(p));
      return AddResult::kPending;
    }
    p.attach(*anchor);
    return AddResult::kAdded;
  }

  // Attaches the pending factors the IMU has reached (or drops those that fell out), kind by
  // kind in a fixed order.
  void FlushPending() {
    const TimeNs newest = imu.back().header.stamp_ns;
    for (FactorKind kind : {FactorKind::kGnss, FactorKind::kHeading, FactorKind::kVelocity,
                            FactorKind::kRelativePose, FactorKind::kZeroRate}) {
      std::erase_if(pending, [&](const Pending& p) {
        if (p.kind != kind || p.ready_ns > newest) return false;
        if (Node* anchor = Anchor(p.anchor_ns)) {
          p.attach(*anchor);
        } else {
          ++num_dropped;  // the window moved past it while it waited
        }
        return true;
      });
    }
  }

  // The parameter blocks of neighbouring states in the order of their factors' Jacobians, then
  // the globals.
  BlockLayout Layout(std::initializer_list<Node*> nodes) const {
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

  // The prior the Schur complement `kept` ((15 + G) dims: next's tangent, then the globals)
  // leaves on `next` and the globals.
  void AddMarginalizationPrior(Node& next, const LinearSystem& kept) {
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

  // `linearized`: the old state's factors already linearised at the current values (the chain
  // solve's final system, chain_system.hpp), else they are linearised here.
  void MarginalizeOldest(const LinearSystem* linearized = nullptr) {
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

  // The Gauss-Markov globals over dt (sliding_window_globals.cpp): their values decay and the
  // prior `kept` ((15 + G) dims) gains their process noise.
  void CarryGaussMarkovGlobals(double dt_s, LinearSystem* kept);

  // Into the batch store; the marginalisation prior goes (the batch has every factor it
  // summarised), the first state's initial prior stays.
  void Keep(std::unique_ptr<Node> node) {
    if (!kept.empty()) {
      std::erase_if(node->factors, [](const Factor& f) { return f.kind == FactorKind::kPrior; });
    }
    kept.push_back(std::move(node));
  }

  // The window as chain_system.hpp sees it: each state's blocks and the factors anchored there.
  std::vector<ChainState> Chain() const {
    std::vector<ChainState> chain(states.size());
    for (std::size_t k = 0; k < states.size(); ++k) {
      const std::vector<double*> blocks = states[k]->Blocks();
      std::copy(blocks.begin(), blocks.end(), chain[k].blocks.begin());
      for (const Factor& f : states[k]->factors) chain[k].factors.push_back(&f.record);
    }
    return chain;
  }

  // Every window state's marginal covariance at the current values (NaN when a factor does not
  // evaluate: no covariance to vouch for).
  std::vector<Mat15> WindowMarginals() const {
    ChainSystem system;
    if (!LinearizeChain(Chain(), manifold, &system)) {
      return std::vector<Mat15>(states.size(),
                                Mat15::Constant(std::numeric_limits<double>::quiet_NaN()));
    }
    return ChainMarginalCovariances(system);
  }

  Mat15 NewestInformation() const {
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
};

}  // namespace statebench::est
