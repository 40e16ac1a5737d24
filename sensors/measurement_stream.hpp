// One time-ordered stream of measurements, ordered by ARRIVAL time, whatever produced them
// (the simulated sensor suite, a recorded log). Estimators consume it through MeasurementSource.
//
// Order: arrival time, then stamp, then sensor id, then the variant alternative index (a total
// order on everything a well-formed stream can hold; equal keys keep their input order).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <queue>
#include <vector>

#include "core/measurements.hpp"

namespace statebench::sensors {

class MeasurementSource {
 public:
  virtual ~MeasurementSource() = default;
  // The next measurement in arrival order, or nothing when the stream has ended.
  virtual std::optional<Measurement> Next() = 0;
};

// Strict weak order of the stream (see the header comment).
bool ArrivesBefore(const Measurement& a, const Measurement& b);

// A source over measurements held in memory; sorts them by ArrivesBefore (stable).
class VectorSource : public MeasurementSource {
 public:
  explicit VectorSource(std::vector<Measurement> measurements);
  std::optional<Measurement> Next() override;

 private:
  std::vector<Measurement> measurements_;
  std::size_t next_ = 0;
};

// Min-queue by ArrivesBefore; equal keys come out in insertion order (deterministic).
class ArrivalQueue {
 public:
  void Push(Measurement m);
  bool empty() const { return heap_.empty(); }
  std::size_t size() const { return heap_.size(); }
  const Measurement& Top() const { return heap_.top().m; }
  Measurement Pop();

 private:
  struct Entry {
    Measurement m;
    std::uint64_t sequence;
  };
  struct Later {
    bool operator()(const Entry& a, const Entry& b) const;
  };
  std::priority_queue<Entry, std::vector<Entry>, Later> heap_;
  std::uint64_t next_sequence_ = 0;
};

// Merges sources that are each in arrival order into one stream in arrival order. Equal keys
// across sources come out in the order of the sources in the constructor.
class MeasurementMerger : public MeasurementSource {
 public:
  explicit MeasurementMerger(std::vector<std::unique_ptr<MeasurementSource>> sources);
  std::optional<Measurement> Next() override;

 private:
  void Refill(std::size_t source);

  std::vector<std::unique_ptr<MeasurementSource>> sources_;
  std::vector<std::optional<Measurement>> heads_;
};

}  // namespace statebench::sensors
