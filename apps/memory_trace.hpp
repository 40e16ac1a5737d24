// Resident memory of this process over a run's simulated time, for run.json: a long run must
// not grow (docs/cli.md, run.json "memory").
#pragma once

#include <nlohmann/json.hpp>
#include <vector>

#include "core/time.hpp"

namespace statebench::app {

class MemoryTrace {
 public:
  // One sample every `interval_s` of simulated time.
  explicit MemoryTrace(double interval_s = 60.0) : interval_ns_(FromSeconds(interval_s)) {}

  // Call with the stamps of the run as it goes (cheap: reads /proc only once per interval).
  void At(TimeNs t_ns);
  // {"interval_s", "rss_mb": [...], "peak_rss_mb_so_far": [...], "peak_rss_mb"}: the resident
  // memory at each sample, the process's peak up to it, and the peak at the end.
  nlohmann::json Json() const;

 private:
  TimeNs interval_ns_;
  TimeNs next_ns_ = 0;
  std::vector<double> rss_mb_;
  std::vector<double> peak_mb_;
};

// Resident set size of this process now, MB (0 when /proc is not readable).
double ResidentMegabytes();
// The peak resident set size of this process so far (getrusage), MB.
double PeakResidentMegabytes();

}  // namespace statebench::app
