#include "estimator/estimate_status.hpp"

#include <gtest/gtest.h>

namespace statebench::est {
namespace {

TEST(EstimateStatus, FollowsTheLastFixAndTheLastReinitialization) {
  EstimatorDiagnostics d;
  const std::vector<std::string> gnss = {"gnss_front", "gnss_rear"};
  EXPECT_EQ(StatusAt(d, {}, FromSeconds(1.0)), EstimateStatus::kLocal);
  EXPECT_EQ(StatusAt(d, gnss, FromSeconds(1.0)), EstimateStatus::kDeadReckoning);  // no fix yet
  d.Initialized(FromSeconds(1.0), "static");
  d.sensors["gnss_rear"].Accept(FromSeconds(2.0));
  EXPECT_EQ(StatusAt(d, gnss, FromSeconds(2.5)), EstimateStatus::kGlobal);
  EXPECT_EQ(StatusAt(d, gnss, FromSeconds(7.0)), EstimateStatus::kGlobal);
  EXPECT_EQ(StatusAt(d, gnss, FromSeconds(7.01)), EstimateStatus::kDeadReckoning);
  // Lost at 8 s, re-initialised at 9 s: recovering until 19 s, whatever the fixes do.
  d.Lost(FromSeconds(8.0), "lost");
  d.Initialized(FromSeconds(9.0), "moving (gnss course)");
  ASSERT_EQ(d.lost.size(), 1u);
  EXPECT_EQ(d.lost[0].reinitialization, "moving (gnss course)");
  EXPECT_EQ(d.initialization, "static");  // the first initialisation stays
  EXPECT_EQ(d.LatestInitializationNs(), FromSeconds(9.0));
  d.sensors["gnss_front"].Accept(FromSeconds(9.0));
  EXPECT_EQ(StatusAt(d, gnss, FromSeconds(9.5)), EstimateStatus::kRecovering);
  EXPECT_EQ(StatusAt(d, gnss, FromSeconds(18.99)), EstimateStatus::kRecovering);
  d.sensors["gnss_front"].Accept(FromSeconds(18.9));
  EXPECT_EQ(StatusAt(d, gnss, FromSeconds(19.0)), EstimateStatus::kGlobal);
  EXPECT_STREQ(EstimateStatusName(EstimateStatus::kDeadReckoning), "dead_reckoning");
}

}  // namespace
}  // namespace statebench::est
