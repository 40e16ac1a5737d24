// GNSS measurements of one stamp turned into factor inputs.
//
// For each dual-antenna pair of the setup: the receiver's heading of that stamp if there is one,
// else, when both antennas have a fix, the heading of the baseline between them
// (HeadingFromFixes). When both fixes are there the main antenna's position is used and the aux
// antenna's is not: its information is already in the heading, using both would count it twice.
// Every other fix is a position input.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/measurements.hpp"
#include "estimator/estimator_config.hpp"
#include "estimator/gnss_enu.hpp"

namespace statebench::est {

struct PositionInput {
  GnssPositionEnu fix;
  Vec3 p_imu_antenna = Vec3::Zero();
};

struct HeadingInput {
  DualAntennaHeading heading;
  Vec3 baseline_imu = Vec3::Zero();  // main -> aux
  std::string counter_id;            // diagnostics id: heading id, or "main+aux" when paired
};

struct StampGroup {
  std::vector<PositionInput> positions;
  std::vector<HeadingInput> headings;
  std::vector<std::string> merged;  // aux antennas whose fix went into a heading
};

// fixes by antenna id, headings by heading id, all of one stamp and known to the setup.
StampGroup GroupStamp(const std::map<std::string, GnssPositionEnu>& fixes,
                      const std::map<std::string, DualAntennaHeading>& headings,
                      const EstimatorSensorSetup& setup);

// The reported covariance with the antenna's estimator overrides: scaled by covariance_scale,
// eigenvalues floored at min_sigma_m^2.
Mat3 AntennaCovariance(const GnssAntenna& antenna, const Mat3& reported);

}  // namespace statebench::est
