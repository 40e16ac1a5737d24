// Measurements to and from a binary stream (the stage cache's sensor streams): every field,
// every bit, lidar points included.
#pragma once

#include "core/binary_io.hpp"
#include "core/measurements.hpp"

namespace statebench::sensors {

void WriteMeasurement(BinaryWriter& out, const Measurement& m);
// Throws InputError on a truncated stream or an unknown measurement type.
Measurement ReadMeasurement(BinaryReader& in);

}  // namespace statebench::sensors
