// One lidar odometry shared by the estimators of a run that would register the same scans with
// the same options (lidar.motion_prior: constant_velocity or gyro, motion_factor_options.hpp).
//
// Without the estimator's own prediction a registration depends on the sequence of scans, the
// raw gyro samples (gyro prior: the rotation of the guess and of the deskew; the translation
// from the constant-velocity model) and the odometry's options only, so it is computed once, by
// the first estimator that asks for a scan, and handed to every other one. Each estimator keeps its own factor creation (covariance
// scale and floors, the gate against its own IMU prediction, its own window): an estimator
// given a pool gets the very results it would compute alone.
//
// The pool keeps the newest results only (kRecentScans): estimators fed in step with each other
// ask for a scan within a few periods of one another. A scan asked for after the odometry moved
// past it without registering it, or after it left the recent results, comes back not accepted,
// with a reason that says so.
#pragma once

#include <cstddef>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/measurements.hpp"
#include "core/se3.hpp"
#include "estimator/gyro_track.hpp"
#include "estimator/lidar_odometry.hpp"
#include "estimator/lidar_registration_record.hpp"

namespace statebench::est {

// The lidars registered as one scan (several are merged into the first one's frame) and where
// each is mounted relative to the first, and what decides which scans and IMU samples the
// estimator lets through to the odometry (its reorder latency and IMU limits, as text).
struct LidarSetKey {
  std::vector<std::pair<std::string, SE3>> mounts;  // id, T_first_lidar
  std::string intake;
};

// Text identifying everything a registration depends on: the lidar set, the rotation of the
// gyro prior (q_imu_lidar: the first lidar's mount rotation in the IMU frame; nullopt: no gyro)
// and every field of the odometry's options (ICP included), at full precision.
std::string SharedOdometryKey(const LidarSetKey& lidars, const std::optional<Quat>& q_imu_lidar,
                              const LidarOdometryOptions& options);

class SharedLidarOdometry {
 public:
  static constexpr std::size_t kRecentScans = 256;

  // q_imu_lidar: predict rotations with the raw gyro (Register's `gyro`) in this lidar mount;
  // nullopt: constant velocity alone.
  explicit SharedLidarOdometry(const LidarOdometryOptions& options,
                               std::optional<Quat> q_imu_lidar = std::nullopt)
      : odometry_(options), q_imu_lidar_(q_imu_lidar) {}

  // The registration of `scan`, whose sweep ends at sweep_end_ns (scans asked for in stamp order
  // by each caller). The first ask registers it; later asks return the kept result. `computed`
  // (optional) tells which. gyro: the raw gyro samples through the sweep's end (used with a
  // q_imu_lidar; every caller holds the same samples).
  LidarOdometryResult Register(const LidarScan& scan, TimeNs sweep_end_ns,
                               const GyroTrack* gyro = nullptr, bool* computed = nullptr);

  std::size_t registered() const { return registered_; }
  std::size_t reused() const { return reused_; }

  // Hand out these registrations, recorded by a run with the same inputs, instead of
  // registering (call before the first Register). A scan that is not the next recorded one is an
  // InputError: the record was not made from these inputs.
  void Replay(std::vector<RecordedRegistration> recorded);
  bool replaying() const { return replay_.has_value(); }
  // Keep every registration (for a record of the run); off by default.
  void KeepAll() { keep_all_ = true; }
  const std::vector<RecordedRegistration>& all() const { return all_; }

 private:
  struct Entry {
    TimeNs stamp_ns;
    std::size_t points;
    LidarOdometryResult result;
  };

  std::optional<LidarMotionPrior> GyroPrior(TimeNs t_ns, TimeNs sweep_end_ns,
                                            const GyroTrack& gyro) const;

  LidarOdometryResult Compute(const LidarScan& scan, std::size_t points, TimeNs sweep_end_ns,
                              const GyroTrack* gyro);

  LidarOdometry odometry_;
  std::optional<Quat> q_imu_lidar_;
  std::optional<std::vector<RecordedRegistration>> replay_;
  std::size_t replay_next_ = 0;
  bool keep_all_ = false;
  std::vector<RecordedRegistration> all_;
  std::deque<Entry> recent_;  // stamp order
  std::size_t registered_ = 0;
  std::size_t reused_ = 0;
};

// Where the registrations of earlier runs are kept (the stage cache), by SharedOdometryKey.
class RegistrationStore {
 public:
  virtual ~RegistrationStore() = default;
  // The registrations a complete earlier run recorded under `key`, or nullopt.
  virtual std::optional<std::vector<RecordedRegistration>> Load(const std::string& key) = 0;
  virtual void Save(const std::string& key,
                    const std::vector<RecordedRegistration>& registrations) = 0;
};

// The shared odometries of one run, one per key. Estimators built with the same pool share;
// an estimator built without one makes its own. With a store, an odometry whose key the store
// holds replays it, and Finish() stores the others.
class LidarOdometryPool {
 public:
  explicit LidarOdometryPool(RegistrationStore* store = nullptr) : store_(store) {}
  // The run went through to its end: the registrations computed go into the store.
  void Finish();

  std::shared_ptr<SharedLidarOdometry> For(const LidarSetKey& lidars,
                                           const std::optional<Quat>& q_imu_lidar,
                                           const LidarOdometryOptions& options);
  std::size_t size() const;
  // Per shared odometry, in key order: {"registered": scans registered, "reused": results
  // handed out again}.
  std::vector<std::pair<std::size_t, std::size_t>> Counts() const;

 private:
  RegistrationStore* store_;
  mutable std::mutex mutex_;
  std::map<std::string, std::shared_ptr<SharedLidarOdometry>> odometries_;
};

}  // namespace statebench::est
