// A GNSS fix in the estimator's local ENU world frame. Conversion by core/geodetic.hpp
// (GeographicLib LocalCartesian around the origin, exact). The receiver's covariance is in the
// ENU frame at the antenna; it is used unrotated (the two frames differ by the angle subtended
// at the earth's centre, 1.6e-3 rad at 10 km, negligible for a covariance).
#pragma once

#include <optional>
#include <string>

#include "core/eigen_types.hpp"
#include "core/geodetic.hpp"
#include "core/measurements.hpp"

namespace statebench::est {

struct GnssPositionEnu {
  MeasurementHeader header;
  Vec3 p_enu = Vec3::Zero();           // antenna phase centre, m
  Mat3 covariance = Mat3::Identity();  // m^2
  GnssFixStatus status = GnssFixStatus::kNone;
  std::optional<GnssVelocity> velocity;  // antenna velocity, ENU, when the receiver gives one
};

// Rejects (nullopt, reason in *why) a fix without a solution, with non-finite or absurd values
// (|lat| > 90 deg, |lon| > 180 deg, altitude outside [-1000, 100000] m) or with a covariance that
// is not finite, symmetric and positive definite. A velocity with a non-finite value or a sigma
// that is not positive is dropped (the position stays usable).
std::optional<GnssPositionEnu> GnssFixToEnu(const GnssFix& fix, const LocalEnuFrame& frame,
                                            std::string* why = nullptr);

}  // namespace statebench::est
