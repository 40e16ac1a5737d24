// The interface every simulated sensor implements: it sees every truth sample (1 kHz) in time
// order and appends the measurements it produces.
#pragma once

#include <vector>

#include "core/measurements.hpp"
#include "core/truth.hpp"
#include "sensors/sensor_spec.hpp"

namespace statebench::sensors {

class SensorModel {
 public:
  explicit SensorModel(SensorSpec spec) : spec_(std::move(spec)) {}
  virtual ~SensorModel() = default;
  SensorModel(const SensorModel&) = delete;
  SensorModel& operator=(const SensorModel&) = delete;

  // Called with every truth sample, stamps strictly increasing. Appends to *out the
  // measurements completed at truth.t_ns (usually none, or one when t_ns is a sample time).
  virtual void Observe(const TruthSample& truth, std::vector<Measurement>* out) = 0;

  // Contract used to release measurements in arrival order: every measurement appended by
  // Observe(truth) arrives at or after truth.t_ns + MinArrivalDelayNs().
  virtual TimeNs MinArrivalDelayNs() const { return spec_.LatencyNs(); }

  const SensorSpec& spec() const { return spec_; }

 protected:
  MeasurementHeader MakeHeader(TimeNs stamp_ns) const {
    return MeasurementHeader{spec_.id, stamp_ns, stamp_ns + spec_.LatencyNs()};
  }

 private:
  SensorSpec spec_;
};

}  // namespace statebench::sensors
