#include "estimator/imu_noise.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace statebench::est {
namespace {

TEST(ImuNoise, DefaultsAreIndustrialMemsAndValid) {
  const ImuNoise noise;
  std::string why;
  EXPECT_TRUE(noise.IsValid(&why)) << why;
  EXPECT_DOUBLE_EQ(noise.gyro_noise_density, 1.7e-4);
  EXPECT_DOUBLE_EQ(noise.accel_noise_density, 2.0e-3);
  EXPECT_DOUBLE_EQ(noise.gyro_random_walk, 1.9e-5);
  EXPECT_DOUBLE_EQ(noise.accel_random_walk, 3.0e-3);
}

TEST(ImuNoise, RejectsNonPositiveOrNonFiniteAndNamesTheField) {
  ImuNoise noise;
  noise.accel_random_walk = 0.0;
  std::string why;
  EXPECT_FALSE(noise.IsValid(&why));
  EXPECT_NE(why.find("accel_random_walk"), std::string::npos) << why;

  noise = ImuNoise();
  noise.gyro_noise_density = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(noise.IsValid(&why));
  EXPECT_NE(why.find("gyro_noise_density"), std::string::npos) << why;

  noise = ImuNoise();
  noise.integration_density = 0.0;
  EXPECT_TRUE(noise.IsValid());
  noise.integration_density = -1.0;
  EXPECT_FALSE(noise.IsValid(nullptr));
}

}  // namespace
}  // namespace statebench::est
