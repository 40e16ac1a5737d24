#include "sensors/measurement_stream.hpp"

#include <algorithm>
#include <tuple>

namespace statebench::sensors {

bool ArrivesBefore(const Measurement& a, const Measurement& b) {
  const MeasurementHeader& ha = HeaderOf(a);
  const MeasurementHeader& hb = HeaderOf(b);
  const std::size_t ia = a.index();
  const std::size_t ib = b.index();
  return std::tie(ha.arrival_ns, ha.stamp_ns, ha.sensor_id, ia) <
         std::tie(hb.arrival_ns, hb.stamp_ns, hb.sensor_id, ib);
}

VectorSource::VectorSource(std::vector<Measurement> measurements)
    : measurements_(std::move(measurements)) {
  std::stable_sort(measurements_.begin(), measurements_.end(), ArrivesBefore);
}

std::optional<Measurement> VectorSource::Next() {
  if (next_ >= measurements_.size()) return std::nullopt;
  return std::move(measurements_[next_++]);
}

bool ArrivalQueue::Later::operator()(const Entry& a, const Entry& b) const {
  if (ArrivesBefore(b.m, a.m)) return true;
  if (ArrivesBefore(a.m, b.m)) return false;
  return a.sequence > b.sequence;
}

void ArrivalQueue::Push(Measurement m) { heap_.push(Entry{std::move(m), next_sequence_++}); }

Measurement ArrivalQueue::Pop() {
  // priority_queue::top is const; the entry is copied out (LidarScan points are shared, so the
  // copy is cheap) and then removed.
  Measurement m = heap_.top().m;
  heap_.pop();
  return m;
}

MeasurementMerger::MeasurementMerger(std::vector<std::unique_ptr<MeasurementSource>> sources)
    : sources_(std::move(sources)), heads_(sources_.size()) {
  for (std::size_t i = 0; i < sources_.size(); ++i) Refill(i);
}

void MeasurementMerger::Refill(std::size_t source) { heads_[source] = sources_[source]->Next(); }

std::optional<Measurement> MeasurementMerger::Next() {
  // Linear scan over the heads: a vehicle has a handful of sources.
  std::optional<std::size_t> best;
  for (std::size_t i = 0; i < heads_.size(); ++i) {
    if (!heads_[i]) continue;
    if (!best || ArrivesBefore(*heads_[i], *heads_[*best])) best = i;
  }
  if (!best) return std::nullopt;
  Measurement m = std::move(*heads_[*best]);
  Refill(*best);
  return m;
}

}  // namespace statebench::sensors
