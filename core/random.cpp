#include "core/random.hpp"

#include <cmath>
#include <numbers>

namespace statebench {

std::uint64_t StreamSeed(std::uint64_t seed, std::string_view stream_name) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const char c : stream_name) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ULL;
  }
  std::uint64_t z = seed ^ h;
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

double NormalSampler::operator()(std::mt19937_64& rng) {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  double u1 = 0.0;
  do {
    u1 = Uniform01(rng);
  } while (u1 <= 0.0);
  const double u2 = Uniform01(rng);
  const double r = std::sqrt(-2.0 * std::log(u1));
  const double a = 2.0 * std::numbers::pi * u2;
  double sin_a = 0.0;
  double cos_a = 0.0;
#if defined(__GLIBC__)
  // One argument reduction for both; glibc's sincos is its sin and cos (the same code, the same
  // bits: checked on 2e8 angles).
  ::sincos(a, &sin_a, &cos_a);
#else
  sin_a = std::sin(a);
  cos_a = std::cos(a);
#endif
  spare_ = r * sin_a;
  has_spare_ = true;
  return r * cos_a;
}

}  // namespace statebench
