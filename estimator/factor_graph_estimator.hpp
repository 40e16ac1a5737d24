// The factor-graph estimator: the Estimator interface on top of SlidingWindowSmoother.
//
// Pipeline (each step a named function in the .cpp):
//  1. Add(): plausibility checks (measurement_checks.hpp), sensor ids from the setup, stamps;
//     rejections are counted per sensor and reason. Accepted measurements go to a reorder buffer.
//  2. The reorder buffer releases them in stamp order once the newest IMU sample is
//     reorder_latency_s past their stamp. The smoother therefore runs reorder_latency_s behind
//     the IMU on a stream whose order does not depend on the delivery order: any delivery with
//     delays up to reorder_latency_s gives bit-identical smoothed states.
//  3. Until initialised, released data feed the StateInitializer (static or moving alignment);
//     its first state opens the window. The ENU origin is options.origin or the first fix.
//  4. GNSS fixes of one stamp are grouped (gnss_stamp_group.hpp): the two antennas of a
//     dual-antenna pair give a heading (or the receiver's DualAntennaHeading of that stamp is
//     used) plus the main antenna's position. Every measurement passes the covariance threshold
//     (paper), then a Mahalanobis gate against the IMU prediction from the last solve
//     (measurement_gate.hpp), then goes into the smoother with the robust kernel; once it leaves
//     the window its final whitened residual tells whether the kernel down-weighted it.
//  5. Every solve_interval_s of (lagged) IMU time the window is solved and the states older than
//     window_s are marginalised; the newest state and its covariance become the anchor.
//  6. StateAt(t) (imu_rate_output.hpp): from the anchor through the buffered IMU samples (mean
//     and covariance) for t at or after the anchor, up to the newest IMU sample: the IMU-rate
//     output. For t inside the window, the smoothed state at or before t carried to t, with the
//     covariance of the latest earlier anchor (a filtered covariance, an upper bound of the
//     smoothed one). Older stamps: nullopt. From the newest solve's stamp on, the output blends
//     that solve's correction in at a bounded rate instead of jumping by it (output_blend.hpp;
//     the covariance covers the offset still shown); the front ends' gates use the unblended
//     prediction.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/geodetic.hpp"
#include "estimator/estimator.hpp"
#include "estimator/estimator_config.hpp"
#include "estimator/shared_lidar_odometry.hpp"

namespace statebench::est {

class FactorGraphEstimator final : public Estimator {
 public:
  // Throws InputError if the options are not valid. lidar_pool (may be nullptr; need not outlive
  // the estimator): where a shared lidar odometry comes from (lidar.motion_prior:
  // constant_velocity), so that the estimators of one run register each scan once.
  FactorGraphEstimator(const EstimatorSensorSetup& setup, const FactorGraphOptions& options,
                       LidarOdometryPool* lidar_pool = nullptr);
  ~FactorGraphEstimator() override;
  FactorGraphEstimator(const FactorGraphEstimator&) = delete;
  FactorGraphEstimator& operator=(const FactorGraphEstimator&) = delete;

  std::string name() const override { return "factor_graph"; }
  void Add(const Measurement& measurement) override;
  std::optional<StateEstimate> StateAt(TimeNs t_ns) const override;
  EstimatorDiagnostics diagnostics() const override;
  void SetVerdictObserver(VerdictObserver observer) override;
  // EndOfLog releases what the reorder buffer holds and solves the window once more (StateAt
  // then shows every measurement; no measurement may follow).
  //
  // options.batch: the full-batch smoother. The fixed-lag smoother runs as without it (same
  // states, factors, gates and front ends; the lidar front end's initial guesses come from it)
  // but keeps every state and factor that leaves its window; each smoother run (from an
  // initialisation to a restart, the switch into ENU or EndOfLog) is then solved as a whole
  // (SlidingWindowSmoother::SolveBatch). StateAt answers from the batch states
  // (batch_output.hpp), and nullopt before EndOfLog.
  bool EstimatesAtEnd() const override;
  void EndOfLog() override;

  // From now on, keep the smoothed states that leave the window (their final estimates) until
  // TakeSmoothedStates takes them; off by default, so that a long run keeps nothing it is not
  // asked for.
  void KeepSmoothedStates();
  // Smoothed states kept since the last call, oldest first.
  std::vector<NavState> TakeSmoothedStates();
  // The ENU origin; nullopt until known.
  std::optional<GeodeticPoint> origin() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace statebench::est
