#include "estimator/sliding_window_smoother.hpp"

#include <ceres/ordered_groups.h>
#include <ceres/solver.h>

#include <Eigen/Cholesky>

#include "core/error.hpp"
#include "estimator/chain_levenberg_marquardt.hpp"
#include "estimator/dual_antenna_factor.hpp"
#include "estimator/marginalization_prior.hpp"
#include "estimator/sliding_window_impl.hpp"
#include "estimator/sqrt_information.hpp"
#include "estimator/zero_rate_factor.hpp"

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

SlidingWindowSmoother::SlidingWindowSmoother(const SlidingWindowOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw InputError(why);
  impl_ = std::make_unique<Impl>(options);
}

SlidingWindowSmoother::~SlidingWindowSmoother() = default;

bool SlidingWindowSmoother::initialized() const { return !impl_->states.empty(); }

void SlidingWindowSmoother::SetImuNoise(const ImuNoise& noise) {
  std::string why;
  if (!noise.IsValid(&why)) throw InputError(why);
  impl_->options.imu_noise = noise;
}

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
  m.ExtendFromNewest();
  if (m.options.keep_all_states || m.options.keep_lagged_states) m.all_imu.push_back(sample);
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
  auto node = std::make_unique<Impl::Node>();
  node->t_ns = state.t_ns;
  node->x = StateParameters::FromNavState(state);
  m.AddBlocks(*node);
  m.AddFactor(*node, Impl::FactorKind::kPrior, prior, nullptr, node->Blocks());
  m.states.push_back(std::move(node));
  m.samples_since_state = 0;
  if (m.options.keep_all_states || m.options.keep_lagged_states) m.all_imu = m.imu;
}

AddResult SlidingWindowSmoother::AddGnss(const GnssPositionEnu& fix, const Vec3& p_imu_antenna,
                                         std::optional<int> time_offset,
                                         std::optional<std::array<int, 3>> error) {
  Impl& m = *impl_;
  if (!initialized()) throw InputError("sliding window smoother: gnss fix before initialization");
  SqrtInformation<3>(fix.covariance, "gnss fix '" + fix.header.sensor_id + "'");  // validates
  if (!p_imu_antenna.allFinite()) throw InputError("gnss fix: non-finite lever arm");
  if (time_offset && !m.KnownGlobal(*time_offset)) {
    throw InputError("gnss fix: unknown time offset index");
  }
  if (error &&
      !(m.KnownGlobal((*error)[0]) && m.KnownGlobal((*error)[1]) && m.KnownGlobal((*error)[2]))) {
    throw InputError("gnss fix: unknown error state index");
  }
  const TimeNs t = fix.header.stamp_ns;
  return m.Add(
      {Impl::FactorKind::kGnss, t, t, [&m, fix, p_imu_antenna, time_offset, error](Impl::Node& a) {
         m.AttachGnss(a, fix, p_imu_antenna, time_offset, error);
       }});
}

AddResult SlidingWindowSmoother::AddDualAntenna(const DualAntennaHeading& heading,
                                                const Vec3& p_imu_main, const Vec3& p_imu_aux,
                                                std::optional<std::array<int, 2>> baseline) {
  Impl& m = *impl_;
  if (!initialized()) throw InputError("sliding window smoother: heading before initialization");
  DualAntennaFactor validate(heading, p_imu_main, p_imu_aux);  // throws on bad input
  (void)validate;
  if (baseline && (!m.KnownGlobal((*baseline)[0]) || !m.KnownGlobal((*baseline)[1]))) {
    throw InputError("dual antenna heading: unknown baseline correction index");
  }
  const TimeNs t = heading.header.stamp_ns;
  return m.Add({Impl::FactorKind::kHeading, t, t,
                [&m, heading, p_imu_main, p_imu_aux, baseline](Impl::Node& a) {
                  m.AttachHeading(a, heading, p_imu_main, p_imu_aux, baseline);
                }});
}

AddResult SlidingWindowSmoother::AddRelativePose(TimeNs t1_ns, TimeNs t2_ns,
                                                 const RelativePoseMeasurement& m,
                                                 const RobustKernel& kernel,
                                                 std::optional<MountCorrection> mount) {
  Impl& s = *impl_;
  if (!initialized())
    throw InputError("sliding window smoother: relative pose before initialization");
  if (t2_ns <= t1_ns) throw InputError("relative pose: t2 must be after t1");
  if (!m.sqrt_information.allFinite()) throw InputError("relative pose: non-finite information");
  if (mount) s.CheckMount(*mount, "relative pose", /*roll_allowed=*/true);
  // Anchored at t1, waits for t2.
  const Impl::RelativePose r{t1_ns, t2_ns, m, kernel, mount};
  return s.Add({Impl::FactorKind::kRelativePose, t1_ns, t2_ns,
                [&s, r](Impl::Node& a) { s.AttachRelativePose(a, r); }});
}

