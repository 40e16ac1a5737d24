// All simulated sensors of a setup, fed with truth samples one by one (1 kHz), releasing the
// measurements of every sensor as one stream in arrival order (measurement_stream.hpp).
//
// A measurement is released once nothing still to come can arrive before it: a model observing
// the truth at t only emits measurements arriving at or after t + its MinArrivalDelayNs(), so
// after Push(truth at t) everything arriving at or before t + min over models of that delay is
// final. The release is therefore delayed by the smallest latency, never more.
//
// Lidar entries of the setup are not simulated here (the lidar simulation adds its models with
// AddModel).
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "core/geodetic.hpp"
#include "sensors/gnss_receiver.hpp"
#include "sensors/measurement_stream.hpp"
#include "sensors/sensor_model.hpp"
#include "sensors/sensor_setup.hpp"

namespace statebench::sensors {

class SensorSuite {
 public:
  // `frame` is the scenario's local ENU frame (WGS84 origin); `seed` the scenario seed, from
  // which every sensor derives its own streams by its id.
  SensorSuite(const SensorSetup& setup, const LocalEnuFrame& frame, std::uint64_t seed);

  void AddModel(std::unique_ptr<SensorModel> model);
  // Replaces every model by replace(model) in place (the stage cache wraps or swaps them, see
  // cached_sensor_model.hpp); call after SetSatelliteVisibility.
  void ReplaceModels(
      const std::function<std::unique_ptr<SensorModel>(std::unique_ptr<SensorModel>)>& replace);
  // Urban-canyon hook, given to every GNSS receiver.
  void SetSatelliteVisibility(const std::shared_ptr<const SatelliteVisibility>& visibility);

  // Feeds the next truth sample (stamps strictly increasing) and appends to *ready the
  // measurements that are now final, in arrival order.
  void Push(const TruthSample& truth, std::vector<Measurement>* ready);
  // End of the run: appends everything still buffered, in arrival order.
  void Finish(std::vector<Measurement>* ready);

  std::size_t buffered() const { return queue_.size(); }
  const std::vector<std::unique_ptr<SensorModel>>& models() const { return models_; }

 private:
  void AddDualAntennaHeadings(std::vector<Measurement>* step) const;

  LocalEnuFrame frame_;
  std::vector<std::unique_ptr<SensorModel>> models_;
  std::vector<GnssReceiver*> receivers_;
  std::vector<DualAntennaHeadingOptions> headings_;
  TimeNs min_delay_ns_ = 0;
  std::optional<TimeNs> last_truth_ns_;
  std::vector<Measurement> step_;
  ArrivalQueue queue_;
};

// The suite as a MeasurementSource: pulls truth from `next_truth` until a measurement is ready;
// when the truth ends the remaining measurements are released.
class SimulatedMeasurementSource : public MeasurementSource {
 public:
  using TruthFeed = std::function<std::optional<TruthSample>()>;
  SimulatedMeasurementSource(std::unique_ptr<SensorSuite> suite, TruthFeed next_truth);
  std::optional<Measurement> Next() override;

 private:
  std::unique_ptr<SensorSuite> suite_;
  TruthFeed next_truth_;
  bool finished_ = false;
  std::vector<Measurement> batch_;
  std::deque<Measurement> ready_;
};

}  // namespace statebench::sensors
