// The factor graph's intake: the checks every measurement passes on arrival (a sensor of the
// setup that a front end takes, finite and plausible values, stamps that are neither repeated nor
// later than their arrival) and the reorder buffer that releases them in stamp order once the
// IMU is `latency` past their stamp. A measurement older than what was released already is late:
// it skips the buffer.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/measurements.hpp"
#include "estimator/estimator_config.hpp"
#include "estimator/front_end.hpp"
#include "estimator/reorder_buffer.hpp"

namespace statebench::est {

enum class Admission { kRejected, kImu, kQueued, kLate };

class MeasurementIntake {
 public:
  // `setup` must outlive the intake.
  MeasurementIntake(const EstimatorSensorSetup& setup, TimeNs latency_ns, const ImuLimits& limits)
      : setup_(setup), latency_ns_(latency_ns), imu_limits_(limits) {}

  // Counts m as received and checks it; rejections are counted in ctx. An IMU sample that passes
  // becomes ctx.newest_imu_ns. `claim`: the best answer of the front ends for m.
  Admission Admit(const Measurement& m, Claim claim, FrontEndContext& ctx);
  // Every held measurement stamped at least the latency before the newest IMU sample, in stamp
  // order (IMU samples first within a stamp).
  std::vector<Measurement> Release(TimeNs newest_imu_ns);
  // Takes every held measurement stamped before t_ns out of the stream (the estimator starts
  // over after a gap: what came before it can no longer be used).
  std::vector<Measurement> DropBefore(TimeNs t_ns) { return reorder_.Release(t_ns - 1); }
  // Every held measurement, in stamp order (the log ended).
  std::vector<Measurement> ReleaseAll() { return reorder_.Release(INT64_MAX); }

 private:
  bool AfterArrival(const MeasurementHeader& h) const;
  std::optional<RejectReason> CheckStamp(const MeasurementHeader& h, TimeNs newest_imu_ns);
  Admission AdmitImu(const ImuSample& s, FrontEndContext& ctx);

  const EstimatorSensorSetup& setup_;
  TimeNs latency_ns_;
  ImuLimits imu_limits_;
  ReorderBuffer reorder_;
  TimeNs newest_arrival_ns_ = INT64_MIN;  // arrival stamps given (> 0) so far
  std::map<std::string, std::set<TimeNs>> seen_stamps_;
};

}  // namespace statebench::est
