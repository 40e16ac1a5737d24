#include "estimator/imu_band_split.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace statebench::est {

ImuBand SplitImuBand(std::span<const Vec3> x, int taps) {
  ImuBand band;
  const int n = static_cast<int>(x.size());
  const int length = 2 * taps - 1;  // the triangle
  if (taps < 2 || n < length + 2) return band;
  // First moving average: y[i] = mean(x[i .. i + taps - 1]); second: z[i] = mean(y[i .. ]);
  std::vector<Vec3> y(static_cast<std::size_t>(n - taps + 1));
  Vec3 sum = Vec3::Zero();
  for (int i = 0; i < taps; ++i) sum += x[i];
  y[0] = sum / taps;
  for (int i = 1; i + taps - 1 < n; ++i) {
    sum += x[i + taps - 1] - x[i - 1];
    y[i] = sum / taps;
  }
  const int m = n - length + 1;  // low-band samples
  Vec3 low_sum = Vec3::Zero(), low_sq = Vec3::Zero();
  sum = Vec3::Zero();
  for (int i = 0; i < taps; ++i) sum += y[i];
  for (int i = 0; i < m; ++i) {
    if (i > 0) sum += y[i + taps - 1] - y[i - 1];
    const Vec3 z = sum / taps;
    low_sum += z;
    low_sq += z.cwiseAbs2();
  }
  const Vec3 low_mean = low_sum / m;
  band.lowpass_std =
      ((low_sq - m * low_mean.cwiseAbs2()).cwiseMax(0.0) / std::max(m - 1, 1)).cwiseSqrt();
  band.valid = true;
  return band;
}

int LowPassTaps(double lowpass_s, double dt_s) {
  if (!(dt_s > 0.0) || !(lowpass_s > 0.0)) return 1;
  return std::max(1, static_cast<int>(std::lround(lowpass_s / dt_s)));
}

}  // namespace statebench::est
