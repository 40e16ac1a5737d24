// A sensor's measurement stream kept in the stage cache (core/stage_cache.hpp) and played back.
//
// RecordingSensorModel wraps a real model and writes every measurement it emits with the truth
// stamp it was emitted at; ReplayedSensorModel emits those measurements at the same truth stamps
// without simulating anything (no raycast for a lidar). The suite around them releases the same
// stream, bit for bit, as long as the truth is the same, which the cache key guarantees.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>

#include "core/binary_io.hpp"
#include "sensors/sensor_model.hpp"

namespace statebench::sensors {

class RecordingSensorModel : public SensorModel {
 public:
  // Writes into `file` (inside the cache's Begin() folder). Throws InputError when it cannot.
  RecordingSensorModel(std::unique_ptr<SensorModel> inner, const std::filesystem::path& file);

  void Observe(const TruthSample& truth, std::vector<Measurement>* out) override;
  TimeNs MinArrivalDelayNs() const override { return delay_ns_; }

  // Ends the stream (the truth is over); throws InputError when a write failed.
  void Close();
  SensorModel& inner() { return *inner_; }

 private:
  std::unique_ptr<SensorModel> inner_;
  TimeNs delay_ns_ = 0;
  BinaryWriter writer_;
};

class ReplayedSensorModel : public SensorModel {
 public:
  // Throws InputError when the file is not a recorded stream.
  ReplayedSensorModel(SensorSpec spec, const std::filesystem::path& file);

  // Throws InputError when the stream holds a measurement for a truth stamp that was skipped
  // (the cache entry does not belong to this truth) or is truncated.
  void Observe(const TruthSample& truth, std::vector<Measurement>* out) override;
  TimeNs MinArrivalDelayNs() const override { return delay_ns_; }

 private:
  void ReadNextStamp();

  std::filesystem::path file_;
  BinaryReader reader_;
  TimeNs delay_ns_ = 0;
  std::optional<TimeNs> next_stamp_ns_;  // nullopt: the stream has ended
};

}  // namespace statebench::sensors