AddResult SlidingWindowSmoother::AddBodyVelocity(TimeNs t_ns, const BodyVelocityMeasurement& m,
                                                 const RobustKernel& kernel,
                                                 std::optional<MountCorrection> mount) {
  Impl& s = *impl_;
  if (!initialized()) throw InputError("sliding window smoother: velocity before initialization");
  if (!m.sqrt_information.allFinite() || !m.v_frame.allFinite() || !m.p_imu_point.allFinite()) {
    throw InputError("body velocity: non-finite value");
  }
  if (mount) {
    s.CheckMount(*mount, "body velocity", /*roll_allowed=*/false);
    if (m.frame != BodyVelocityMeasurement::Frame::kVehicle) {
      throw InputError("body velocity: a mount correction needs a vehicle-frame measurement");
    }
  }
  return s.Add(
      {Impl::FactorKind::kVelocity, t_ns, t_ns, [&s, t_ns, m, kernel, mount](Impl::Node& a) {
         s.AttachVelocity(a, t_ns, m, kernel, mount);
       }});
}

AddResult SlidingWindowSmoother::AddZeroRate(TimeNs t_end_ns, const Vec3& mean_gyro_radps,
                                             double sigma_radps, const RobustKernel& kernel) {
  Impl& s = *impl_;
  if (!initialized()) throw InputError("sliding window smoother: zero rate before initialization");
  [[maybe_unused]] const ZeroRateFactor validated(mean_gyro_radps, sigma_radps);  // or throws
  return s.Add({Impl::FactorKind::kZeroRate, t_end_ns, t_end_ns,
                [&s, mean_gyro_radps, sigma_radps, kernel](Impl::Node& a) {
                  s.AddFactor(a, Impl::FactorKind::kZeroRate,
                              new ZeroRateFactor(mean_gyro_radps, sigma_radps),
                              kernel.MakeLossFunction().release(), {a.x.bias.data()});
                }});
}

namespace {

// One ceres::Solve of the window as it stands.
void SolveWindowWithCeres(ceres::Problem& problem, const SlidingWindowOptions& o,
                          SmootherSolveSummary* out) {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  // Eigen's sparse Cholesky, not SuiteSparse's: CHOLMOD's supernodal factorisation calls the
  // system BLAS, whose kernels sum in an order that follows the data's addresses, so two runs of
  // the same input differed in their last bits with the heap layout. Eigen's is as fast here
  // (windows of tens of states) and gives the same bits wherever the data lie.
  options.sparse_linear_algebra_library_type = ceres::EIGEN_SPARSE;
  options.max_num_iterations = o.max_iterations;
  options.initial_trust_region_radius = o.initial_trust_region_radius;
  options.num_threads = o.num_threads;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  // Ceres calls a solve whose cost is infinite from the start "usable" (it stops at iteration 0
  // with nothing to compare): a window with a non-finite cost has no solution to vouch for.
  out->usable = summary.IsSolutionUsable() && std::isfinite(summary.final_cost);
  out->iterations = static_cast<int>(summary.iterations.size()) - 1;
  out->initial_cost = summary.initial_cost;
  out->final_cost = summary.final_cost;
}

}  // namespace

