#include "estimator/sliding_window_smoother.hpp"

#include <ceres/problem.h>
#include <ceres/solver.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <deque>
#include <span>

#include "core/error.hpp"
#include "estimator/bias_random_walk_factor.hpp"
#include "estimator/dual_antenna_factor.hpp"
#include "estimator/gnss_propagated_position_factor.hpp"
#include "estimator/imu_factor.hpp"
#include "estimator/imu_preintegration.hpp"
#include "estimator/linear_system.hpp"
#include "estimator/marginalization_prior.hpp"
#include "estimator/so3_manifold.hpp"
#include "estimator/sqrt_information.hpp"
#include "estimator/state_parameters.hpp"

namespace statebench::est {

bool SlidingWindowOptions::IsValid(std::string* why) const {
  const auto fail = [&](const std::string& message) {
    if (why != nullptr) *why = "sliding window options: " + message;
    return false;
  };
  if (!(window_s > 0.0) || !std::isfinite(window_s)) return fail("window_s must be positive");
  if (imu_samples_per_state < 1) return fail("imu_samples_per_state must be at least 1");
  if (max_iterations < 1) return fail("max_iterations must be at least 1");
  if (!(initial_trust_region_radius > 0.0)) {
    return fail("initial_trust_region_radius must be positive");
  }
  if (num_threads < 1) return fail("num_threads must be at least 1");
  for (const RobustKernel* k : {&gnss_kernel, &heading_kernel}) {
    if (k->type != RobustKernelType::kNone && (!(k->scale > 0.0) || !std::isfinite(k->scale))) {
      return fail("robust kernel scale must be positive");
    }
  }
  std::string noise_why;
  if (!imu_noise.IsValid(&noise_why)) return fail(noise_why);
  return true;
}

namespace {

constexpr std::ptrdiff_t kPreintegrationContextSamples = 3;

enum class FactorKind { kPrior, kImu, kBias, kGnss, kHeading, kRelativePose, kVelocity };

struct Factor {
  FactorKind kind;
  FactorRecord record;
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

struct PendingGnss {
  GnssPositionEnu fix;
  Vec3 p_imu_antenna;
};

struct PendingHeading {
  DualAntennaHeading heading;
  Vec3 p_imu_main;
  Vec3 p_imu_aux;
};

struct PendingRelativePose {
  TimeNs t1_ns;
  TimeNs t2_ns;
  RelativePoseMeasurement m;
  RobustKernel kernel;
};

struct PendingVelocity {
  TimeNs t_ns;
  BodyVelocityMeasurement m;
  RobustKernel kernel;
};

}  // namespace

struct SlidingWindowSmoother::Impl {
  explicit Impl(const SlidingWindowOptions& o) : options(o), problem(ProblemOptions()) {}

  static ceres::Problem::Options ProblemOptions() {
    ceres::Problem::Options p;
    p.enable_fast_removal = true;
    p.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;  // one shared manifold
    return p;
  }

  SlidingWindowOptions options;
  RightQuaternionManifold manifold;
  ceres::Problem problem;
  std::deque<std::unique_ptr<Node>> states;
  std::vector<ImuSample> imu;  // raw samples from the oldest state's stamp on
  int samples_since_state = 0;
  std::vector<PendingGnss> pending_gnss;
  std::vector<PendingHeading> pending_headings;
  std::vector<PendingRelativePose> pending_relative;
  std::vector<PendingVelocity> pending_velocity;
  std::vector<NavState> marginalized;
  int num_dropped = 0;  // pending measurements found too old, since the last Solve

  void AddBlocks(Node& n) {
    problem.AddParameterBlock(n.x.q_world_imu.data(), 4, &manifold);
    problem.AddParameterBlock(n.x.p_world.data(), 3);
    problem.AddParameterBlock(n.x.v_world.data(), 3);
    problem.AddParameterBlock(n.x.bias.data(), 6);
  }

  void AddFactor(Node& anchor, FactorKind kind, ceres::CostFunction* cost,
                 ceres::LossFunction* loss, std::vector<double*> blocks) {
    problem.AddResidualBlock(cost, loss, blocks);
    anchor.factors.push_back({kind, FactorRecord{cost, loss, std::move(blocks)}});
  }

