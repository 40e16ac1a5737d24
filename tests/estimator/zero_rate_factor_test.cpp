#include "estimator/zero_rate_factor.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "core/random.hpp"
#include "jacobian_check.hpp"

namespace statebench::est {
namespace {

TEST(ZeroRateFactor, WhitensTheBiasAgainstTheMeanGyro) {
  const ZeroRateFactor factor(Vec3(1e-3, -2e-3, 3e-3), 1e-4);
  const std::vector<double> bias = {1.1e-3, -2e-3, 2.8e-3, 0.5, -0.5, 0.1};
  const double* ptrs[] = {bias.data()};
  Vec3 r;
  ASSERT_TRUE(factor.Evaluate(ptrs, r.data(), nullptr));
  EXPECT_NEAR(r.x(), 1.0, 1e-9);  // one sigma
  EXPECT_NEAR(r.y(), 0.0, 1e-9);
  EXPECT_NEAR(r.z(), -2.0, 1e-9);  // the accelerometer bias plays no part
  EXPECT_THROW(ZeroRateFactor(Vec3::Zero(), 0.0), InputError);
  EXPECT_THROW(ZeroRateFactor(Vec3(std::nan(""), 0.0, 0.0), 1e-4), InputError);
}

TEST(ZeroRateFactor, JacobianMatchesNumericDifferences) {
  const ZeroRateFactor factor(Vec3(2e-3, 1e-3, -4e-3), 3e-4);
  auto rng = MakeRng(5, "zero_rate_jacobian");
  NormalSampler normal;
  std::vector<std::vector<double>> blocks(1, std::vector<double>(6));
  for (double& x : blocks[0]) x = 0.01 * normal(rng);
  const auto check = testing::CheckJacobians(factor, blocks, {nullptr}, 1e-6, "zero rate");
  EXPECT_LT(check.worst_relative_error, 1e-8);
}

}  // namespace
}  // namespace statebench::est
