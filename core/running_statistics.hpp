// Statistics of a stream of non-negative values (errors, solve times) in memory that does not
// grow with the stream: count, mean, RMS, standard deviation and maximum exactly (Welford's
// update for the variance), quantiles from a histogram with logarithmic bins.
//
// Quantiles: bin k >= 1 holds [kMin (1 + r)^(k-1), kMin (1 + r)^k) with r = 1e-3, bin 0 holds
// [0, kMin); a quantile is the geometric middle of its bin, clamped to the exact minimum and
// maximum, so its relative error is below r / 2 = 0.05 % for values in [kMin, kMax] (the idea of
// HdrHistogram). Bins are allocated up to the largest value seen: 2.3 k bins per decade, 4 bytes
// each (values of 1 mm to 10 m: about 40 KB). Values above kMax share the last bin; NaN and
// negative values are refused by the caller's contract (asserted).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace statebench {

class RunningStatistics {
 public:
  static constexpr double kMin = 1e-9;
  static constexpr double kMax = 1e9;
  static constexpr double kRelativeResolution = 1e-3;

  void Add(double value);

  std::size_t count() const { return count_; }
  double mean() const { return mean_; }
  double rms() const;
  double std() const;  // population standard deviation (divides by the count)
  double min() const { return count_ ? min_ : 0.0; }
  double max() const { return count_ ? max_ : 0.0; }
  // The q-quantile (0 <= q <= 1) within the resolution above; the median is Quantile(0.5) with
  // the convention of an even count (mean of the two middle values' bins). 0 when empty.
  double Quantile(double q) const;
  double Median() const;

  // The values counted in bins of equal width on a log scale, `bins_per_decade` per decade, edges
  // at 10^(k / bins_per_decade) (to the histogram's resolution above: a fine bin counts in the
  // coarse bin holding its middle), from the lowest non-empty bin to the highest, empty bins
  // between included; values below kMin count in the lowest. Empty when nothing was added.
  struct LogBin {
    double low = 0.0;
    double high = 0.0;
    std::uint64_t count = 0;
  };
  std::vector<LogBin> LogHistogram(int bins_per_decade) const;

 private:
  std::size_t BinOf(double value) const;
  double BinValue(std::size_t bin) const;
  // The value of rank k (0-based) in sorted order, at bin resolution.
  double ValueOfRank(std::uint64_t k) const;

  std::size_t count_ = 0;
  double mean_ = 0.0;
  double m2_ = 0.0;       // Welford: sum of squared deviations from the running mean
  double sum_sq_ = 0.0;   // for the RMS
  double min_ = 0.0;
  double max_ = 0.0;
  std::vector<std::uint32_t> bins_;
};

}  // namespace statebench
