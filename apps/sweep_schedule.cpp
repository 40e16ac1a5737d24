#include "apps/sweep_schedule.hpp"

#include <utility>

namespace statebench::app {

SweepSchedule::SweepSchedule(std::vector<std::string> groups)
    : groups_(std::move(groups)), started_(groups_.size(), false) {}

std::optional<std::size_t> SweepSchedule::Next() {
  for (std::size_t i = 0; i < groups_.size(); ++i) {
    if (started_[i]) continue;
    const std::string& g = groups_[i];
    if (running_[g] > 0 && !warm_.count(g)) continue;  // its first run is still computing the stages
    started_[i] = true;
    ++started_count_;
    ++running_[g];
    return i;
  }
  return std::nullopt;
}

void SweepSchedule::Finished(std::size_t i) {
  const std::string& g = groups_.at(i);
  --running_[g];
  warm_.insert(g);
}

}  // namespace statebench::app
