#include "apps/memory_trace.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <fstream>

namespace statebench::app {

double ResidentMegabytes() {
  std::ifstream statm("/proc/self/statm");
  long pages_total = 0, pages_resident = 0;
  if (!(statm >> pages_total >> pages_resident)) return 0.0;
  return static_cast<double>(pages_resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / 1e6;
}

double PeakResidentMegabytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1e3;  // ru_maxrss: kB
}

void MemoryTrace::At(TimeNs t_ns) {
  if (t_ns < next_ns_) return;
  rss_mb_.push_back(ResidentMegabytes());
  peak_mb_.push_back(PeakResidentMegabytes());
  next_ns_ = t_ns + interval_ns_;
}

nlohmann::json MemoryTrace::Json() const {
  return {{"interval_s", ToSeconds(interval_ns_)},
          {"rss_mb", rss_mb_},
          {"peak_rss_mb_so_far", peak_mb_},
          {"peak_rss_mb", PeakResidentMegabytes()}};
}

}  // namespace statebench::app
