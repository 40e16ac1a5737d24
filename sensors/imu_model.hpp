// Simulated IMU: exact angular rate and specific force at its mount, plus the mount's vibration
// when the options have one (ImuVibration), plus the errors of ImuTriadErrors.
//
// Sampling is instantaneous: the sample stamped t is the exact rate and specific force at t
// (the 1 kHz truth has a sample at every IMU stamp because the rate divides 1000 Hz). Real
// IMUs low-pass filter and average inside the interval, which acts like a small delay (half a
// period for a plain average over the preceding interval); that is not modelled, so the stamp
// of a simulated sample is exactly the instant it describes.
#pragma once

#include <cstdint>
#include <optional>

#include "sensors/imu_options.hpp"
#include "sensors/imu_triad_errors.hpp"
#include "sensors/imu_vibration.hpp"
#include "sensors/sensor_model.hpp"

namespace statebench::sensors {

class ImuModel : public SensorModel {
 public:
  ImuModel(const SensorSpec& spec, const ImuOptions& options, std::uint64_t seed);

  void Observe(const TruthSample& truth, std::vector<Measurement>* out) override;

  // The sample at truth.t_ns regardless of the schedule; advances the error processes by one
  // period. Observe calls it at the sample times (after moving the vibration on to truth.t_ns).
  ImuSample Sample(const TruthSample& truth);

  const ImuTriadErrors& gyro_errors() const { return gyro_; }
  const ImuTriadErrors& accel_errors() const { return accel_; }

 private:
  ImuTriadErrors gyro_;
  ImuTriadErrors accel_;
  std::optional<ImuVibration> vibration_;
  std::optional<TimeNs> vibration_t_ns_;  // the truth stamp the vibration is at
};

}  // namespace statebench::sensors
