#include "core/stage_profile.hpp"

#include <gtest/gtest.h>

namespace statebench {
namespace {

StageTimes Times(std::initializer_list<std::pair<Stage, double>> monotonic,
                 std::initializer_list<std::pair<Stage, double>> cpu = {}) {
  StageTimes t;
  for (const auto& [stage, s] : monotonic) t.monotonic_s[static_cast<std::size_t>(stage)] = s;
  for (const auto& [stage, s] : cpu) t.process_cpu_s[static_cast<std::size_t>(stage)] = s;
  return t;
}

double At(const std::array<double, kStageCount>& split, Stage stage) {
  return split[static_cast<std::size_t>(stage)];
}

// Time charged per stage while this thread does some work.
StageTimes ChargedBySomeWork() {
  const StageTimes before = CurrentStageTimes();
  volatile double sink = 0.0;
  for (int i = 0; i < 200000; ++i) sink = sink + 1.0;
  return CurrentStageTimes() - before;
}

double Monotonic(const StageTimes& t, Stage stage) {
  return t.monotonic_s[static_cast<std::size_t>(stage)];
}

TEST(StageProfile, ScopesChargeExclusiveTimeAndRestoreTheEnclosingStage) {
  const StageScope outer(Stage::kEstimators);
  {
    const StageScope inner(Stage::kWriting);
    const StageTimes d = ChargedBySomeWork();
    EXPECT_GT(Monotonic(d, Stage::kWriting), 0.0);
    EXPECT_EQ(Monotonic(d, Stage::kEstimators), 0.0);
  }
  // Back in kEstimators: time now accrues there, not to kWriting.
  const StageTimes d = ChargedBySomeWork();
  EXPECT_EQ(Monotonic(d, Stage::kWriting), 0.0);
  EXPECT_GT(Monotonic(d, Stage::kEstimators), 0.0);
}

TEST(StageProfile, SerialStagesShareTheRestOfTheCpuTimeByMonotonicTime) {
  // 10 s of process CPU: 4 s measured in the (parallel) raycast, 6 s over 1 s + 2 s serial.
  const StageTimes span = Times({{Stage::kVehicle, 1.0}, {Stage::kEstimators, 2.0},
                                 {Stage::kLidarRaycast, 2.0}},
                                {{Stage::kLidarRaycast, 4.0}});
  const CpuAttribution attribution(span, 10.0);
  const auto split = attribution.Split(span);
  EXPECT_DOUBLE_EQ(At(split, Stage::kLidarRaycast), 4.0);
  EXPECT_DOUBLE_EQ(At(split, Stage::kVehicle), 2.0);
  EXPECT_DOUBLE_EQ(At(split, Stage::kEstimators), 4.0);
  EXPECT_DOUBLE_EQ(attribution.Total(span), 10.0);
  // A part of the span (one estimator's calls) at the same rate.
  EXPECT_DOUBLE_EQ(attribution.Total(Times({{Stage::kEstimators, 0.5}})), 1.0);
}

TEST(StageProfile, WithoutSerialTimeTheCpuTimeGoesToOther) {
  const CpuAttribution attribution(StageTimes{}, 3.0);
  EXPECT_DOUBLE_EQ(At(attribution.Split(StageTimes{}), Stage::kOther), 3.0);
}

TEST(StageProfile, EveryStageHasAName) {
  for (std::size_t i = 0; i < kStageCount; ++i) {
    EXPECT_NE(StageName(static_cast<Stage>(i)), "?");
  }
}

}  // namespace
}  // namespace statebench
