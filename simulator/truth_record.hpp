// One step of the vehicle model as the stage cache keeps it (the `vehicle` stage,
// docs/sweeps.md "The stage cache"): the truth sample, and the tracking errors the run's truth
// summary is made of. Written and read back field by field, every bit.
#pragma once

#include "core/binary_io.hpp"
#include "core/truth.hpp"

namespace statebench::sim {

struct TrackedTruth {
  TruthSample sample;
  double lateral_error_m = 0.0;       // body origin to the smoothed route centre line
  double longitudinal_error_m = 0.0;  // model ahead of (+) or behind SUMO's ego along the route
};

void WriteTrackedTruth(BinaryWriter& out, const TrackedTruth& truth);
// The end of the recorded truth (ReadTrackedTruth returns false there).
void WriteTruthEnd(BinaryWriter& out);
// False at the end mark; throws InputError on a truncated file.
bool ReadTrackedTruth(BinaryReader& in, TrackedTruth* truth);

}  // namespace statebench::sim
