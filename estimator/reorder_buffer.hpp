// Reorder buffer: turns an arrival-ordered stream into a stamp-ordered one.
//
// Measurements are held until a watermark (the newest IMU stamp minus the maximum expected
// latency) passes their stamp, then released sorted by (stamp, IMU before other sensors, sensor
// id). The order of release therefore depends only on the stamps, not on the order of arrival:
// as long as every measurement arrives before the watermark passes its stamp, any delivery
// order releases the same sequence at the same watermarks. That is what makes out-of-order
// delivery give exactly the in-order result downstream.
#pragma once

#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "core/measurements.hpp"
#include "core/time.hpp"

namespace statebench::est {

class ReorderBuffer {
 public:
  void Push(const Measurement& measurement);

  // Removes and returns, in release order, every held measurement stamped at or before
  // watermark_ns. The watermark never moves back (an older one releases nothing).
  std::vector<Measurement> Release(TimeNs watermark_ns);

  // Highest watermark released so far (INT64_MIN before any): a measurement stamped at or before
  // it arrives too late to keep the order.
  TimeNs watermark_ns() const { return watermark_ns_; }
  std::size_t size() const { return held_.size(); }

 private:
  struct Entry {
    TimeNs stamp_ns;
    int rank;  // 0 for IMU samples, 1 otherwise
    std::string sensor_id;
    std::uint64_t sequence;  // arrival order, only to keep exact duplicates apart
    Measurement measurement;
    bool operator<(const Entry& o) const;
  };
  std::multiset<Entry> held_;
  std::uint64_t next_sequence_ = 0;
  TimeNs watermark_ns_ = INT64_MIN;
};

}  // namespace statebench::est
