#include "estimator/imu_noise.hpp"

#include <cmath>

namespace statebench::est {
namespace {

bool CheckPositive(double value, bool allow_zero, const char* name, std::string* why) {
  const bool ok = std::isfinite(value) && (value > 0.0 || (allow_zero && value == 0.0));
  if (!ok && why != nullptr) {
    *why = std::string("imu noise field '") + name + "' must be finite and " +
           (allow_zero ? "non-negative" : "positive") + ", got " + std::to_string(value);
  }
  return ok;
}

}  // namespace

bool ImuNoise::IsValid(std::string* why) const {
  return CheckPositive(gyro_noise_density, false, "gyro_noise_density", why) &&
         CheckPositive(accel_noise_density, false, "accel_noise_density", why) &&
         CheckPositive(gyro_random_walk, false, "gyro_random_walk", why) &&
         CheckPositive(accel_random_walk, false, "accel_random_walk", why) &&
         CheckPositive(integration_density, true, "integration_density", why);
}

}  // namespace statebench::est
