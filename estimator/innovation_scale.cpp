#include "estimator/innovation_scale.hpp"

#include <algorithm>
#include <cmath>

namespace statebench::est {
namespace {

// Median of chi-square(n): exact for n = 1, 2, 3, else Wilson-Hilferty n (1 - 2 / (9 n))^3.
double ChiSquareMedian(int n) {
  switch (n) {
    case 1:
      return 0.454936;
    case 2:
      return 1.386294;
    case 3:
      return 2.365974;
    default: {
      const double c = 1.0 - 2.0 / (9.0 * n);
      return n * c * c * c;
    }
  }
}

}  // namespace

InnovationScale::InnovationScale(int dimension, double gate_chi2)
    : expected_median_(ChiSquareMedian(dimension)), gate_chi2_(gate_chi2) {
  batch_.reserve(kBatch);
}

bool InnovationScale::Add(double mahalanobis_squared) {
  if (!std::isfinite(mahalanobis_squared)) return false;
  batch_.push_back(std::min(mahalanobis_squared, gate_chi2_));
  if (static_cast<int>(batch_.size()) < kBatch) return false;
  auto middle = batch_.begin() + kBatch / 2;
  std::nth_element(batch_.begin(), middle, batch_.end());
  double median = *middle;
  if (kBatch % 2 == 0) median = 0.5 * (median + *std::max_element(batch_.begin(), middle));
  batch_.clear();
  if (median >= gate_chi2_) return false;
  const double implied = scale_ * median / expected_median_;
  const double scale = implied > kMinScale ? std::min(implied, kMaxScale) : 1.0;
  if (scale == scale_) return false;
  scale_ = scale;
  return true;
}

void InnovationScale::Reset() {
  scale_ = 1.0;
  batch_.clear();
}

}  // namespace statebench::est
