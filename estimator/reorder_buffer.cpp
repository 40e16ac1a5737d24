#include "estimator/reorder_buffer.hpp"

#include <tuple>

namespace statebench::est {

bool ReorderBuffer::Entry::operator<(const Entry& o) const {
  return std::tie(stamp_ns, rank, sensor_id, sequence) <
         std::tie(o.stamp_ns, o.rank, o.sensor_id, o.sequence);
}

void ReorderBuffer::Push(const Measurement& measurement) {
  const MeasurementHeader& h = HeaderOf(measurement);
  const int rank = std::holds_alternative<ImuSample>(measurement) ? 0 : 1;
  held_.insert(Entry{h.stamp_ns, rank, h.sensor_id, next_sequence_++, measurement});
}

std::vector<Measurement> ReorderBuffer::Release(TimeNs watermark_ns) {
  std::vector<Measurement> out;
  if (watermark_ns <= watermark_ns_) return out;
  watermark_ns_ = watermark_ns;
  while (!held_.empty() && held_.begin()->stamp_ns <= watermark_ns) {
    auto node = held_.extract(held_.begin());
    out.push_back(std::move(node.value().measurement));
  }
  return out;
}

}  // namespace statebench::est
