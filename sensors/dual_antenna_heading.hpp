// Dual-antenna heading: yaw and pitch of the baseline from the main to the auxiliary antenna,
// computed from the two fixes of the same stamp (so its noise is the antennas' errors).
//
// With b = p_aux - p_main in the local ENU world frame:
//   yaw   = atan2(b_north, b_east)        (counter-clockwise from east, as the body yaw)
//   pitch = atan2(-b_up, |b_horizontal|)   (the R = Rz(yaw) Ry(pitch) Rx(roll) convention of
//                                           so3::ToRollPitchYaw: positive nose down in FLU)
// When the baseline lies along the body +x axis these are the body yaw and pitch; otherwise the
// estimator accounts for the baseline direction in the body (from the two lever arms).
// Reported sigmas propagate the two reported covariances through these formulas to first order.
// A heading is produced only when both fixes have at least min_status.
#pragma once

#include <optional>
#include <string>

#include "core/geodetic.hpp"
#include "core/measurements.hpp"

namespace statebench::sensors {

struct DualAntennaHeadingOptions {
  std::string id;
  std::string main_antenna;  // sensor ids of two gnss entries with the same rate
  std::string aux_antenna;
  double latency_s = 0.0;
  GnssFixStatus min_status = GnssFixStatus::kRtkFixed;
};

std::optional<DualAntennaHeading> ComputeDualAntennaHeading(
    const DualAntennaHeadingOptions& options, const GnssFix& main, const GnssFix& aux,
    const LocalEnuFrame& frame);

}  // namespace statebench::sensors
