// What the single-track EKF (ekf_single_track.hpp) lacks or has to take on trust in a sensor
// setup, said before it runs (EstimatorDiagnostics::warnings): no GNSS antenna (a local frame), a
// missing speed input (speed_encoder or body_velocity) or steering input changes what the filter
// is, sensors it cannot use are ignored, and a vehicle file whose axles are not where the
// setup's encoders are is probably another vehicle's.
#pragma once

#include <string>
#include <vector>

#include "estimator/ekf_options.hpp"
#include "estimator/estimator_config.hpp"

namespace statebench::est {

// How far (m, along the body x axis) an encoder may sit from the axle the vehicle file puts it on.
inline constexpr double kAxleMountToleranceM = 0.1;

std::vector<std::string> EkfInputWarnings(const EstimatorSensorSetup& setup,
                                          const SingleTrackParams& vehicle);

}  // namespace statebench::est
