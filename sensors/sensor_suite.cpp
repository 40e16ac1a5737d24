#include "sensors/sensor_suite.hpp"

#include <algorithm>
#include <cassert>
#include <limits>

#include "sensors/encoder_model.hpp"
#include "sensors/imu_model.hpp"

namespace statebench::sensors {
namespace {

std::unique_ptr<SensorModel> MakeModel(const SensorConfig& c, const LocalEnuFrame& frame,
                                       std::uint64_t seed) {
  switch (c.type()) {
    case SensorType::kImu:
      return std::make_unique<ImuModel>(c.spec, std::get<ImuOptions>(c.options), seed);
    case SensorType::kGnss:
      return std::make_unique<GnssReceiver>(c.spec, std::get<GnssOptions>(c.options), frame, seed);
    case SensorType::kWheelEncoders:
      return std::make_unique<WheelEncoderModel>(c.spec, std::get<WheelEncoderOptions>(c.options),
                                                 seed);
    case SensorType::kSpeedEncoder:
      return std::make_unique<SpeedEncoderModel>(c.spec, std::get<SpeedEncoderOptions>(c.options),
                                                 seed);
    case SensorType::kSteeringEncoder:
      return std::make_unique<SteeringEncoderModel>(
          c.spec, std::get<SteeringEncoderOptions>(c.options), seed);
    case SensorType::kLidar:
      return nullptr;  // simulated by the lidar module
  }
  return nullptr;
}

const GnssFix* FindFix(const std::vector<Measurement>& step, const std::string& id) {
  for (const Measurement& m : step) {
    const auto* fix = std::get_if<GnssFix>(&m);
    if (fix && fix->header.sensor_id == id) return fix;
  }
  return nullptr;
}

}  // namespace

SensorSuite::SensorSuite(const SensorSetup& setup, const LocalEnuFrame& frame, std::uint64_t seed)
    : frame_(frame), headings_(setup.dual_antenna_headings) {
  min_delay_ns_ = std::numeric_limits<TimeNs>::max();
  for (const SensorConfig& c : setup.sensors) {
    if (auto model = MakeModel(c, frame_, seed)) AddModel(std::move(model));
  }
  for (const auto& h : headings_) min_delay_ns_ = std::min(min_delay_ns_, FromSeconds(h.latency_s));
}

void SensorSuite::AddModel(std::unique_ptr<SensorModel> model) {
  min_delay_ns_ = std::min(min_delay_ns_, model->MinArrivalDelayNs());
  if (auto* receiver = dynamic_cast<GnssReceiver*>(model.get())) receivers_.push_back(receiver);
  models_.push_back(std::move(model));
}

void SensorSuite::ReplaceModels(
    const std::function<std::unique_ptr<SensorModel>(std::unique_ptr<SensorModel>)>& replace) {
  std::vector<std::unique_ptr<SensorModel>> models = std::move(models_);
  models_.clear();
  receivers_.clear();
  min_delay_ns_ = std::numeric_limits<TimeNs>::max();
  for (const auto& h : headings_) min_delay_ns_ = std::min(min_delay_ns_, FromSeconds(h.latency_s));
  for (auto& model : models) AddModel(replace(std::move(model)));
}

void SensorSuite::SetSatelliteVisibility(
    const std::shared_ptr<const SatelliteVisibility>& visibility) {
  for (GnssReceiver* r : receivers_) r->SetSatelliteVisibility(visibility);
}

void SensorSuite::AddDualAntennaHeadings(std::vector<Measurement>* step) const {
  for (const DualAntennaHeadingOptions& h : headings_) {
    const GnssFix* main = FindFix(*step, h.main_antenna);
    const GnssFix* aux = FindFix(*step, h.aux_antenna);
    if (!main || !aux) continue;
    if (auto heading = ComputeDualAntennaHeading(h, *main, *aux, frame_)) {
      step->push_back(*heading);
    }
  }
}

void SensorSuite::Push(const TruthSample& truth, std::vector<Measurement>* ready) {
  assert(!last_truth_ns_ || truth.t_ns > *last_truth_ns_);
  last_truth_ns_ = truth.t_ns;
  step_.clear();
  for (const auto& model : models_) model->Observe(truth, &step_);
  AddDualAntennaHeadings(&step_);
  for (Measurement& m : step_) queue_.Push(std::move(m));

  // Anything observed later (at t' > t) arrives at or after t' + min_delay > t + min_delay.
  const TimeNs release_ns = min_delay_ns_ > std::numeric_limits<TimeNs>::max() - truth.t_ns
                                ? std::numeric_limits<TimeNs>::max()
                                : truth.t_ns + min_delay_ns_;
  while (!queue_.empty() && HeaderOf(queue_.Top()).arrival_ns <= release_ns) {
    ready->push_back(queue_.Pop());
  }
}

void SensorSuite::Finish(std::vector<Measurement>* ready) {
  while (!queue_.empty()) ready->push_back(queue_.Pop());
}

SimulatedMeasurementSource::SimulatedMeasurementSource(std::unique_ptr<SensorSuite> suite,
                                                       TruthFeed next_truth)
    : suite_(std::move(suite)), next_truth_(std::move(next_truth)) {}

std::optional<Measurement> SimulatedMeasurementSource::Next() {
  while (ready_.empty() && !finished_) {
    batch_.clear();
    if (std::optional<TruthSample> truth = next_truth_()) {
      suite_->Push(*truth, &batch_);
    } else {
      suite_->Finish(&batch_);
      finished_ = true;
    }
    for (Measurement& m : batch_) ready_.push_back(std::move(m));
  }
  if (ready_.empty()) return std::nullopt;
  Measurement m = std::move(ready_.front());
  ready_.pop_front();
  return m;
}

}  // namespace statebench::sensors
