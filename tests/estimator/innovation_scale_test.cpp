// InnovationScale: a sensor that reports its covariance right keeps scale 1 (seeded, many
// batches, 5 % outliers included); one that reports 4x too small a variance gets about 4 within two
// batches and keeps it; the scale never drops below 1, and a batch mostly beyond the gate (the
// estimate went wrong) does not move it.
#include "estimator/innovation_scale.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "core/random.hpp"

namespace statebench::est {
namespace {

// d2 of a 3D innovation with true variance true_variance per axis against a reported variance of
// 1 scaled by the current scale; every `outlier_every`-th one 100 times larger (multipath).
double ScaleTestSample(std::mt19937_64& rng, NormalSampler& normal, double true_variance,
                       double scale, int k, int outlier_every) {
  double d2 = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double r = normal(rng);
    d2 += true_variance * r * r;
  }
  if (outlier_every > 0 && k % outlier_every == 0) d2 *= 100.0;
  return d2 / scale;
}

TEST(InnovationScale, AConsistentSensorKeepsScaleOne) {
  auto rng = MakeRng(3, "innovation_scale_test");
  NormalSampler normal;
  InnovationScale s(3, 16.27);
  int changes = 0;
  for (int k = 0; k < 100 * InnovationScale::kBatch; ++k) {
    changes += s.Add(ScaleTestSample(rng, normal, 1.0, s.scale(), k, 20)) ? 1 : 0;
  }
  EXPECT_EQ(changes, 0);
  EXPECT_EQ(s.scale(), 1.0);
}

TEST(InnovationScale, AnUnderReportedCovarianceIsScaledUp) {
  auto rng = MakeRng(4, "innovation_scale_test");
  NormalSampler normal;
  InnovationScale s(3, 16.27);
  for (int k = 0; k < 2 * InnovationScale::kBatch; ++k) {
    s.Add(ScaleTestSample(rng, normal, 4.0, s.scale(), k, 0));
  }
  EXPECT_GT(s.scale(), 2.5);
  EXPECT_LT(s.scale(), 6.0);
  double lowest = s.scale(), highest = s.scale();
  for (int k = 0; k < 40 * InnovationScale::kBatch; ++k) {
    s.Add(ScaleTestSample(rng, normal, 4.0, s.scale(), k, 0));
    lowest = std::min(lowest, s.scale());
    highest = std::max(highest, s.scale());
  }
  EXPECT_GT(lowest, 2.5);
  EXPECT_LT(highest, 6.0);
  s.Reset();
  EXPECT_EQ(s.scale(), 1.0);
}

TEST(InnovationScale, AWrongEstimateIsNotABadCovariance) {
  // Every innovation far beyond the gate (the estimate went wrong): the scale stays.
  InnovationScale s(3, 16.27);
  for (int k = 0; k < 10 * InnovationScale::kBatch; ++k) s.Add(1e4 + k);
  EXPECT_EQ(s.scale(), 1.0);
}

TEST(InnovationScale, NeverBelowTheReportedCovariance) {
  auto rng = MakeRng(5, "innovation_scale_test");
  NormalSampler normal;
  InnovationScale s(3, 16.27);
  for (int k = 0; k < 10 * InnovationScale::kBatch; ++k) {
    s.Add(ScaleTestSample(rng, normal, 0.1, s.scale(), k, 0));  // reported 10x too large
  }
  EXPECT_EQ(s.scale(), 1.0);
}

}  // namespace
}  // namespace statebench::est
