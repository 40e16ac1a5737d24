#include "estimator/bias_random_walk_factor.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "core/random.hpp"
#include "jacobian_check.hpp"

namespace statebench::est {
namespace {

TEST(BiasRandomWalkFactor, WhitensByRandomWalkOverDt) {
  ImuNoise noise;
  noise.gyro_random_walk = 2e-5;
  noise.accel_random_walk = 4e-3;
  const BiasRandomWalkFactor factor(noise, 0.25);
  std::vector<double> b_i(6, 0.0), b_j = {1e-5, 0, 0, 0, 0, 2e-3};
  const double* ptrs[] = {b_i.data(), b_j.data()};
  Vec6 r;
  factor.Evaluate(ptrs, r.data(), nullptr);
  // sigma_g = 2e-5 * sqrt(0.25) = 1e-5, sigma_a = 4e-3 * 0.5 = 2e-3: both are one sigma.
  EXPECT_NEAR(r(0), 1.0, 1e-12);
  EXPECT_NEAR(r(5), 1.0, 1e-12);
  EXPECT_NEAR(r.squaredNorm(), 2.0, 1e-12);
  EXPECT_THROW(BiasRandomWalkFactor(noise, 0.0), InputError);
  noise.gyro_random_walk = -1.0;
  EXPECT_THROW(BiasRandomWalkFactor(noise, 0.01), InputError);
}

TEST(BiasRandomWalkFactor, JacobiansMatchNumericDifferences) {
  const BiasRandomWalkFactor factor(ImuNoise{}, 0.01);
  auto rng = MakeRng(11, "bias_rw_jacobian");
  NormalSampler normal;
  std::vector<std::vector<double>> blocks(2, std::vector<double>(6));
  for (auto& b : blocks) {
    for (double& x : b) x = 0.01 * normal(rng);
  }
  const auto check =
      testing::CheckJacobians(factor, blocks, {nullptr, nullptr}, 1e-6, "bias random walk");
  EXPECT_LT(check.worst_relative_error, 1e-8);
}

}  // namespace
}  // namespace statebench::est
