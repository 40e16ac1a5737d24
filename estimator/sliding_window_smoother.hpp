// Fixed-lag smoother: a window of navigation states linked by preintegrated IMU factors and bias
// random walks, with GNSS and dual-antenna factors at their own stamps, solved with Ceres
// (sparse normal Cholesky; rotations on RightQuaternionManifold). States older than the window
// are marginalised by Schur complement into a MarginalizationPrior on the oldest kept state, so
// their information is kept (linearised at the estimate when they leave).
//
// States: one at every imu_samples_per_state-th IMU sample (1 = every sample, as in the paper).
// Usage: AddImu(sample at t0); Initialize(state at t0, covariance); then feed IMU samples and
// measurements in arrival order and call Solve() whenever an update is wanted.
//
// Measurements are attached to the latest state at or before their stamp, propagated to the
// stamp with the IMU (GnssPropagatedPositionFactor, DualAntennaFactor with the rotation delta):
// a late measurement still inside the window lands where in-order arrival would put it. One
// newer than the newest IMU sample waits until the IMU reaches its stamp; one older than the
// oldest state is refused.
//
// The newest state's 15x15 covariance (core/state.hpp ordering) is the marginal of the window's
// linearised system, computed by eliminating the states oldest first (block-tridiagonal, O(N)).
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/measurements.hpp"
#include "core/state.hpp"
#include "estimator/body_velocity_factor.hpp"
#include "estimator/gnss_enu.hpp"
#include "estimator/imu_noise.hpp"
#include "estimator/imu_triad_factor.hpp"
#include "estimator/relative_pose_factor.hpp"
#include "estimator/robust_kernel.hpp"
#include "estimator/window_solver.hpp"

namespace statebench::est {

struct SlidingWindowOptions {
  double window_s = 1.0;          // states older than newest - window_s are marginalised
  int imu_samples_per_state = 1;  // 1: a state per IMU sample; N: keyframes every N samples
  ImuNoise imu_noise;
  RobustKernel gnss_kernel;     // on GNSS position factors
  RobustKernel heading_kernel;  // on dual-antenna factors
  int max_iterations = 10;
  // Levenberg-Marquardt starts close to Gauss-Newton. The preintegrated IMU factors are stiff
  // (information up to ~1e12 per step) while biases are weakly observed; with Ceres' default
  // radius (1e4) the damping all but freezes the weak directions and a window needs more than
  // 10 iterations (measured: 10+ at 1e4, 2-3 at 1e10-1e13 for keyframes and states per sample).
  double initial_trust_region_radius = 1e13;
  int num_threads = 1;
  WindowSolver solver = WindowSolver::kCeres;
  // The batch store: keep every state and factor that leaves the window (memory grows with the
  // run: about 10 KB per state with lidar factors) for SolveBatch.
  bool keep_all_states = false;
  // The lagged store: each state as it leaves the window (its estimate with the window's lag)
  // with its marginal covariance in the window's last linearisation, and every IMU sample, for
  // LaggedStates (about 2 KB per state and 0.1 KB per IMU sample).
  bool keep_lagged_states = false;

  bool IsValid(std::string* why = nullptr) const;
};

enum class AddResult { kAdded, kPending, kTooOld };

struct SmootherSolveSummary {
  bool usable = false;  // Ceres returned a usable solution and the cost is finite
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  int num_states = 0;
  int num_marginalized = 0;  // states that left the window in this call
  // Not usable and the window longer than window_s: marginalisation waited for a usable solve.
  bool marginalization_deferred = false;
  // States marginalised although the solve was not usable (the window reached 2 x window_s).
  int num_marginalized_unusable = 0;
  // Factors of marginalised states left out of the prior: not finite at its linearisation point.
  int num_left_out_of_prior = 0;
  int num_imu_factors = 0;
  int num_gnss_factors = 0;
  int num_heading_factors = 0;
  int num_relative_pose_factors = 0;
  int num_velocity_factors = 0;
  int num_zero_rate_factors = 0;
  int num_dropped_pending = 0;  // waiting measurements the window passed before the IMU came
};

// Every state since Initialize solved at once (SlidingWindowSmoother::SolveBatch).
struct SmootherBatch {
  bool usable = false;  // as SmootherSolveSummary::usable
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  std::vector<NavState> states;  // oldest first
  // Each state's marginal covariance in the batch's linearised system (core/state.hpp
  // ordering); empty when the solve is not usable.
  std::vector<Mat15> covariances;
  std::vector<ImuSample> imu;  // every raw sample from the first state's stamp on
};

class SlidingWindowSmoother {
 public:
  // Throws InputError if the options are not valid.
  explicit SlidingWindowSmoother(const SlidingWindowOptions& options);
  ~SlidingWindowSmoother();
  SlidingWindowSmoother(const SlidingWindowSmoother&) = delete;
  SlidingWindowSmoother& operator=(const SlidingWindowSmoother&) = delete;

