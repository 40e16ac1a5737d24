// One lidar sweep as a StateBench lidar packets file (`.packets`, docs/log-format.md "Packets
// files"): what a spinning lidar's packets carry instead of the points. The header holds the beam
// model (the rings' elevations, columns per revolution, rotation rate, first azimuth, spin
// direction), from which every beam's direction and every column's firing time are regenerated
// (LidarBeamModel::Directions, ColumnTimeS); then per column a hit mask, per return its range
// (lidar_range_word.hpp) and intensity. The reader rebuilds each point with BeamReturn, the
// simulator's own function, so a sweep reads back bit for bit. A point the range word cannot
// rebuild (about 0.1 % of them, and points a fault moved or made NaN) is kept as raw floats.
//
// Layout (integers little-endian, doubles IEEE-754 binary64 little-endian):
//
//   offset   bytes  content
//   0        8      magic "SBLIDPK" and a zero byte
//   8        4      format version: 1
//   12       4      n, the number of returns
//   16       4      m, the number of raw points
//   20       8      checksum of the beam directions the writer computed (lidar_packet_beams.hpp)
//   28       1      intensity encoding: 0 uint8 (every intensity a whole number 0..255), 1 float32
//   29       1      1 when the head spins clockwise (seen from above), else 0
//   30       2      C, channels (1 to 1024)
//   32       4      N, columns per revolution (1 to 2^20; C N at most 2^21)
//   36       8      rotation rate, Hz
//   44       8      azimuth of column 0, rad
//   52       8 C    the rings' elevations, rad, ring 0 first
//   52+8C    N B    hit masks, B = ceil(C / 8) bytes a column: bit r % 8 of byte r / 8 is set
//                   when ring r of the column returned
//   ...      4 n    range words, in point order
//   ...      n/4 n  intensities, uint8 or float32
//   ...      16 m   raw points: uint32 point index (increasing), float32 x y z
//
// The points are the hits, column by column, rings ascending: the point of column c and ring r has
// t = ColumnTimeS(c), ring r, its intensity and x y z = BeamReturn(Direction(c, r), range), or
// the raw point's x y z when one names it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <vector>

#include "core/measurements.hpp"
#include "sensors/lidar_beam_model.hpp"

namespace statebench::sensors {

// The file's bytes, or nullopt when the points are not returns of `beams` in its order (rings
// ascending within a column, at most one point per beam, each with its column's t and a ring
// below C) or the model is outside the format's limits: such a sweep needs another format.
std::optional<std::vector<std::uint8_t>> EncodeLidarPackets(const std::vector<LidarPoint>& points,
                                                            const LidarBeamModel& beams);

// The points of a packets file's bytes. Throws InputError naming `file` and the field when they
// are not a packets file of this version, too short or too long for their header, or hold
// impossible values (a beam model outside the limits, masks that disagree with n, ring bits
// beyond C, raw point indices not increasing below n), or when the beam directions computed here
// differ from the writer's (the checksum: another C library's cos or sin).
std::vector<LidarPoint> DecodeLidarPackets(std::span<const std::uint8_t> bytes,
                                           const std::filesystem::path& file);

// False (nothing written) when EncodeLidarPackets gives nullopt; throws InputError naming the file
// when it cannot be written.
bool WriteLidarPacketFile(const std::filesystem::path& file, const std::vector<LidarPoint>& points,
                          const LidarBeamModel& beams);

std::vector<LidarPoint> ReadLidarPacketFile(const std::filesystem::path& file);

}  // namespace statebench::sensors
