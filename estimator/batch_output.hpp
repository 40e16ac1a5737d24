// The full-batch smoother's output (FactorGraphOptions::batch): the batch states of each segment
// (one per smoother run: the estimator's restarts and its switch from a local frame into ENU each
// close one, the end of the log the last) carried to any stamp through the raw IMU samples.
//
// At a stamp t the mean is the latest batch state at or before t carried to t
// (imu_propagation.hpp); the covariance is that state's batch marginal carried the same way: it
// leaves out what the next state knows about t, so it bounds the smoothed covariance at t from
// above (equal at the states). A segment whose batch solve was not usable gives no estimate.
#pragma once

#include <optional>
#include <vector>

#include "estimator/imu_noise.hpp"
#include "estimator/imu_propagation.hpp"
#include "estimator/sliding_window_smoother.hpp"

namespace statebench::est {

class BatchOutput {
 public:
  explicit BatchOutput(const ImuNoise& noise) : noise_(noise) {}

  // The next segment (its states after every earlier segment's first state); local_frame: its
  // states are in the estimator's local frame (before the switch into ENU).
  void Add(SmootherBatch batch, bool local_frame);

  struct At {
    PropagatedState state;
    bool local_frame = false;
  };
  // nullopt before the first segment, after the last sample of the segment t_ns falls in, or in
  // a segment without a usable solve.
  std::optional<At> StateAt(TimeNs t_ns) const;

 private:
  struct Segment {
    SmootherBatch batch;
    bool local_frame = false;
  };
  ImuNoise noise_;
  std::vector<Segment> segments_;
};

}  // namespace statebench::est