  // Raw IMU sample. InputError (and nothing changes) on a non-finite value or a stamp that does
  // not increase.
  void AddImu(const ImuSample& sample);

  // First state, at the stamp of the last IMU sample added, with its prior covariance.
  // InputError if no IMU sample has that stamp or the covariance is not positive definite.
  void Initialize(const NavState& state, const Mat15& covariance);
  bool initialized() const;

  // GNSS antenna fix (ENU) with the antenna's position in the IMU frame. InputError if the
  // covariance is not positive definite or before Initialize. With time_offset (an index
  // AddGlobal gave) the fix stamped t is the antenna at t - offset
  // (gnss_time_offset_factor.hpp); InputError on an index it did not give.
  // With error (three indices AddGlobal gave: the receiver's slowly varying east, north and up
  // error) the fix is the antenna plus that error (gnss_error_state_factor.hpp).
  AddResult AddGnss(const GnssPositionEnu& fix, const Vec3& p_imu_antenna,
                    std::optional<int> time_offset = std::nullopt,
                    std::optional<std::array<int, 3>> error = std::nullopt);

  // A global parameter of the window: a scalar every state's factors may touch (a GNSS
  // receiver's time offset in s, a mount's rotation correction in rad), solved with the states
  // (bordered_chain.hpp) and kept through marginalisation in the joint prior of the oldest state
  // and the globals (bordered_marginalization_prior.hpp). It starts at 0 with the prior
  // N(0, prior_sigma^2) and is held within +-max_abs after each solve. Returns its index.
  // With a correlation time tau the global is a first-order Gauss-Markov process of stationary
  // sigma prior_sigma instead of a constant: constant within the window, and each time a state
  // leaves it (dt to the next), the marginalisation prior carries it on as
  // e' = exp(-dt/tau) e + w, var(w) = prior_sigma^2 (1 - exp(-2 dt/tau)). The full-batch
  // smoother (keep_all_states) holds it constant over the log.
  // InputError before Initialize, on a sigma, bound or tau that is not positive, or with the
  // Ceres solver and keep_all_states (not supported there).
  int AddGlobal(const std::string& name, double prior_sigma, double max_abs,
                std::optional<double> correlation_time_s = std::nullopt);
  struct GlobalEstimate {
    std::string name;
    double value = 0.0;
    double sigma = 0.0;   // marginal, from the last solve's linearisation (0 before a solve)
    int num_clamped = 0;  // solves after which it was held at its bound
  };
  // In the order AddGlobal gave their indices.
  std::vector<GlobalEstimate> Globals() const;
  // The one AddGlobal gave `index` (what the front ends read per measurement). InputError on an
  // index it did not give.
  GlobalEstimate Global(int index) const;
  // The IMU's triad errors (imu_triad_factor.hpp): each term an entry of the gyro's or the
  // accelerometer's error matrix K, the value of a global AddGlobal gave. The IMU factors created
  // from now on are ImuTriadFactors on these globals (those in the window keep theirs). An empty
  // list: plain ImuFactors again. InputError on an index AddGlobal did not give.
  struct ImuTriadGlobal {
    int global = -1;
    ImuTriadTerm term;
  };
  void SetImuTriad(std::vector<ImuTriadGlobal> terms);
  // Dual-antenna heading with both antennas' positions in the IMU frame. InputError on a
  // measurement DualAntennaFactor refuses. With baseline (two indices AddGlobal gave: yaw,
  // pitch) the baseline is turned by those corrections (DualAntennaFactor::
  // CreateWithBaselineCorrection); InputError on an index it did not give.
  AddResult AddDualAntenna(const DualAntennaHeading& heading, const Vec3& p_imu_main,
                           const Vec3& p_imu_aux,
                           std::optional<std::array<int, 2>> baseline = std::nullopt);

