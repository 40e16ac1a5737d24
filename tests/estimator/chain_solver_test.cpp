// The window's chain solver (chain_system.hpp, chain_levenberg_marquardt.hpp): its block
// elimination against the dense system of the same factors, and the whole estimator with
// `solver: chain` against `solver: ceres` on a noisy drive.
#include <ceres/loss_function.h>
#include <ceres/problem.h>
#include <ceres/solver.h>
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <memory>

#include "core/random.hpp"
#include "core/so3.hpp"
#include "estimator/bias_random_walk_factor.hpp"
#include "estimator/chain_levenberg_marquardt.hpp"
#include "estimator/chain_system.hpp"
#include "estimator/factor_graph_estimator.hpp"
#include "estimator/gnss_propagated_position_factor.hpp"
#include "estimator/imu_factor.hpp"
#include "estimator/marginalization_prior.hpp"
#include "estimator/so3_manifold.hpp"
#include "estimator/state_parameters.hpp"
#include "estimator_scenario.hpp"

namespace statebench::est {
namespace {

// Four states 0.1 s apart, IMU and bias factors between neighbours, a prior on the first, GNSS
// fixes (one with a Huber loss beyond its scale) on each; states perturbed off the solution.
struct SmallChain {
  RightQuaternionManifold manifold;
  std::vector<std::unique_ptr<StateParameters>> x;
  std::vector<std::unique_ptr<ceres::CostFunction>> costs;
  std::unique_ptr<ceres::LossFunction> huber = std::make_unique<ceres::HuberLoss>(1.0);
  std::vector<std::unique_ptr<FactorRecord>> records;
  std::vector<ChainState> chain;

  std::vector<double*> Blocks(StateParameters& s) {
    return {s.q_world_imu.data(), s.p_world.data(), s.v_world.data(), s.bias.data()};
  }
  void Add(std::size_t anchor, ceres::CostFunction* cost, const ceres::LossFunction* loss,
           std::vector<double*> blocks) {
    costs.emplace_back(cost);
    records.push_back(std::make_unique<FactorRecord>(FactorRecord{cost, loss, std::move(blocks)}));
    chain[anchor].factors.push_back(records.back().get());
  }

  SmallChain() {
    const ImuNoise noise;
    auto rng = MakeRng(3, "chain_solver_test");
    NormalSampler normal;
    const auto r3 = [&](double s) { return Vec3(s * normal(rng), s * normal(rng), s * normal(rng)); };
    NavState truth;
    truth.v_world = Vec3(5.0, 0.5, 0.0);
    Mat15 P0 = Mat15::Identity() * 1e-4;
    chain.resize(4);
    x.push_back(std::make_unique<StateParameters>(StateParameters::FromNavState(truth)));
    Add(0, MarginalizationPrior::FromCovariance(truth, P0), nullptr, Blocks(*x[0]));
    for (int k = 1; k < 4; ++k) {
      ImuPreintegration pim(noise, ImuBias{});
      for (int i = 0; i <= 10; ++i) {
        pim.Integrate((k - 1) * 100'000'000LL + i * 10'000'000LL, Vec3(0.01, -0.02, 0.3),
                      Vec3(0.2, 1.0, 9.81));
      }
      truth = pim.Predict(truth);
      NavState start = truth;
      start.p_world += r3(0.05);
      start.v_world += r3(0.02);
      start.q_world_imu = start.q_world_imu * so3::Exp<double>(r3(0.01));
      x.push_back(std::make_unique<StateParameters>(StateParameters::FromNavState(start)));
      std::vector<double*> imu_blocks = Blocks(*x[k - 1]);
      for (double* b : Blocks(*x[k])) {
        if (b != x[k]->bias.data()) imu_blocks.push_back(b);
      }
      Add(k - 1, new ImuFactor(pim), nullptr, imu_blocks);
      Add(k - 1, new BiasRandomWalkFactor(noise, pim.dt()), nullptr,
          {x[k - 1]->bias.data(), x[k]->bias.data()});
      ImuPreintegration none(noise, ImuBias{});
      none.Integrate(k * 100'000'000LL, Vec3::Zero(), Vec3::Zero());
      const Vec3 fix = truth.p_world + r3(0.02) + (k == 2 ? Vec3(0.5, 0.0, 0.0) : Vec3::Zero());
      Add(k, new GnssPropagatedPositionFactor(fix, Mat3::Identity() * 4e-4, Vec3(0.5, 0.0, 1.0), none,
                                              truth.q_world_imu),
          k == 2 ? huber.get() : nullptr, Blocks(*x[k]));
    }
    for (std::size_t k = 0; k < 4; ++k) {
      const auto b = Blocks(*x[k]);
      std::copy(b.begin(), b.end(), chain[k].blocks.begin());
    }
  }