  // Latest state with t_ns <= t, or nullptr if t is before the window.
  Node* Anchor(TimeNs t_ns) {
    if (states.empty() || t_ns < states.front()->t_ns) return nullptr;
    auto it = std::upper_bound(states.begin(), states.end(), t_ns,
                               [](TimeNs t, const auto& n) { return t < n->t_ns; });
    return std::prev(it)->get();
  }

  ImuPreintegration Preintegrate(const Node& from, TimeNs t_end_ns) const {
    const NavState s = from.State();
    return ImuPreintegration::FromSamples(std::span<const ImuSample>(imu), from.t_ns, t_end_ns,
                                          options.imu_noise, ImuBias{s.gyro_bias, s.accel_bias});
  }

  void CreateState(TimeNs t_ns) {
    Node& prev = *states.back();
    ImuPreintegration pim = Preintegrate(prev, t_ns);
    auto node = std::make_unique<Node>();
    node->t_ns = t_ns;
    node->x = StateParameters::FromNavState(pim.Predict(prev.State()));
    AddBlocks(*node);
    const double dt = pim.dt();
    AddFactor(prev, FactorKind::kImu, new ImuFactor(std::move(pim)), nullptr,
              {prev.x.q_world_imu.data(), prev.x.p_world.data(), prev.x.v_world.data(),
               prev.x.bias.data(), node->x.q_world_imu.data(), node->x.p_world.data(),
               node->x.v_world.data()});
    AddFactor(prev, FactorKind::kBias, new BiasRandomWalkFactor(options.imu_noise, dt), nullptr,
              {prev.x.bias.data(), node->x.bias.data()});
    states.push_back(std::move(node));
  }

  void AttachGnss(Node& anchor, const PendingGnss& m) {
    auto* cost = new GnssPropagatedPositionFactor(m.fix.p_enu, m.fix.covariance, m.p_imu_antenna,
                                                  Preintegrate(anchor, m.fix.header.stamp_ns),
                                                  anchor.State().q_world_imu);
    AddFactor(anchor, FactorKind::kGnss, cost, options.gnss_kernel.MakeLossFunction().release(),
              {anchor.x.q_world_imu.data(), anchor.x.p_world.data(), anchor.x.v_world.data(),
               anchor.x.bias.data()});
  }

  void AttachHeading(Node& anchor, const PendingHeading& m) {
    const Quat dR = Preintegrate(anchor, m.heading.header.stamp_ns).delta_q();
    AddFactor(anchor, FactorKind::kHeading,
              DualAntennaFactor::Create(m.heading, m.p_imu_main, m.p_imu_aux, dR),
              options.heading_kernel.MakeLossFunction().release(), {anchor.x.q_world_imu.data()});
  }

  void AttachRelativePose(Node& a, const PendingRelativePose& r) {
    // The state after a, when it is not after t2, carries t2 (neighbouring states only).
    Node* b = nullptr;
    for (std::size_t k = 0; k + 1 < states.size(); ++k) {
      if (states[k].get() == &a) {
        if (states[k + 1]->t_ns <= r.t2_ns) b = states[k + 1].get();
        break;
      }
    }
    ceres::LossFunction* loss = r.kernel.MakeLossFunction().release();
    if (b == nullptr) {
      AddFactor(a, FactorKind::kRelativePose,
                CreateRelativePoseFactorOneAnchor(r.m, Preintegrate(a, r.t1_ns),
                                                  Preintegrate(a, r.t2_ns)),
                loss, a.Blocks());
      return;
    }
    std::vector<double*> blocks = a.Blocks();
    for (double* block : b->Blocks()) blocks.push_back(block);
    AddFactor(a, FactorKind::kRelativePose,
              CreateRelativePoseFactor(r.m, Preintegrate(a, r.t1_ns), Preintegrate(*b, r.t2_ns)),
              loss, std::move(blocks));
  }

  // Raw gyro at t_ns, linearly interpolated in the buffer (which covers the window).
  Vec3 GyroAt(TimeNs t_ns) const {
    auto it = std::lower_bound(imu.begin(), imu.end(), t_ns, [](const ImuSample& s, TimeNs t) {
      return s.header.stamp_ns < t;
    });
    if (it == imu.end()) return imu.back().gyro;
    if (it->header.stamp_ns == t_ns || it == imu.begin()) return it->gyro;
    return InterpolateImuSample(*std::prev(it), *it, t_ns).gyro;
  }