  // Relative motion of a sensor frame between t1 < t2 (lidar odometry, kinematic factor). The
  // pose at t1 is carried from the latest state at or before t1 (anchor a); the pose at t2 from
  // the state after a when it is at or before t2 (else from a too), so the factor links
  // neighbouring states only and marginalises like the IMU factor. Pending while t2 is newer
  // than the newest IMU sample; kTooOld if t1 is before the window. `kernel` may be kNone.
  // With mount the sensor frame is turned by the corrections (relative_pose_factor.hpp, pitch and
  // yaw, or roll too). InputError if t2 <= t1, the information is not finite, or on a mount
  // index AddGlobal did not give (or pitch or yaw missing).
  // A mount rotation correction c of a sensor frame, R_imu_sensor Exp(c) (rad, about the
  // frame's own axes): the indices AddGlobal gave its estimated axes, -1 for an axis held at 0.
  struct MountCorrection {
    int roll = -1;
    int pitch = -1;
    int yaw = -1;
  };
  AddResult AddRelativePose(TimeNs t1_ns, TimeNs t2_ns, const RelativePoseMeasurement& m,
                            const RobustKernel& kernel,
                            std::optional<MountCorrection> mount = std::nullopt);
  // Velocity of a vehicle point at t_ns (speed encoder, non-holonomic, zero velocity); the raw
  // gyro at the stamp (m.gyro_raw) is filled in from the IMU buffer. Same pending rules.
  // With mount (the vehicle frame's pitch and yaw corrections, rad, two indices AddGlobal gave;
  // no roll) the measurement frame is turned by them (CreateMountCorrectedBodyVelocityFactor);
  // InputError on an index it did not give, a roll, or a world-frame measurement.
  AddResult AddBodyVelocity(TimeNs t_ns, const BodyVelocityMeasurement& m,
                            const RobustKernel& kernel,
                            std::optional<MountCorrection> mount = std::nullopt);
  // Mean raw gyro over a still span ending at t_end_ns (zero_rate_factor.hpp): a measurement of
  // the gyro bias of the state the span's end belongs to. Same pending rules. InputError on a
  // non-finite mean or a sigma that is not positive.
  AddResult AddZeroRate(TimeNs t_end_ns, const Vec3& mean_gyro_radps, double sigma_radps,
                        const RobustKernel& kernel);

  // The IMU noise of the IMU, bias and GNSS-propagation factors created from now on (those in
  // the window keep theirs). InputError if it is not valid.
  void SetImuNoise(const ImuNoise& noise);

  // Optimises the window, then marginalises the states that left it.
  SmootherSolveSummary Solve();

  // With keep_all_states: the full-batch smoother. Every state since Initialize (those that
  // left the window and the window's) with every factor they had, the first state's initial
  // prior but no marginalisation prior, solved together by the chain Levenberg-Marquardt from
  // the values they have (the fixed-lag estimates) with up to max_iterations iterations; the
  // covariances are the marginals of the final linearisation (chain_system.hpp). Call once, at
  // the end: the smoother is left with the batch values. InputError without keep_all_states or
  // before Initialize.
  SmootherBatch SolveBatch(int max_iterations);

  // With keep_lagged_states: the fixed-lag smoother's smoothed output. Every state since
  // Initialize as last estimated before it left the window (the window's states as they are
  // now), each with its marginal covariance in the window at that time (the globals' share in
  // it: bordered_chain.hpp's BorderedChainMarginalCovariances of the window linearised after the
  // solve that marginalised it), and every IMU sample since the first state; usable, no
  // iterations. InputError without keep_lagged_states or before Initialize.
  SmootherBatch LaggedStates() const;

  NavState NewestState() const;
  // Newest state propagated with the IMU to the newest sample (equal to NewestState() when a
  // state sits on every sample).
  NavState PredictToNewestImu() const;
  // The preintegration from the newest state to the newest sample, as integrated at the values
  // the state had then (they may have moved since: a user checks its bias_lin and stamps), or
  // null; valid until the next call that changes the smoother. For ImuRateOutput::AfterAnchor.
  const ImuPreintegration* FromNewestState() const;
  // Marginal covariance of the newest state, core/state.hpp ordering.
  Mat15 NewestCovariance() const;
  std::vector<NavState> WindowStates() const;
  // States that left the window since the last call, oldest first, as last estimated.
  std::vector<NavState> TakeMarginalizedStates();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace statebench::est