SmootherSolveSummary SlidingWindowSmoother::Solve() {
  Impl& m = *impl_;
  SmootherSolveSummary out;
  if (!initialized()) return out;
  std::optional<Mat15> newest_information;
  // The oldest state's factors as the solve's final linearisation left them (chain solver, no
  // globals): the first state to leave needs no linearisation of its own.
  std::optional<LinearSystem> oldest_linearized;
  if (m.options.solver == WindowSolver::kCeres) {
    SolveWindowWithCeres(*m.problem, m.options, &out);
    if (!m.globals.empty() && out.usable) newest_information = m.UpdateGlobals(nullptr);
  } else {
    const std::vector<double*> globals = m.GlobalBlocks();
    const ChainSolveSummary chain = SolveChainLevenbergMarquardt(
        m.Chain(), m.manifold,
        ChainSolveOptions{m.options.max_iterations, m.options.initial_trust_region_radius},
        globals);
    out.usable = chain.usable;
    out.iterations = chain.iterations;
    out.initial_cost = chain.initial_cost;
    out.final_cost = chain.final_cost;
    // Marginalising below keeps the newest state's marginal (the prior is the Schur complement
    // of the same linearisation), so the solve's elimination serves NewestCovariance.
    if (chain.has_system) {
      newest_information = m.globals.empty() ? NewestMarginalInformation(chain.system)
                                             : m.UpdateGlobals(&chain.system);
      if (m.globals.empty() && m.states.size() > 1 && chain.system.first_pair_H.allFinite() &&
          chain.system.first_pair_g.allFinite()) {
        oldest_linearized = LinearSystem{chain.system.first_pair_H, chain.system.first_pair_g};
      }
    }
  }
  for (const auto& n : m.states) {
    for (const Impl::Factor& f : n->factors) {
      out.num_imu_factors += f.kind == Impl::FactorKind::kImu;
      out.num_gnss_factors += f.kind == Impl::FactorKind::kGnss;
      out.num_heading_factors += f.kind == Impl::FactorKind::kHeading;
      out.num_relative_pose_factors += f.kind == Impl::FactorKind::kRelativePose;
      out.num_velocity_factors += f.kind == Impl::FactorKind::kVelocity;
      out.num_zero_rate_factors += f.kind == Impl::FactorKind::kZeroRate;
    }
  }
  // A solve Ceres marks unusable leaves the window at a linearisation point nobody vouches for:
  // nothing is marginalised from it (the prior would freeze that point for good); the window
  // grows until a usable solve, up to twice its length, beyond which the oldest states go anyway
  // (memory and time stay bounded) and are counted.
  const TimeNs window_ns = FromSeconds(m.options.window_s);
  const TimeNs limit_ns = out.usable ? window_ns : 2 * window_ns;
  const auto span_ns = [&m] { return m.states.back()->t_ns - m.states.front()->t_ns; };
  if (!out.usable && span_ns() > window_ns) out.marginalization_deferred = true;
  const bool leaving = m.states.size() > 1 && span_ns() > limit_ns;
  // The leaving states' marginals in the window they leave (the lagged store).
  const std::vector<Mat15> marginals =
      m.options.keep_lagged_states && leaving ? m.WindowMarginals() : std::vector<Mat15>{};
  while (m.states.size() > 1 && span_ns() > limit_ns) {
    if (m.options.keep_lagged_states) {
      m.lagged_states.push_back(m.states.front()->State());
      m.lagged_covariances.push_back(marginals[static_cast<std::size_t>(out.num_marginalized)]);
    }
    m.MarginalizeOldest(out.num_marginalized == 0 && oldest_linearized ? &*oldest_linearized
                                                                       : nullptr);
    ++out.num_marginalized;
    out.num_marginalized_unusable += out.usable ? 0 : 1;
  }
  if (newest_information) m.newest_information = newest_information;
  out.num_states = static_cast<int>(m.states.size());
  out.num_dropped_pending = m.num_dropped;
  m.num_dropped = 0;
  out.num_left_out_of_prior = m.num_left_out;
  m.num_left_out = 0;
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

const ImuPreintegration* SlidingWindowSmoother::FromNewestState() const {
  return impl_->from_newest ? &*impl_->from_newest : nullptr;
}

Mat15 SlidingWindowSmoother::NewestCovariance() const {
  if (!initialized()) throw InputError("sliding window smoother: not initialized");
  const Mat15 information =
      impl_->newest_information ? *impl_->newest_information : impl_->NewestInformation();
  const Eigen::LDLT<Mat15> ldlt(0.5 * (information + information.transpose()));
  Mat15 covariance = ldlt.solve(Mat15::Identity());
  return 0.5 * (covariance + covariance.transpose());
}

SmootherBatch SlidingWindowSmoother::LaggedStates() const {
  const Impl& m = *impl_;
  if (!m.options.keep_lagged_states) {
    throw InputError("sliding window smoother: LaggedStates without keep_lagged_states");
  }
  if (!initialized()) throw InputError("sliding window smoother: LaggedStates before Initialize");
  SmootherBatch out;
  out.usable = true;
  out.states = m.lagged_states;
  out.covariances = m.lagged_covariances;
  for (const auto& n : m.states) out.states.push_back(n->State());
  for (const Mat15& c : m.WindowMarginals()) out.covariances.push_back(c);
  out.imu = m.all_imu;
  return out;
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
