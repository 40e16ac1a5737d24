#include "apps/scored_outages.hpp"

#include <algorithm>
#include <cmath>

namespace statebench::app {
namespace {

void AddWindow(double start_s, double end_s, TimeNs end_ns,
               std::vector<reports::OutageWindow>* windows) {
  const TimeNs begin_ns = FromSeconds(std::max(start_s, 0.0));
  if (begin_ns >= end_ns) return;
  windows->push_back(
      {begin_ns, std::isfinite(end_s) ? std::min(FromSeconds(end_s), end_ns) : end_ns});
}

}  // namespace

std::vector<reports::OutageWindow> ScoredOutages(const sim::ScenarioSensors& sensors,
                                                 TimeNs end_ns) {
  const auto receivers = sensors.setup.OfType(sensors::SensorType::kGnss);
  std::vector<reports::OutageWindow> windows;
  if (receivers.empty()) return windows;
  for (const sensors::GnssOutage& o :
       std::get<sensors::GnssOptions>(receivers.front()->options).outages) {
    const bool shared = std::all_of(receivers.begin(), receivers.end(), [&o](const auto* r) {
      const auto& outages = std::get<sensors::GnssOptions>(r->options).outages;
      return std::any_of(outages.begin(), outages.end(), [&o](const sensors::GnssOutage& p) {
        return p.start_s == o.start_s && p.end_s == o.end_s;
      });
    });
    if (shared) AddWindow(o.start_s, o.end_s, end_ns, &windows);
  }
  for (const sim::SensorOutage& o : sensors.faults.sensor_outages) {
    const bool all_gnss = std::all_of(receivers.begin(), receivers.end(), [&o](const auto* r) {
      return std::find(o.sensors.begin(), o.sensors.end(), r->spec.id) != o.sensors.end();
    });
    if (all_gnss) AddWindow(o.start_s, o.end_s, end_ns, &windows);
  }
  std::sort(windows.begin(), windows.end(),
            [](const reports::OutageWindow& a, const reports::OutageWindow& b) {
              return a.begin_ns < b.begin_ns;
            });
  return windows;
}

}  // namespace statebench::app
