// Seeded random streams. Every stream is derived from the scenario seed and a stream name
// (usually the sensor id), so the same seed gives the same bits whatever else is simulated.
#pragma once

#include <cstdint>
#include <random>
#include <string_view>

namespace statebench {

// 64-bit FNV-1a of the name, mixed with the seed by SplitMix64.
std::uint64_t StreamSeed(std::uint64_t seed, std::string_view stream_name);

inline std::mt19937_64 MakeRng(std::uint64_t seed, std::string_view stream_name) {
  return std::mt19937_64(StreamSeed(seed, stream_name));
}

// Standard normal deviates by Box-Muller on the engine's raw 64-bit output, so the sequence is
// the same with every standard library (std::normal_distribution is implementation-defined).
class NormalSampler {
 public:
  double operator()(std::mt19937_64& rng);

 private:
  bool has_spare_ = false;
  double spare_ = 0.0;
};

// Uniform in [0, 1) from the top 53 bits.
inline double Uniform01(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

}  // namespace statebench
