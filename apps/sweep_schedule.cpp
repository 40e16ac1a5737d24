#include "apps/sweep_schedule.hpp"

#include <utility>

namespace statebench::app {

SweepSchedule::SweepSchedule(std::vector<std::string> groups)
    : groups_(std::move(groups)), started_(groups_.size(), false) {}

std::optional<std::size_t> SweepSchedule::Next() {
  const auto start = [&](std::size_t i) {
    started_[i] = true;
    ++started_count_;
    ++running_[groups_[i]];
    return i;
  };
  // A run whose group's stages are cached first: it reads them while they are still there.
  for (std::size_t i = 0; i < groups_.size(); ++i) {
    if (!started_[i] && warm_.count(groups_[i])) return start(i);
  }
  // Then the first run of a group nobody computes yet.
  for (std::size_t i = 0; i < groups_.size(); ++i) {
    if (!started_[i] && running_[groups_[i]] == 0) return start(i);
  }
  return std::nullopt;  // every run left waits for its group's first run
}

void SweepSchedule::Finished(std::size_t i) {
  const std::string& g = groups_.at(i);
  --running_[g];
  warm_.insert(g);
}

}  // namespace statebench::app
