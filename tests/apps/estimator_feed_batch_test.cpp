// EstimatorFeed with an estimator that estimates at the end of the log (the factor graph's
// full-batch smoother) beside a real-time one: every output epoch is held until Finish, then both
// are written and scored over one span, and the batch is scored at every epoch the real-time
// one is.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "../estimator/estimator_scenario.hpp"
#include "apps/estimator_feed.hpp"
#include "estimator/factor_graph_estimator.hpp"

namespace statebench::app {
namespace {

namespace fs = std::filesystem;

TEST(EstimatorFeedBatch, ABatchEstimatorIsScoredAtTheEndOverTheSameSpan) {
  const fs::path dir =
      fs::temp_directory_path() / ("statebench_feed_batch_test_" + std::to_string(getpid()));
  struct RemoveOnExit {
    fs::path dir;
    ~RemoveOnExit() {
      std::error_code ec;
      fs::remove_all(dir, ec);
    }
  } cleanup{dir};
  est::testing::ScenarioOptions so = est::testing::DriftingImuRtkOptions(30.0);
  so.gnss_sigma_h = so.reported_sigma_h = 0.3;
  so.gnss_sigma_v = so.reported_sigma_v = 0.5;
  const est::testing::Scenario sc = est::testing::MakeScenario(so);
  const est::EstimatorSensorSetup setup = est::testing::MakeSetup(so);

  EstimatorFeed feed(setup.imu_id, LocalEnuFrame(est::testing::kTestOrigin));
  for (const bool batch : {false, true}) {
    est::FactorGraphOptions o;
    o.batch = batch;
    const std::string label = batch ? "batch" : "fixed_lag";
    feed.Add(label, "factor_graph", dir / label,
             std::make_unique<est::FactorGraphEstimator>(setup, o), false);
  }
  EXPECT_TRUE(feed.EstimatesAtEnd());
  feed.ScoreAgainstTruth(SE3::Identity(), {});
  for (TimeNs t = 0; t <= FromSeconds(so.duration_s); t += 10 * kNsPerMillisecond) {
    const NavState s = sc.Truth(t);
    TruthSample truth;
    truth.t_ns = t;
    truth.body.T_world_frame = SE3(s.q_world_imu, s.p_world);
    truth.body.v_world = s.v_world;
    feed.AddTruth(truth);
  }
  for (const Measurement& m : sc.stream) feed.Feed(m);
  EXPECT_EQ(feed.estimators()[1].estimates, 0u);  // nothing before the end
  const std::vector<EstimatorScore> scores = feed.Finish();
  ASSERT_EQ(scores.size(), 2u);
  const nlohmann::json& fixed = scores[0].metrics_json;
  const nlohmann::json& batch = scores[1].metrics_json;
  EXPECT_GT(feed.estimators()[1].estimates, 2500u);
  EXPECT_EQ(fixed["availability"]["span_begin_s"], batch["availability"]["span_begin_s"]);
  EXPECT_EQ(fixed["availability"]["span_imu_stamps"], batch["availability"]["span_imu_stamps"]);
  EXPECT_EQ(fixed["compared"], batch["compared"]);
  EXPECT_EQ(batch["availability"]["span_fraction"].get<double>(), 1.0);
  std::printf("RMSE position fixed-lag %.3f m, batch %.3f m over %d epochs\n",
              scores[0].metrics.rmse_position_m, scores[1].metrics.rmse_position_m,
              fixed["compared"].get<int>());
  EXPECT_LE(scores[1].metrics.rmse_position_m, scores[0].metrics.rmse_position_m);
  EXPECT_EQ(scores[1].diagnostics.batch_solves.size(), 1u);
  EXPECT_TRUE(fs::exists(dir / "batch" / "estimate.csv"));
}

}  // namespace
}  // namespace statebench::app
