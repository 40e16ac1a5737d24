// Keeps `target` random traffic vehicles in a running libsumo simulation: each has a random
// origin and destination edge (drawn from a core/random.hpp stream of the scenario seed), is
// routed by SUMO's router, departs at a random free position and, once it arrives, is replaced.
// Vehicle ids are "density<k>". Only call while a libsumo simulation is loaded.
#pragma once

#include <cstdint>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace statebench::sim {

class DensityTraffic {
 public:
  // `edges`: candidate origins and destinations; `avoid_at_start`: edges left free for the
  // initial placement (the ego's departure edge).
  DensityTraffic(int target, std::uint64_t seed, const std::set<std::string>& edges,
                 std::set<std::string> avoid_at_start);

  // Call once before the first step.
  void Start();
  // Call after every step: forgets arrived vehicles and adds replacements.
  void AfterStep(const std::vector<std::string>& arrived_ids);

 private:
  // Adds one vehicle; false when no connected origin/destination pair was found.
  bool Add(bool initial);

  int target_ = 0;
  std::mt19937_64 rng_;
  std::vector<std::string> edges_;
  std::set<std::string> avoid_at_start_;
  std::set<std::string> alive_;  // added and not yet arrived (pending ones included)
  int next_id_ = 0;
};

}  // namespace statebench::sim
