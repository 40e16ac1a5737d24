// The sweep's start order: a group's runs wait while its first run computes the shared stages.
#include "apps/sweep_schedule.hpp"

#include <gtest/gtest.h>

namespace statebench::app {
namespace {

TEST(SweepSchedule, RunsOfABusyGroupWaitForItsFirstRun) {
  // Two seeds (groups a, b) x three estimator options, in the expansion's order.
  SweepSchedule s({"a", "b", "a", "b", "a", "b"});
  EXPECT_EQ(s.Next(), 0u);
  EXPECT_EQ(s.Next(), 1u);
  EXPECT_EQ(s.Next(), std::nullopt);  // both groups compute: a third job slot waits
  s.Finished(1);
  EXPECT_EQ(s.Next(), 3u);  // b is warm; a still computes
  EXPECT_EQ(s.Next(), 5u);
  EXPECT_EQ(s.Next(), std::nullopt);
  s.Finished(0);
  EXPECT_EQ(s.Next(), 2u);
  EXPECT_EQ(s.Next(), 4u);
  EXPECT_TRUE(s.AllStarted());
  EXPECT_EQ(s.Next(), std::nullopt);
}

TEST(SweepSchedule, AGroupWhoseStagesAreCachedGoesBeforeNewGroups) {
  // Three seeds (groups a, b, c) x three estimator options in the expansion's order: a group's
  // runs are three apart. Two job slots: once a group is warm its runs follow each other, so
  // the cache holds two groups at a time however many seeds the sweep has.
  SweepSchedule s({"a", "b", "c", "a", "b", "c", "a", "b", "c"});
  EXPECT_EQ(s.Next(), 0u);
  EXPECT_EQ(s.Next(), 1u);
  s.Finished(0);
  EXPECT_EQ(s.Next(), 3u);  // a is cached: its second run, not c's first
  s.Finished(1);
  EXPECT_EQ(s.Next(), 4u);
  s.Finished(3);
  EXPECT_EQ(s.Next(), 6u);
  s.Finished(4);
  EXPECT_EQ(s.Next(), 7u);
  s.Finished(6);
  EXPECT_EQ(s.Next(), 2u);  // a and b all started: c's first run
  s.Finished(7);
  EXPECT_EQ(s.Next(), std::nullopt);  // c computes; the other slot waits for it
  s.Finished(2);
  EXPECT_EQ(s.Next(), 5u);
  EXPECT_EQ(s.Next(), 8u);
  EXPECT_TRUE(s.AllStarted());
}

TEST(SweepSchedule, AFailedFirstRunReleasesItsGroup) {
  SweepSchedule s({"a", "a"});
  EXPECT_EQ(s.Next(), 0u);
  EXPECT_EQ(s.Next(), std::nullopt);
  s.Finished(0);  // failed: the next run computes the stages itself
  EXPECT_EQ(s.Next(), 1u);
}

TEST(SweepSchedule, DistinctGroupsRunInOrder) {
  SweepSchedule s({"a", "b", "c"});
  EXPECT_EQ(s.Next(), 0u);
  EXPECT_EQ(s.Next(), 1u);
  EXPECT_EQ(s.Next(), 2u);
  EXPECT_FALSE(s.Next().has_value());
}

}  // namespace
}  // namespace statebench::app
