// Lidar front end: the scans of one lidar (or, with lidar.merge_scans, of several merged into one
// scan per period in the first lidar's frame) wait until the IMU covers their sweep, are deskewed
// and predicted with the IMU (poses every 5 ms over the sweep, from the window or the IMU-rate
// propagation), registered by the lidar odometry, checked against the IMU prior, and become
// relative-pose factors between consecutive scans with the odometry's covariance (scaled and
// floored). With lidar.estimate_mount the lidar frame's rotation against the IMU is estimated as
// three globals of the window (relative_pose_factor.hpp, MountAxes), per lidar.
//
// By default every lidar has a front end of its own (MakeFrontEnds): its own odometry, map,
// factors and mount globals. Merging trusts the lidars' relative mounts as exact: a relative
// rotation error d (hand-measured mounts, ~0.2 deg per axis each) turns one lidar's points
// against the other's by d (10 cm at 30 m on a 0.2 deg error), the map they share holds both
// versions of each surface and every registration pulls towards a compromise that moves with the
// vehicle: the odometry drifts in yaw, which no single mount correction of the merged frame can
// take out (docs/estimator-config.md, "Several lidars").
//
// With lidar.motion_prior: constant_velocity (or gyro) the odometry predicts with its own model
// (and the raw gyro's rotation) instead and is shared (shared_lidar_odometry.hpp): every scan of the used lidars is registered, before
// the initialisation and across restarts too, so that the registrations depend on the scans
// alone; the factors still start at the estimator's first state and are gated against its own
// IMU prediction.
#pragma once

#include <deque>
#include <memory>
#include <optional>
#include <vector>

#include "estimator/factor_plan.hpp"
#include "estimator/front_end.hpp"
#include "estimator/lidar_odometry.hpp"
#include "estimator/lidar_scan_merger.hpp"
#include "estimator/shared_lidar_odometry.hpp"

namespace statebench::est {

class LidarFrontEnd final : public MeasurementFrontEnd {
 public:
  // `setup` (which `lidars` point into) and `options` must outlive the front end. lidars: the
  // lidars it registers (several: merged into the first one's frame); empty: lidar factors off,
  // every lidar scan of the setup is taken and refused as disabled. pool: where a shared
  // odometry comes from (constant-velocity prior); nullptr: one of its own.
  LidarFrontEnd(const EstimatorSensorSetup& setup, std::vector<const EstimatorSensor*> lidars,
                const FactorGraphOptions& options, FrontEndContext& ctx,
                LidarOdometryPool* pool = nullptr);

  // Takes the scans of its lidars (of every lidar of the setup when it has none); a lidar of
  // the setup that another front end registers is kOtherKind.
  Claim Claims(const Measurement& m) const override;
  void Process(const Measurement& m) override;
  void AfterRelease() override { ProcessWaitingScans(); }
  void OnImu(const ImuSample& sample) override;
  // A new map and no previous scan: the next relative motion starts from the new window.
  void OnRestart() override;

 private:
  bool Used(const std::string& id) const;
  void ProcessWaitingScans();
  std::optional<LidarMotionPrior> MotionPrior(TimeNs t_ns, TimeNs sweep_end_ns,
                                              std::optional<SE3>* T_world_prev) const;
  void RegisterScan(const LidarScan& scan, TimeNs sweep_end_ns);
  LidarOdometryResult Registration(const LidarScan& scan, TimeNs sweep_end_ns,
                                   std::optional<SE3>* T_prev_curr_imu);
  // The lidar's motion between two stamps predicted by the estimator (nullopt if not held).
  std::optional<SE3> PredictedMotion(TimeNs from_ns, TimeNs to_ns) const;
  // The (first) lidar's mount correction as globals of the window with lidar.estimate_mount,
  // else none; and its X = T_imu_lidar turned by the current estimate. The globals are named
  // after the lidar: each front end's lidar has its own.
  std::optional<SlidingWindowSmoother::MountCorrection> MountCorrection();
  SE3 ImuLidar() const;

  const EstimatorSensorSetup& setup_;
  const std::vector<const EstimatorSensor*> lidars_;
  const FactorGraphOptions& options_;
  FrontEndContext& ctx_;
  std::optional<LidarOdometry> odometry_;          // IMU prior: this estimator's own
  std::shared_ptr<SharedLidarOdometry> shared_;   // constant-velocity or gyro prior
  std::optional<GyroTrack> gyro_;                  // gyro prior: the raw samples
  std::optional<LidarScanMerger> merger_;  // with more than one lidar
  // Released scans whose sweep the IMU has not covered, with their sweep's end (computed once:
  // the queue is looked at after every released measurement).
  struct WaitingScan {
    LidarScan scan;
    TimeNs sweep_end_ns = 0;
  };
  std::deque<WaitingScan> waiting_;
  std::optional<TimeNs> last_scan_ns_;     // stamp of the newest accepted scan
  TimeNs restart_ns_ = INT64_MIN;          // shared odometry: no factor reaches before this
};

}  // namespace statebench::est
