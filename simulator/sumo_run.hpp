// Runs a built scenario in SUMO, in-process through libsumo, and records the ego's reference and
// the traffic (sumo_result.hpp).
//
// SUMO runs with the scenario's step (<= 0.1 s), ballistic position updates (positions follow
// the speeds and accelerations SUMO reports), --seed derived from the scenario seed, and the
// ego with lane changes disabled so its path is a lane centre line. It steps until the duration
// or until the ego reaches the end of its route, then a little further (without recording) so
// the driven path reaches `lookahead_m` past the last sample. Same scenario and seed: the same
// SumoResult, bit for bit; another seed: other traffic.
//
// libsumo holds one simulation per process: runs are serialised by a process-wide lock.
#pragma once

#include <filesystem>

#include "simulator/ego_vehicle_type.hpp"
#include "simulator/network_builder.hpp"
#include "simulator/scenario.hpp"
#include "simulator/sumo_result.hpp"

namespace statebench::sim {

struct SumoRunOptions {
  double lookahead_m = 50.0;   // driven path beyond the last sample, unless the route ends
  double max_tail_s = 60.0;    // at most this much extra SUMO time to get it
  bool record_traffic = true;  // false: SumoResult::traffic stays empty
  // SUMO's warnings (emergency braking, teleports, ...) go to <work_dir>/sumo.log and stderr
  // when true; when false (library default: nothing printed) they are dropped.
  bool sumo_warnings = false;
};

// Throws InputError when SUMO rejects the files or the ego cannot drive its route (it could not
// depart, or got stuck and was teleported), std::runtime_error on other SUMO failures.
SumoResult RunSumo(const Scenario& scenario, const BuiltNetwork& built,
                   const SumoRunOptions& options = {});

// NetworkBuilder(tools).Build + RunSumo, with the SUMO files in `work_dir`.
SumoResult SimulateSumo(const Scenario& scenario, const EgoVehicleType& ego_type,
                        const std::filesystem::path& work_dir, const SumoRunOptions& options = {});

}  // namespace statebench::sim