  void AttachVelocity(Node& a, const PendingVelocity& v) {
    BodyVelocityMeasurement m = v.m;
    m.gyro_raw = GyroAt(v.t_ns);
    AddFactor(a, FactorKind::kVelocity, CreateBodyVelocityFactor(m, Preintegrate(a, v.t_ns)),
              v.kernel.MakeLossFunction().release(),
              {a.x.q_world_imu.data(), a.x.v_world.data(), a.x.bias.data()});
  }

  // Attaches the pending measurements the IMU has reached (or drops those that fell out).
  void FlushPending() {
    const TimeNs newest = imu.back().header.stamp_ns;
    const auto flush = [&](auto& pending, auto attach) {
      std::erase_if(pending, [&](const auto& m) {
        const TimeNs t = StampOf(m);
        if (t > newest) return false;
        if (Node* anchor = Anchor(t)) {
          attach(*anchor, m);
        } else {
          ++num_dropped;  // the window moved past it while it waited
        }
        return true;
      });
    };
    flush(pending_gnss, [&](Node& a, const PendingGnss& m) { AttachGnss(a, m); });
    flush(pending_headings, [&](Node& a, const PendingHeading& m) { AttachHeading(a, m); });
    flush(pending_velocity, [&](Node& a, const PendingVelocity& m) { AttachVelocity(a, m); });
    // A relative pose waits for t2 but is anchored at t1.
    std::erase_if(pending_relative, [&](const PendingRelativePose& r) {
      if (r.t2_ns > newest) return false;
      if (Node* anchor = Anchor(r.t1_ns)) {
        AttachRelativePose(*anchor, r);
      } else {
        ++num_dropped;
      }
      return true;
    });
  }
  static TimeNs StampOf(const PendingVelocity& m) { return m.t_ns; }
  static TimeNs StampOf(const PendingGnss& m) { return m.fix.header.stamp_ns; }
  static TimeNs StampOf(const PendingHeading& m) { return m.heading.header.stamp_ns; }

  void MarginalizeOldest() {
    Node& old = *states[0];
    Node& next = *states[1];
    BlockLayout layout;
    for (Node* n : {&old, &next}) {
      const auto blocks = n->Blocks();
      layout.Add(blocks[0], 4, &manifold);
      layout.Add(blocks[1], 3, nullptr);
      layout.Add(blocks[2], 3, nullptr);
      layout.Add(blocks[3], 6, nullptr);
    }
    std::vector<const FactorRecord*> records;
    for (const Factor& f : old.factors) records.push_back(&f.record);
    LinearSystem system;
    Linearize(records, layout, &system);
    const LinearSystem kept = SchurComplement(system, 15);

    auto* prior = new MarginalizationPrior(next.x, kept.H, kept.g);
    AddFactor(next, FactorKind::kPrior, prior, nullptr, next.Blocks());
    for (double* block : old.Blocks()) problem.RemoveParameterBlock(block);  // and its factors
    marginalized.push_back(old.State());
    states.pop_front();
    const TimeNs t_oldest = states.front()->t_ns;
    // Keep the samples before the oldest state that preintegration from it uses as context
    // for its cubic interpolant (ImuPreintegration::FromSamples).
    auto first_kept = std::lower_bound(
        imu.begin(), imu.end(), t_oldest,
        [](const ImuSample& s, TimeNs t) { return s.header.stamp_ns < t; });
    first_kept -= std::min<std::ptrdiff_t>(kPreintegrationContextSamples,
                                          first_kept - imu.begin());
    imu.erase(imu.begin(), first_kept);
  }

