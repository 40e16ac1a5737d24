// The estimator contract's output (core/state.hpp StateEstimate) from a propagated state in the
// local ENU frame: the mean and covariance with the position in WGS84 as well.
#pragma once

#include <optional>

#include "core/geodetic.hpp"
#include "core/state.hpp"
#include "estimator/imu_propagation.hpp"

namespace statebench::est {

// nullopt when any value is not finite: an estimator never outputs NaN.
std::optional<StateEstimate> ToStateEstimate(const PropagatedState& p, const LocalEnuFrame& frame);

}  // namespace statebench::est
