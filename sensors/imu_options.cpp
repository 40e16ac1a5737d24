#include "sensors/imu_options.hpp"

#include <numbers>

namespace statebench::sensors {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr double kDegPerHour = kDegToRad / 3600.0;

}  // namespace

ImuOptions ImuPreset(ImuGrade grade) {
  ImuOptions o;
  switch (grade) {
    case ImuGrade::kConsumer:  // BMI088 class
      o.gyro = {.noise_density = 2.4e-4,
                .random_walk = 2e-5,
                .turn_on_bias_sigma = 0.3 * kDegToRad,
                .scale_factor_sigma = 1e-2,
                .misalignment_sigma_rad = 5e-3,
                .quantization = 2.66e-4};  // 16 bit over +-500 deg/s
      o.accel = {.noise_density = 2e-3,
                 .random_walk = 3e-3,
                 .turn_on_bias_sigma = 0.1,
                 .scale_factor_sigma = 5e-3,
                 .misalignment_sigma_rad = 5e-3,
                 .quantization = 1.8e-3};  // 16 bit over +-6 g
      break;
    case ImuGrade::kIndustrial:  // ADIS16448 class
      o.gyro = {.noise_density = 1.7e-4,
                .random_walk = 1.9e-5,
                .turn_on_bias_sigma = 0.05 * kDegToRad,
                .scale_factor_sigma = 1e-3,
                .misalignment_sigma_rad = 1e-3,
                .quantization = 0.02 * kDegToRad};
      o.accel = {.noise_density = 2.0e-3,
                 .random_walk = 3.0e-3,
                 .turn_on_bias_sigma = 0.02,
                 .scale_factor_sigma = 2e-3,
                 .misalignment_sigma_rad = 1e-3,
                 .quantization = 8.2e-3};  // 0.833 mg per LSB
      break;
    case ImuGrade::kTactical:  // 1 deg/h, 0.1 deg/sqrt(h) class
      o.gyro = {.noise_density = 2.9e-5,
                .random_walk = 1e-6,
                .turn_on_bias_sigma = 1.0 * kDegPerHour,
                .scale_factor_sigma = 1e-4,
                .misalignment_sigma_rad = 1e-4,
                .quantization = 0.0};
      o.accel = {.noise_density = 4e-4,
                 .random_walk = 1e-4,
                 .turn_on_bias_sigma = 0.01,
                 .scale_factor_sigma = 1e-4,
                 .misalignment_sigma_rad = 1e-4,
                 .quantization = 0.0};
      break;
  }
  return o;
}

std::optional<ImuGrade> ParseImuGrade(std::string_view name) {
  if (name == "consumer") return ImuGrade::kConsumer;
  if (name == "industrial") return ImuGrade::kIndustrial;
  if (name == "tactical") return ImuGrade::kTactical;
  return std::nullopt;
}

}  // namespace statebench::sensors
