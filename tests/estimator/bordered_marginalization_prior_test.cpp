#include "estimator/bordered_marginalization_prior.hpp"

#include <gtest/gtest.h>

#include <random>

#include "core/so3.hpp"
#include "estimator/marginalization_prior.hpp"
#include "estimator/so3_manifold.hpp"
#include "jacobian_check.hpp"

namespace statebench::est {
namespace {

NavState BorderedPriorState() {
  NavState s;
  s.q_world_imu = Quat(Eigen::AngleAxisd(0.7, Vec3(0.2, -0.4, 1.0).normalized()));
  s.p_world = Vec3(3.0, -2.0, 0.5);
  s.v_world = Vec3(4.0, 1.0, 0.1);
  s.gyro_bias = Vec3(0.001, -0.002, 0.0005);
  s.accel_bias = Vec3(0.02, 0.01, -0.03);
  return s;
}

std::vector<std::vector<double>> BorderedPriorBlocks(const StateParameters& p,
                                                     const Eigen::VectorXd& globals) {
  auto v = [](const auto& a) { return std::vector<double>(a.begin(), a.end()); };
  std::vector<std::vector<double>> out{v(p.q_world_imu), v(p.p_world), v(p.v_world), v(p.bias)};
  for (Eigen::Index i = 0; i < globals.size(); ++i) out.push_back({globals(i)});
  return out;
}

// The prior's quadratic is 1/2 dx^T H dx + g^T dx (+ const) on the joint tangent, and its
// Jacobians match numeric differences on the manifold.
TEST(BorderedMarginalizationPrior, IsTheQuadraticOfItsInformation) {
  std::mt19937 rng(17);
  std::normal_distribution<double> normal;
  const int n = 17;  // a state and two globals
  Eigen::MatrixXd A(n + 3, n);
  for (int i = 0; i < A.rows(); ++i)
    for (int j = 0; j < n; ++j) A(i, j) = normal(rng);
  const Eigen::MatrixXd H = A.transpose() * A;
  Eigen::VectorXd g(n);
  for (int i = 0; i < n; ++i) g(i) = normal(rng);
  const StateParameters x0 = StateParameters::FromNavState(BorderedPriorState());
  const Eigen::VectorXd globals0 = Eigen::Vector2d(0.08, -0.01);
  const BorderedMarginalizationPrior prior(x0, globals0, H, g);
  ASSERT_EQ(prior.num_residuals(), n);
  ASSERT_EQ(prior.parameter_block_sizes().size(), 6u);

  // Moved by a known tangent step.
  Eigen::VectorXd delta(n);
  for (int i = 0; i < n; ++i) delta(i) = 0.05 * normal(rng);
  NavState moved = BorderedPriorState();
  moved.q_world_imu = moved.q_world_imu * so3::Exp<double>(delta.head<3>());
  moved.p_world += delta.segment<3>(3);
  moved.v_world += delta.segment<3>(6);
  moved.gyro_bias += delta.segment<3>(9);
  moved.accel_bias += delta.segment<3>(12);
  const auto eval = [&](const StateParameters& x, const Eigen::VectorXd& globals) {
    const auto blocks = BorderedPriorBlocks(x, globals);
    std::vector<const double*> ptrs;
    for (const auto& b : blocks) ptrs.push_back(b.data());
    Eigen::VectorXd r(n);
    prior.Evaluate(ptrs.data(), r.data(), nullptr);
    return 0.5 * r.squaredNorm();
  };
  const double cost0 = eval(x0, globals0);
  const double cost1 = eval(StateParameters::FromNavState(moved), globals0 + delta.tail<2>());
  const double expected = 0.5 * delta.dot(H * delta) + g.dot(delta);
  EXPECT_NEAR(cost1 - cost0, expected, 1e-9 * (1.0 + std::abs(expected)));

  const RightQuaternionManifold so3_manifold;
  const auto check = testing::CheckJacobians(
      prior, BorderedPriorBlocks(StateParameters::FromNavState(moved), globals0),
      {&so3_manifold, nullptr, nullptr, nullptr, nullptr, nullptr}, 1e-6, "bordered prior");
  EXPECT_LT(check.worst_relative_error, 1e-6);
}

}  // namespace
}  // namespace statebench::est