  // The same factors in one dense system (linear_system.hpp), Huber's first-order weight.
  LinearSystem Dense() {
    BlockLayout layout;
    for (auto& s : x) {
      layout.Add(s->q_world_imu.data(), 4, &manifold);
      layout.Add(s->p_world.data(), 3, nullptr);
      layout.Add(s->v_world.data(), 3, nullptr);
      layout.Add(s->bias.data(), 6, nullptr);
    }
    std::vector<const FactorRecord*> all;
    for (const auto& r : records) all.push_back(r.get());
    LinearSystem system;
    EXPECT_TRUE(Linearize(all, layout, &system));
    return system;
  }
};

TEST(ChainSystem, EliminationMatchesTheDenseSystem) {
  SmallChain c;
  ChainSystem chain;
  ASSERT_TRUE(LinearizeChain(c.chain, c.manifold, &chain));
  const LinearSystem dense = c.Dense();
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(60, 60);
  Eigen::VectorXd g(60);
  for (int k = 0; k < 4; ++k) {
    H.block<15, 15>(15 * k, 15 * k) = chain.D[k];
    g.segment<15>(15 * k) = chain.g[k];
    if (k < 3) {
      H.block<15, 15>(15 * k, 15 * k + 15) = chain.B[k];
      H.block<15, 15>(15 * k + 15, 15 * k) = chain.B[k].transpose();
    }
  }
  const double scale = dense.H.cwiseAbs().maxCoeff();
  EXPECT_LT((H - dense.H).cwiseAbs().maxCoeff(), 1e-12 * scale);
  EXPECT_LT((g - dense.g).cwiseAbs().maxCoeff(), 1e-12 * dense.g.cwiseAbs().maxCoeff());
  double cost = 0.0;
  ASSERT_TRUE(ChainCost(c.chain, &cost));
  EXPECT_NEAR(chain.cost, cost, 1e-12 * cost);

  // (H + diag(d)) dx = -g by elimination, against a dense LDLT.
  std::vector<Vec15> damping(4, Vec15::Constant(1e-3)), dx;
  ASSERT_TRUE(SolveChain(chain, damping, &dx));
  Eigen::MatrixXd Hd = dense.H;
  Hd.diagonal().array() += 1e-3;
  const Eigen::VectorXd expected = Hd.ldlt().solve(-dense.g);
  for (int k = 0; k < 4; ++k) {
    EXPECT_LT((dx[k] - expected.segment<15>(15 * k)).norm(), 1e-9 * expected.norm()) << k;
  }
  // The newest marginal: the inverse of the newest block of H^-1.
  const Mat15 newest = NewestMarginalInformation(chain);
  const Mat15 expected_newest =
      Mat15(dense.H.ldlt().solve(Eigen::MatrixXd::Identity(60, 60)).bottomRightCorner<15, 15>())
          .inverse();
  EXPECT_LT((newest - expected_newest).cwiseAbs().maxCoeff(),
            1e-7 * expected_newest.cwiseAbs().maxCoeff());
}

TEST(ChainSystem, AFactorReachingBeyondTheNextStateIsRefused) {
  SmallChain c;
  c.Add(0, new BiasRandomWalkFactor(ImuNoise{}, 0.1), nullptr,
        {c.x[0]->bias.data(), c.x[2]->bias.data()});
  ChainSystem chain;
  EXPECT_FALSE(LinearizeChain(c.chain, c.manifold, &chain));
}

// The same start and factors solved by ceres::Solve with the smoother's options: the same
// iterations and the same solution to Ceres' tolerances.
TEST(ChainLevenbergMarquardt, FollowsCeresLevenbergMarquardt) {
  for (int max_iterations : {1, 2, 10}) {
    SmallChain by_chain, by_ceres;
    const ChainSolveSummary s = SolveChainLevenbergMarquardt(
        by_chain.chain, by_chain.manifold, ChainSolveOptions{max_iterations, 1e13});
    ceres::Problem::Options po;
    po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(po);
    for (const auto& r : by_ceres.records) {
      problem.AddResidualBlock(const_cast<ceres::CostFunction*>(r->cost),
                               const_cast<ceres::LossFunction*>(r->loss), r->blocks);
    }
    for (auto& x : by_ceres.x) problem.SetManifold(x->q_world_imu.data(), &by_ceres.manifold);
    ceres::Solver::Options options;
    options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    options.sparse_linear_algebra_library_type = ceres::EIGEN_SPARSE;
    options.max_num_iterations = max_iterations;
    options.initial_trust_region_radius = 1e13;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);

    ASSERT_TRUE(s.usable);
    EXPECT_EQ(s.iterations, static_cast<int>(summary.iterations.size()) - 1) << max_iterations;
    EXPECT_NEAR(s.initial_cost, summary.initial_cost, 1e-12 * summary.initial_cost);
    EXPECT_NEAR(s.final_cost, summary.final_cost, 1e-9 * summary.initial_cost);
    for (std::size_t k = 0; k < 4; ++k) {
      const NavState a = by_chain.x[k]->ToNavState(0), b = by_ceres.x[k]->ToNavState(0);
      EXPECT_LT((a.p_world - b.p_world).norm(), 1e-9) << k;
      EXPECT_LT((a.v_world - b.v_world).norm(), 1e-9) << k;
      EXPECT_LT(testing::RotationError(a, b), 1e-9) << k;
    }
    ASSERT_TRUE(s.has_system);
    EXPECT_NEAR(s.system.cost, s.final_cost, 1e-12 * s.final_cost);
  }
}

// The estimator with either solver on a noisy IMU + GNSS drive: the same outputs to far below
// their uncertainty, the same number of iterations.
TEST(ChainLevenbergMarquardt, EstimatorAgreesWithTheCeresSolver) {
  testing::ScenarioOptions so;
  so.duration_s = 15.0;
  so.imu_noisy = true;
  so.gyro_bias = Vec3(2e-3, -1e-3, 1e-3);
  so.accel_bias = Vec3(0.05, -0.02, 0.03);
  so.gnss_sigma_h = 0.3;
  so.gnss_sigma_v = 0.5;
  so.reported_sigma_h = 0.3;
  so.reported_sigma_v = 0.5;
  so.seed = 5;
  const testing::Scenario sc = testing::MakeScenario(so);
  const EstimatorSensorSetup setup = testing::MakeSetup(so);
  FactorGraphOptions ceres_options;
  ceres_options.origin = testing::kTestOrigin;
  FactorGraphOptions chain_options = ceres_options;
  chain_options.solver = WindowSolver::kChain;
  FactorGraphEstimator with_ceres(setup, ceres_options), with_chain(setup, chain_options);
  int compared = 0;
  double worst_position = 0.0, worst_rotation = 0.0, worst_variance = 0.0;
  for (const Measurement& m : sc.stream) {
    with_ceres.Add(m);
    with_chain.Add(m);
    if (!std::holds_alternative<ImuSample>(m)) continue;
    const auto a = with_ceres.StateAt(HeaderOf(m).stamp_ns);
    const auto b = with_chain.StateAt(HeaderOf(m).stamp_ns);
    ASSERT_EQ(a.has_value(), b.has_value());
    if (!a) continue;
    ++compared;
    worst_position = std::max(worst_position, (a->state.p_world - b->state.p_world).norm());
    worst_rotation = std::max(worst_rotation, testing::RotationError(a->state, b->state));
    worst_variance = std::max(
        worst_variance,
        (b->covariance.diagonal().cwiseQuotient(a->covariance.diagonal()).array() - 1.0)
            .abs()
            .maxCoeff());
  }
  std::printf("chain vs ceres over %d outputs: position %.2e m, rotation %.2e rad, variance %.2e\n",
              compared, worst_position, worst_rotation, worst_variance);
  EXPECT_GT(compared, 1000);
  EXPECT_LT(worst_position, 1e-4);
  EXPECT_LT(worst_rotation, 1e-6);
  EXPECT_LT(worst_variance, 1e-3);
  const EstimatorDiagnostics da = with_ceres.diagnostics(), db = with_chain.diagnostics();
  EXPECT_EQ(da.updates.count(), db.updates.count());
  EXPECT_EQ(db.updates.unusable(), 0u);
  EXPECT_NEAR(da.updates.mean_iterations(), db.updates.mean_iterations(), 0.02);
}

}  // namespace
}  // namespace statebench::est
