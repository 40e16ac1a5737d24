#include "sensors/cached_sensor_model.hpp"

#include <limits>

#include "core/error.hpp"
#include "sensors/measurement_record.hpp"

namespace statebench::sensors {
namespace {

constexpr std::uint32_t kMagic = 0x53545231;  // "STR1"
constexpr TimeNs kEndOfStream = std::numeric_limits<TimeNs>::min();

}  // namespace

RecordingSensorModel::RecordingSensorModel(std::unique_ptr<SensorModel> inner,
                                           const std::filesystem::path& file)
    : SensorModel(inner->spec()),
      inner_(std::move(inner)),
      delay_ns_(inner_->MinArrivalDelayNs()),
      writer_(file) {
  writer_.Put(kMagic);
  writer_.Put(delay_ns_);
}

void RecordingSensorModel::Observe(const TruthSample& truth, std::vector<Measurement>* out) {
  const std::size_t before = out->size();
  inner_->Observe(truth, out);
  for (std::size_t i = before; i < out->size(); ++i) {
    writer_.Put(truth.t_ns);
    WriteMeasurement(writer_, (*out)[i]);
  }
}

void RecordingSensorModel::Close() {
  writer_.Put(kEndOfStream);
  writer_.Close();
}

ReplayedSensorModel::ReplayedSensorModel(SensorSpec spec, const std::filesystem::path& file)
    : SensorModel(std::move(spec)), file_(file), reader_(file) {
  if (reader_.Get<std::uint32_t>() != kMagic) {
    throw InputError(file.string() + ": not a recorded sensor stream");
  }
  delay_ns_ = reader_.Get<TimeNs>();
  ReadNextStamp();
}

void ReplayedSensorModel::ReadNextStamp() {
  const auto stamp = reader_.Get<TimeNs>();
  if (stamp == kEndOfStream) {
    next_stamp_ns_.reset();
  } else {
    next_stamp_ns_ = stamp;
  }
}

void ReplayedSensorModel::Observe(const TruthSample& truth, std::vector<Measurement>* out) {
  while (next_stamp_ns_ && *next_stamp_ns_ <= truth.t_ns) {
    if (*next_stamp_ns_ < truth.t_ns) {
      throw InputError(file_.string() + ": recorded stream of sensor '" + spec().id +
                       "' does not follow this truth (a measurement at truth stamp " +
                       std::to_string(*next_stamp_ns_) + " ns was not replayed)");
    }
    out->push_back(ReadMeasurement(reader_));
    ReadNextStamp();
  }
}

}  // namespace statebench::sensors
