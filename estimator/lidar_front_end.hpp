// Lidar front end: scans of the used lidars (several merged into one scan per period in the first
// lidar's frame) wait until the IMU covers their sweep, are deskewed and predicted with the IMU
// (poses every 5 ms over the sweep, from the window or the IMU-rate propagation), registered by
// the lidar odometry, checked against the IMU prior, and become relative-pose factors between
// consecutive scans with the odometry's covariance (scaled and floored).
#pragma once

#include <deque>
#include <optional>

#include "estimator/factor_plan.hpp"
#include "estimator/front_end.hpp"
#include "estimator/lidar_odometry.hpp"
#include "estimator/lidar_scan_merger.hpp"

namespace statebench::est {

class LidarFrontEnd final : public MeasurementFrontEnd {
 public:
  // `setup` (through `plan`) and `options` must outlive the front end.
  LidarFrontEnd(const EstimatorSensorSetup& setup, const FactorPlan& plan,
                const FactorGraphOptions& options, FrontEndContext& ctx);

  Claim Claims(const Measurement& m) const override;
  void Process(const Measurement& m) override;
  void AfterRelease() override { ProcessWaitingScans(); }
  // A new map and no previous scan: the next relative motion starts from the new window.
  void OnRestart() override;

 private:
  bool Used(const std::string& id) const;
  void ProcessWaitingScans();
  std::optional<LidarMotionPrior> MotionPrior(TimeNs t_ns, TimeNs sweep_end_ns,
                                              std::optional<SE3>* T_world_prev) const;
  void RegisterScan(const LidarScan& scan, TimeNs sweep_end_ns);

  const EstimatorSensorSetup& setup_;
  const FactorPlan& plan_;
  const FactorGraphOptions& options_;
  FrontEndContext& ctx_;
  std::optional<LidarOdometry> odometry_;
  std::optional<LidarScanMerger> merger_;  // with more than one lidar
  std::deque<LidarScan> waiting_;          // released scans whose sweep the IMU has not covered
  std::optional<TimeNs> last_scan_ns_;     // stamp of the newest accepted scan
};

}  // namespace statebench::est
