#include "core/running_statistics.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace statebench {
namespace {

const double kLogBase = std::log1p(RunningStatistics::kRelativeResolution);
const std::size_t kLastBin = static_cast<std::size_t>(
    std::ceil(std::log(RunningStatistics::kMax / RunningStatistics::kMin) / kLogBase));

}  // namespace

void RunningStatistics::Add(double value) {
  assert(value >= 0.0);  // also false for NaN
  ++count_;
  const double delta = value - mean_;
  mean_ += delta / static_cast<double>(count_);
  m2_ += delta * (value - mean_);
  sum_sq_ += value * value;
  if (count_ == 1) {
    min_ = max_ = value;
  } else {
    min_ = std::min(min_, value);
    max_ = std::max(max_, value);
  }
  const std::size_t bin = BinOf(value);
  if (bin >= bins_.size()) bins_.resize(bin + 1, 0);
  ++bins_[bin];
}

double RunningStatistics::rms() const {
  return count_ ? std::sqrt(sum_sq_ / static_cast<double>(count_)) : 0.0;
}

double RunningStatistics::std() const {
  return count_ ? std::sqrt(std::max(0.0, m2_ / static_cast<double>(count_))) : 0.0;
}

std::size_t RunningStatistics::BinOf(double value) const {
  if (!(value >= kMin)) return 0;
  if (value >= kMax) return kLastBin;
  const auto bin = static_cast<std::size_t>(std::floor(std::log(value / kMin) / kLogBase)) + 1;
  return std::min(bin, kLastBin);
}

double RunningStatistics::BinValue(std::size_t bin) const {
  if (bin == 0) return 0.0;  // below kMin: zero within kMin
  // Geometric middle of [kMin (1+r)^(bin-1), kMin (1+r)^bin).
  return kMin * std::exp((static_cast<double>(bin) - 0.5) * kLogBase);
}

double RunningStatistics::ValueOfRank(std::uint64_t k) const {
  if (k == 0) return min_;  // the extremes are known exactly
  if (k + 1 >= count_) return max_;
  std::uint64_t seen = 0;
  for (std::size_t b = 0; b < bins_.size(); ++b) {
    seen += bins_[b];
    if (seen > k) return std::clamp(BinValue(b), min_, max_);
  }
  return max_;
}

double RunningStatistics::Quantile(double q) const {
  if (count_ == 0) return 0.0;
  const double rank = std::clamp(q, 0.0, 1.0) * static_cast<double>(count_ - 1);
  return ValueOfRank(static_cast<std::uint64_t>(rank + 0.5));
}

double RunningStatistics::Median() const {
  if (count_ == 0) return 0.0;
  const std::uint64_t m = count_ / 2;
  return count_ % 2 ? ValueOfRank(m) : 0.5 * (ValueOfRank(m - 1) + ValueOfRank(m));
}

std::vector<RunningStatistics::LogBin> RunningStatistics::LogHistogram(
    int bins_per_decade) const {
  assert(bins_per_decade > 0);
  std::vector<LogBin> out;
  if (count_ == 0) return out;
  const double per_decade = static_cast<double>(bins_per_decade);
  const auto coarse_of = [&](std::size_t fine) {
    const double v = BinValue(fine == 0 ? 1 : fine);
    return static_cast<long>(std::floor(std::log10(v) * per_decade));
  };
  std::size_t first = 0;
  while (first < bins_.size() && bins_[first] == 0) ++first;
  std::size_t last = bins_.size() - 1;
  while (last > first && bins_[last] == 0) --last;
  const long low = coarse_of(first);
  const long high = coarse_of(last);
  for (long k = low; k <= high; ++k) {
    out.push_back({std::pow(10.0, static_cast<double>(k) / per_decade),
                   std::pow(10.0, static_cast<double>(k + 1) / per_decade), 0});
  }
  for (std::size_t b = first; b <= last; ++b) {
    if (bins_[b] != 0) out[static_cast<std::size_t>(coarse_of(b) - low)].count += bins_[b];
  }
  return out;
}

}  // namespace statebench
