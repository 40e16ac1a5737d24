// The Gauss-Markov part of the GNSS error is common to the antennas of a run (the RTK
// correction's slow error), the white part is per antenna: the difference of two antennas'
// errors (what a dual-antenna heading sees) has variance 2 (1 - f) sigma^2, not 2 sigma^2.
#include "sensors/gnss_error_process.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace statebench::sensors {
namespace {

GnssOptions CorrelatedRtk() {
  GnssOptions o;
  o.mode = GnssMode::kRtkFixed;
  o.correlated_fraction = 0.5;
  o.gauss_markov_tau_s = 60.0;
  return o;
}

TEST(GnssCommonMode, TwoAntennasShareTheGaussMarkovPartOnly) {
  const GnssOptions o = CorrelatedRtk();
  const GnssAccuracy& a = o.AccuracyOf(GnssMode::kRtkFixed);
  const double sigma = a.HorizontalSigma();
  GnssErrorProcess front(o, 11, "gnss_front"), rear(o, 11, "gnss_rear");
  double sum_d2 = 0.0, sum_e2 = 0.0;
  const int n = 20000;
  for (int k = 1; k <= n; ++k) {
    const TimeNs t = k * 100'000'000LL;  // 10 Hz
    const Vec3 ef = front.Sample(t, a);
    const Vec3 er = rear.Sample(t, a);
    sum_d2 += (ef - er).x() * (ef - er).x();
    sum_e2 += ef.x() * ef.x();
  }
  const double sd_diff = std::sqrt(sum_d2 / n);
  const double sd = std::sqrt(sum_e2 / n);
  std::printf("[ measured ] sigma per antenna %.4f m, of the difference %.4f m (white only: %.4f)\n",
              sd, sd_diff, std::sqrt(2.0 * (1.0 - o.correlated_fraction)) * sigma);
  // Independent antennas would give sqrt(2) sigma = 1.41 sigma; the white parts alone 1.0 sigma.
  EXPECT_NEAR(sd_diff / sigma, std::sqrt(2.0 * (1.0 - o.correlated_fraction)), 0.05);
  // The per-antenna sigma is still the configured total (2000 s = 33 tau: a few % spread).
  EXPECT_NEAR(sd / sigma, 1.0, 0.15);
}

// The common part is a function of time: an antenna at 5 Hz and one at 10 Hz, or one starting
// later, see the same Gauss-Markov value at a common stamp.
TEST(GnssCommonMode, CommonPartDoesNotDependOnTheFixRate) {
  GnssOptions o = CorrelatedRtk();
  o.correlated_fraction = 1.0;  // Gauss-Markov only
  const GnssAccuracy& a = o.AccuracyOf(GnssMode::kRtkFixed);
  GnssErrorProcess fast(o, 3, "fast"), slow(o, 3, "slow");
  int compared = 0;
  for (int k = 1; k <= 3000; ++k) {
    const TimeNs t = k * 100'000'000LL;
    const Vec3 ef = fast.Sample(t, a);
    if (k % 2 == 0 && k > 1000) {
      EXPECT_LT((ef - slow.Sample(t, a)).norm(), 1e-12) << "at k " << k;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 1000);
}

}  // namespace
}  // namespace statebench::sensors
