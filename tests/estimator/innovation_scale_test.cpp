// InnovationScale: a sensor that reports its covariance right keeps scale 1 (seeded, many
// batches, 5 % outliers included); one that reports 4x too small a variance gets about 4 after one
// batch and keeps it; the scale never drops below 1, and a batch mostly beyond the gate (the
// estimate went wrong) does not move it.
#include "estimator/innovation_scale.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>

#include "core/random.hpp"

namespace statebench::est {
namespace {

constexpr double kScaleTestGate = 16.27;

// Feeds `batches` batches of d2 values to s: each that of a 3D innovation with variance
// true_variance per axis against a reported variance of 1 times the scale in force, every
// `outlier_every`-th one (0: none) 100 times larger (multipath). The lowest and highest scale
// seen after the first batch, and how often it changed.
struct ScaleTestRun {
  double lowest = 1e9, highest = 0.0;
  int changes = 0;
};
ScaleTestRun FeedScale(InnovationScale& s, std::uint64_t seed, double true_variance, int batches,
                       int outlier_every) {
  auto rng = MakeRng(seed, "innovation_scale_test");
  NormalSampler normal;
  ScaleTestRun run;
  for (int k = 0; k < batches * InnovationScale::kBatch; ++k) {
    double d2 = 0.0;
    for (int i = 0; i < 3; ++i) {
      const double r = normal(rng);
      d2 += true_variance * r * r;
    }
    if (outlier_every > 0 && k % outlier_every == 0) d2 *= 100.0;
    run.changes += s.Add(d2 / s.scale()) ? 1 : 0;
    if (k + 1 >= InnovationScale::kBatch) {
      run.lowest = std::min(run.lowest, s.scale());
      run.highest = std::max(run.highest, s.scale());
    }
  }
  return run;
}

TEST(InnovationScale, AConsistentSensorKeepsScaleOne) {
  InnovationScale s(3, kScaleTestGate);
  EXPECT_EQ(FeedScale(s, 3, 1.0, 100, 20).changes, 0);  // 5 % outliers
  EXPECT_EQ(s.scale(), 1.0);
}

TEST(InnovationScale, AnUnderReportedCovarianceIsScaledUp) {
  InnovationScale s(3, kScaleTestGate);
  const ScaleTestRun run = FeedScale(s, 4, 4.0, 40, 0);
  EXPECT_GT(run.lowest, 2.5);
  EXPECT_LT(run.highest, 6.0);
  s.Reset();
  EXPECT_EQ(s.scale(), 1.0);
}

TEST(InnovationScale, AWrongEstimateIsNotABadCovariance) {
  // Every innovation far beyond the gate (the estimate went wrong): the scale stays.
  InnovationScale s(3, kScaleTestGate);
  for (int k = 0; k < 10 * InnovationScale::kBatch; ++k) s.Add(1e4 + k);
  EXPECT_EQ(s.scale(), 1.0);
}

TEST(InnovationScale, NeverBelowTheReportedCovariance) {
  InnovationScale s(3, kScaleTestGate);
  EXPECT_EQ(FeedScale(s, 5, 0.1, 10, 0).changes, 0);  // reported 10x too large
  EXPECT_EQ(s.scale(), 1.0);
}

}  // namespace
}  // namespace statebench::est
