// The range of a lidar return in 32 bits, as a packets file stores it (lidar_packet_file.hpp):
// a binary floating-point number with 29 significant bits (one more than float32 has room for
// after its sign and exponent) over the ranges a lidar reports, 1/16 m to 4096 m:
//
//   bits 31..28  o, the binade: the range lies in [2^(o-4), 2^(o-3)) m
//   bits 27..0   the 28 bits after the leading 1 of its significand
//
// Every word is a range and decodes exactly to a double. The simulator's ranges are doubles
// (52-bit significands), its points (BeamReturn) their products with the beam direction rounded
// to float: a file keeps a word that rebuilds the point's three floats bit for bit. With 29
// significant bits such a word exists for all but about 0.1 % of the points (the rest are kept
// as raw floats); 24 bits (a float32 range) would miss half of them.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <optional>

namespace statebench::sensors {

inline constexpr int kRangeWordLowestBinade = -4;  // 2^-4 m
inline constexpr int kRangeWordBinades = 16;       // up to 2^12 m
inline constexpr int kRangeWordFractionBits = 28;

inline double RangeFromWord(std::uint32_t word) {
  const std::uint64_t binade = word >> kRangeWordFractionBits;
  const std::uint64_t fraction = word & ((1u << kRangeWordFractionBits) - 1u);
  const std::uint64_t exponent = binade + 1023 + kRangeWordLowestBinade;
  return std::bit_cast<double>((exponent << 52) | (fraction << (52 - kRangeWordFractionBits)));
}

// The word of `range_m` when it has one exactly (a positive normal number inside the binades,
// its significand ending within 29 bits), else nullopt.
inline std::optional<std::uint32_t> WordOfRange(double range_m) {
  if (!(range_m > 0.0) || !std::isfinite(range_m)) return std::nullopt;
  const auto bits = std::bit_cast<std::uint64_t>(range_m);
  const int binade = static_cast<int>(bits >> 52) - 1023;
  if (binade < kRangeWordLowestBinade || binade >= kRangeWordLowestBinade + kRangeWordBinades) {
    return std::nullopt;
  }
  constexpr int kDropped = 52 - kRangeWordFractionBits;
  if ((bits & ((std::uint64_t{1} << kDropped) - 1)) != 0) return std::nullopt;
  const auto fraction =
      static_cast<std::uint32_t>((bits >> kDropped) & ((1u << kRangeWordFractionBits) - 1u));
  return (static_cast<std::uint32_t>(binade - kRangeWordLowestBinade) << kRangeWordFractionBits) |
         fraction;
}

}  // namespace statebench::sensors
