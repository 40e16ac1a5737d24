// Internal to SlidingWindowSmoother (not part of the estimator's API): the window of states as
// Ceres parameter blocks, the factors anchored at each state, the raw IMU buffer they are
// preintegrated from, the factors waiting for the IMU, marginalisation of the oldest state and
// the newest state's information. Its steps live beside it: the IMU between states
// (sliding_window_imu.cpp), measurements onto their state (sliding_window_factors.cpp),
// marginalisation (sliding_window_marginalization.cpp), the globals (sliding_window_globals.cpp)
// and the batch (sliding_window_batch.cpp).
#pragma once

#include <ceres/problem.h>

#include <algorithm>
#include <deque>
#include <functional>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "estimator/chain_system.hpp"
#include "estimator/imu_preintegration.hpp"
#include "estimator/imu_triad_factor.hpp"
#include "estimator/linear_system.hpp"
#include "estimator/sliding_window_smoother.hpp"
#include "estimator/so3_manifold.hpp"
#include "estimator/state_parameters.hpp"

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

  // --- The IMU between states (sliding_window_imu.cpp) ---
  // `from`'s preintegration to t_end_ns: from_newest when it is that one, else from the buffer.
  ImuPreintegration Preintegrate(const Node& from, TimeNs t_end_ns) const;
  ImuPreintegration PreintegrateSamples(const Node& from, TimeNs t_end_ns) const;
  // from_newest, when it is the preintegration FromSamples would give from `from` to t_end_ns:
  // `from` is the newest state, at the values and noise it was integrated with.
  const ImuPreintegration* FromNewestTo(const Node& from, TimeNs t_end_ns) const;
  bool FromNewestCurrent() const;
  // After a sample joined the buffer: from_newest extended to it (the same integration steps as
  // FromSamples from the newest state, as ImuRateOutput's cursor), or integrated again from the
  // newest state when that moved (a solve), the noise changed or a sample was skipped.
  void ExtendFromNewest();
  // A new newest state at t_ns, predicted from the previous one, with the IMU factor (with the
  // triad's globals when SetImuTriad gave some) and the bias random walk between the two.
  void CreateState(TimeNs t_ns);
  // Raw gyro at t_ns, linearly interpolated in the buffer (which covers the window).
  Vec3 GyroAt(TimeNs t_ns) const;

  // --- Measurements onto their anchor state (sliding_window_factors.cpp) ---
  void AttachGnss(Node& anchor, const GnssPositionEnu& fix, const Vec3& p_imu_antenna,
                  std::optional<int> time_offset, std::optional<std::array<int, 3>> error);
  void AttachHeading(Node& anchor, const DualAntennaHeading& heading, const Vec3& p_imu_main,
                     const Vec3& p_imu_aux, std::optional<std::array<int, 2>> baseline);
  // InputError unless the mount's indices are globals (pitch and yaw required; roll only where
  // allowed).
  void CheckMount(const SlidingWindowSmoother::MountCorrection& mount, const char* what,
                  bool roll_allowed) const;
  // The blocks of a mount correction's estimated axes (roll, pitch, yaw order), appended.
  void AppendMountBlocks(const std::optional<SlidingWindowSmoother::MountCorrection>& mount,
                         std::vector<double*>* blocks) const;
  struct RelativePose {
    TimeNs t1_ns;
    TimeNs t2_ns;
    RelativePoseMeasurement m;
    RobustKernel kernel;
    std::optional<SlidingWindowSmoother::MountCorrection> mount;
  };
  // On `a` and, when it is not after t2, the state after it (neighbouring states only).
  void AttachRelativePose(Node& a, const RelativePose& r);
  void AttachVelocity(Node& a, TimeNs t_ns, BodyVelocityMeasurement m, const RobustKernel& kernel,
                      std::optional<SlidingWindowSmoother::MountCorrection> mount);
  // A factor at its anchor now, or pending until the IMU reaches ready_ns; kTooOld (and
  // nothing added) when anchor_ns is before the window.
  AddResult Add(Pending p);
  // Attaches the pending factors the IMU has reached (or drops those that fell out), kind by
  // kind in a fixed order.
  void FlushPending();

  // --- Marginalisation and the window's information (sliding_window_marginalization.cpp) ---
  // The parameter blocks of neighbouring states in the order of their factors' Jacobians, then
  // the globals.
  BlockLayout Layout(std::initializer_list<Node*> nodes) const;
  // The prior the Schur complement `kept` ((15 + G) dims: next's tangent, then the globals)
  // leaves on `next` and the globals.
  void AddMarginalizationPrior(Node& next, const LinearSystem& kept);
  // `linearized`: the old state's factors already linearised at the current values (the chain
  // solve's final system, chain_system.hpp), else they are linearised here.
  void MarginalizeOldest(const LinearSystem* linearized = nullptr);
  // The Gauss-Markov globals over dt (sliding_window_globals.cpp): their values decay and the
  // prior `kept` ((15 + G) dims) gains their process noise.
  void CarryGaussMarkovGlobals(double dt_s, LinearSystem* kept);
  // Into the batch store; the marginalisation prior goes (the batch has every factor it
  // summarised), the first state's initial prior stays.
  void Keep(std::unique_ptr<Node> node);
  // The window as chain_system.hpp sees it: each state's blocks and the factors anchored there.
  std::vector<ChainState> Chain() const;
  // Every window state's marginal covariance at the current values, the globals' uncertainty
  // included (NaN when a factor does not evaluate: no covariance to vouch for).
  std::vector<Mat15> WindowMarginals() const;
  // The newest state's marginal information (the chain's, with the globals when there are any).
  Mat15 NewestInformation() const;
};

}  // namespace statebench::est
