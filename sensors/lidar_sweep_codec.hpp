// The lossless transform that makes a lidar sweep compress (docs/log-format.md, "Sweep files"):
// each field of each point is replaced by the difference between its bits and a prediction made
// from the points before it, and the differences are split into byte planes, so that zstd finds
// runs of zero bytes and skewed byte statistics where the raw floats look like noise. Decoding
// makes the same predictions from the decoded points and adds the differences back: every point
// comes back bit for bit, whatever its values (NaN payloads, infinities, subnormals included).
//
// A spinning lidar fires columns: points of one column share t and their direction's azimuth,
// and a channel (ring) keeps its elevation. Per point, in point order ("the ring's last": the
// last earlier point of the same ring; a column starts where t changes):
//   ring       previous point's ring + 1 (mod 2^16; first point: 0)
//   t          previous point's t (first point: 0)
//   x          h_r * c, h_r the ring's last horizontal distance sqrt(x^2 + y^2), (c, s) the
//              column's unit azimuth: (x, y) / h of the column's first point, or for that first
//              point the previous column's azimuth turned by the step between the two before
//   y          x * s / c
//   z          h * e_r, h this point's horizontal distance, e_r = z / h of the ring's last point
//   intensity  2 i_1 - i_2, the ring's last two intensities (with one, the last)
// A prediction falls back to the ring's last value of the field (0 for none) unless its inputs
// and result are zero or normal numbers. All arithmetic is IEEE-754 double, correctly rounded
// (+ - * / sqrt, compiled without contraction into fused multiply-adds), so encoder and decoder
// compute the same bits on any conforming machine, flushing subnormals to zero or not.
//
// A difference is d = bits(value) - bits(prediction) modulo 2^32 (ring: 2^16), zigzag-coded
// (0, -1, 1, -2 -> 0, 1, 2, 3), stored as byte planes: for n points, the field's lowest bytes of
// all points, then the next bytes, and so on (4 n bytes per float field, 2 n for ring).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "core/measurements.hpp"

namespace statebench::sensors {

// The fields in the order of a sweep file's sections.
enum class SweepField { kT, kRing, kX, kY, kZ, kIntensity };
inline constexpr std::size_t kSweepFieldCount = 6;

std::string_view SweepFieldName(SweepField field);  // "t", "ring", "x", ...
// Bytes of the field's planes for n points: 4 n, or 2 n for ring.
std::size_t SweepFieldBytes(SweepField field, std::size_t points);

// The byte planes of every field, indexed by SweepField.
using SweepPlanes = std::array<std::vector<std::uint8_t>, kSweepFieldCount>;

// Fills `planes` (each resized to SweepFieldBytes).
void EncodeSweep(const std::vector<LidarPoint>& points, SweepPlanes& planes);

// The n points whose planes these are (each holding SweepFieldBytes(field, n) bytes), into
// `points` (replaced). Any planes decode to some points: corruption is for the file to detect.
void DecodeSweep(const SweepPlanes& planes, std::size_t n, std::vector<LidarPoint>& points);

}  // namespace statebench::sensors
