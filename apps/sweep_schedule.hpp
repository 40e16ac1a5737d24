// The order a sweep starts its runs in. Runs that differ only in their estimators (the same
// simulation group: SweepRun::simulation_group) share SUMO, every sensor stream and the lidar
// registrations through the stage cache, but only once one of them has finished and stored
// them: a second run of the group started while the first still computes would compute it all
// again. So a group's runs wait while its first run is under way, and other groups' runs go
// first; when nothing else is left, the free job slots wait too (the waiting runs then take a
// second each instead of the whole simulation). Once a group's stages are cached, its runs go
// before any new group: in the expansion's order a group's runs are a whole combination of
// seeds apart, and a cache smaller than the sweep's streams (setup 2: about 3 GB per seed,
// against the 20 GB default limit) would have evicted the entries before they were read.
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace statebench::app {

class SweepSchedule {
 public:
  // groups[i]: the simulation group of run i, in the order the runs should go.
  explicit SweepSchedule(std::vector<std::string> groups);

  // The next run to start (marked started): the first run left of a group with a finished run,
  // else the first run of a group with none under way; nullopt when every run left waits for a
  // running one of its group (or none is left).
  std::optional<std::size_t> Next();
  // Run i ended (ok or failed: either way its group stops waiting).
  void Finished(std::size_t i);
  bool AllStarted() const { return started_count_ == groups_.size(); }

 private:
  std::vector<std::string> groups_;
  std::vector<bool> started_;
  std::size_t started_count_ = 0;
  std::map<std::string, int> running_;  // runs under way, by group
  std::set<std::string> warm_;          // groups with a finished run
};

}  // namespace statebench::app
