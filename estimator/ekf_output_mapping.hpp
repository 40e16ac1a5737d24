// The EKF's output in the estimator contract: its 8 planar states (ekf_single_track_model.hpp)
// predicted to the output stamp and mapped to the 15-state NavState of the IMU (orientation,
// position, velocity, gyro and accelerometer biases) with a 15x15 covariance. What the planar
// filter does not estimate (altitude is filtered apart; roll, pitch, vertical velocity and the
// other bias components) gets the variances of the options.
#pragma once

#include "core/geodetic.hpp"
#include "core/state.hpp"
#include "estimator/ekf_options.hpp"
#include "estimator/ekf_single_track_model.hpp"

namespace statebench::est::ekf {

struct EkfOutputContext {
  const SingleTrackModel& model;
  const EkfOptions& options;
  Mat3 R_body_imu;
  Vec3 p_body_imu;
  const LocalEnuFrame* frame = nullptr;  // latitude/longitude when known
};

StateEstimate EkfOutput(const Snapshot& snap, TimeNs t_out_ns, const EkfOutputContext& context);

}  // namespace statebench::est::ekf