  Mat15 NewestInformation() const {
    Mat15 carried = Mat15::Zero();
    for (std::size_t k = 0; k < states.size(); ++k) {
      Node& n = *states[k];
      const bool last = k + 1 == states.size();
      BlockLayout layout;
      for (Node* m : last ? std::vector<Node*>{&n} : std::vector<Node*>{&n, states[k + 1].get()}) {
        const auto blocks = m->Blocks();
        layout.Add(blocks[0], 4, &manifold);
        layout.Add(blocks[1], 3, nullptr);
        layout.Add(blocks[2], 3, nullptr);
        layout.Add(blocks[3], 6, nullptr);
      }
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

SlidingWindowSmoother::SlidingWindowSmoother(const SlidingWindowOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw InputError(why);
  impl_ = std::make_unique<Impl>(options);
}

SlidingWindowSmoother::~SlidingWindowSmoother() = default;

bool SlidingWindowSmoother::initialized() const { return !impl_->states.empty(); }

void SlidingWindowSmoother::AddImu(const ImuSample& sample) {
  Impl& m = *impl_;
  if (!sample.gyro.allFinite() || !sample.accel.allFinite()) {
    throw InputError("imu sample at " + std::to_string(sample.header.stamp_ns) +
                     " ns: non-finite value");
  }
  if (!m.imu.empty() && sample.header.stamp_ns <= m.imu.back().header.stamp_ns) {
    throw InputError("imu sample at " + std::to_string(sample.header.stamp_ns) +
                     " ns: stamp does not increase");
  }
  if (!initialized()) {
    m.imu.assign(1, sample);  // only the sample the first state may sit on
    return;
  }
  m.imu.push_back(sample);
  if (++m.samples_since_state >= m.options.imu_samples_per_state) {
    m.CreateState(sample.header.stamp_ns);
    m.samples_since_state = 0;
  }
  m.FlushPending();
}

void SlidingWindowSmoother::Initialize(const NavState& state, const Mat15& covariance) {
  Impl& m = *impl_;
  if (initialized()) throw InputError("sliding window smoother: already initialized");
  if (m.imu.empty() || m.imu.back().header.stamp_ns != state.t_ns) {
    throw InputError("sliding window smoother: the first state must sit on the last IMU sample");
  }
  auto* prior = MarginalizationPrior::FromCovariance(state, covariance);  // throws if not PD
  auto node = std::make_unique<Node>();
  node->t_ns = state.t_ns;
  node->x = StateParameters::FromNavState(state);
  m.AddBlocks(*node);
  m.AddFactor(*node, FactorKind::kPrior, prior, nullptr, node->Blocks());
  m.states.push_back(std::move(node));
  m.samples_since_state = 0;
}

AddResult SlidingWindowSmoother::AddGnss(const GnssPositionEnu& fix, const Vec3& p_imu_antenna) {
  Impl& m = *impl_;
  if (!initialized()) throw InputError("sliding window smoother: gnss fix before initialization");
  SqrtInformation<3>(fix.covariance, "gnss fix '" + fix.header.sensor_id + "'");  // validates
  if (!p_imu_antenna.allFinite()) throw InputError("gnss fix: non-finite lever arm");
  const PendingGnss pending{fix, p_imu_antenna};
  if (fix.header.stamp_ns > m.imu.back().header.stamp_ns) {
    m.pending_gnss.push_back(pending);
    return AddResult::kPending;
  }
  Node* anchor = m.Anchor(fix.header.stamp_ns);
  if (anchor == nullptr) return AddResult::kTooOld;
  m.AttachGnss(*anchor, pending);
  return AddResult::kAdded;
}

AddResult SlidingWindowSmoother::AddDualAntenna(const DualAntennaHeading& heading,
                                                const Vec3& p_imu_main, const Vec3& p_imu_aux) {
  Impl& m = *impl_;
  if (!initialized()) throw InputError("sliding window smoother: heading before initialization");
  DualAntennaFactor validate(heading, p_imu_main, p_imu_aux);  // throws on bad input
  (void)validate;
  const PendingHeading pending{heading, p_imu_main, p_imu_aux};
  if (heading.header.stamp_ns > m.imu.back().header.stamp_ns) {
    m.pending_headings.push_back(pending);
    return AddResult::kPending;
  }
  Node* anchor = m.Anchor(heading.header.stamp_ns);
  if (anchor == nullptr) return AddResult::kTooOld;
  m.AttachHeading(*anchor, pending);
  return AddResult::kAdded;
}

AddResult SlidingWindowSmoother::AddRelativePose(TimeNs t1_ns, TimeNs t2_ns,
                                                 const RelativePoseMeasurement& m,
                                                 const RobustKernel& kernel) {
  Impl& s = *impl_;
  if (!initialized()) throw InputError("sliding window smoother: relative pose before initialization");
  if (t2_ns <= t1_ns) throw InputError("relative pose: t2 must be after t1");
  if (!m.sqrt_information.allFinite()) throw InputError("relative pose: non-finite information");
  const PendingRelativePose pending{t1_ns, t2_ns, m, kernel};
  Node* anchor = s.Anchor(t1_ns);
  if (anchor == nullptr) return AddResult::kTooOld;
  if (t2_ns > s.imu.back().header.stamp_ns) {
    s.pending_relative.push_back(pending);
    return AddResult::kPending;
  }
  s.AttachRelativePose(*anchor, pending);
  return AddResult::kAdded;
}

AddResult SlidingWindowSmoother::AddBodyVelocity(TimeNs t_ns, const BodyVelocityMeasurement& m,
                                                 const RobustKernel& kernel) {
  Impl& s = *impl_;
  if (!initialized()) throw InputError("sliding window smoother: velocity before initialization");
  if (!m.sqrt_information.allFinite() || !m.v_frame.allFinite() || !m.p_imu_point.allFinite()) {
    throw InputError("body velocity: non-finite value");
  }
  const PendingVelocity pending{t_ns, m, kernel};
  if (t_ns > s.imu.back().header.stamp_ns) {
    s.pending_velocity.push_back(pending);
    return AddResult::kPending;
  }
  Node* anchor = s.Anchor(t_ns);
  if (anchor == nullptr) return AddResult::kTooOld;
  s.AttachVelocity(*anchor, pending);
  return AddResult::kAdded;
}

SmootherSolveSummary SlidingWindowSmoother::Solve() {
  Impl& m = *impl_;
  SmootherSolveSummary out;
  if (!initialized()) return out;
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.max_num_iterations = m.options.max_iterations;
  options.initial_trust_region_radius = m.options.initial_trust_region_radius;
  options.num_threads = m.options.num_threads;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &m.problem, &summary);
  out.usable = summary.IsSolutionUsable();
  out.iterations = static_cast<int>(summary.iterations.size()) - 1;
  out.initial_cost = summary.initial_cost;
  out.final_cost = summary.final_cost;
  for (const auto& n : m.states) {
    for (const Factor& f : n->factors) {
      out.num_imu_factors += f.kind == FactorKind::kImu;
      out.num_gnss_factors += f.kind == FactorKind::kGnss;
      out.num_heading_factors += f.kind == FactorKind::kHeading;
      out.num_relative_pose_factors += f.kind == FactorKind::kRelativePose;
      out.num_velocity_factors += f.kind == FactorKind::kVelocity;
    }
  }
  const TimeNs window_ns = FromSeconds(m.options.window_s);
  while (m.states.size() > 1 && m.states.back()->t_ns - m.states.front()->t_ns > window_ns) {
    m.MarginalizeOldest();
    ++out.num_marginalized;
  }
  out.num_states = static_cast<int>(m.states.size());
  out.num_dropped_pending = m.num_dropped;
  m.num_dropped = 0;
  return out;
}

NavState SlidingWindowSmoother::NewestState() const {
  if (!initialized()) throw InputError("sliding window smoother: not initialized");
  return impl_->states.back()->State();
}

NavState SlidingWindowSmoother::PredictToNewestImu() const {
  const Impl& m = *impl_;
  const NavState newest = NewestState();
  const TimeNs t_imu = m.imu.back().header.stamp_ns;
  if (t_imu == newest.t_ns) return newest;
  return m.Preintegrate(*m.states.back(), t_imu).Predict(newest);
}

Mat15 SlidingWindowSmoother::NewestCovariance() const {
  if (!initialized()) throw InputError("sliding window smoother: not initialized");
  const Mat15 information = impl_->NewestInformation();
  const Eigen::LDLT<Mat15> ldlt(0.5 * (information + information.transpose()));
  Mat15 covariance = ldlt.solve(Mat15::Identity());
  return 0.5 * (covariance + covariance.transpose());
}

std::vector<NavState> SlidingWindowSmoother::WindowStates() const {
  std::vector<NavState> out;
  for (const auto& n : impl_->states) out.push_back(n->State());
  return out;
}

std::vector<NavState> SlidingWindowSmoother::TakeMarginalizedStates() {
  std::vector<NavState> out;
  out.swap(impl_->marginalized);
  return out;
}

}  // namespace statebench::est
