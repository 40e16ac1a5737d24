#include "simulator/quintic_bspline.hpp"

#include <array>

namespace statebench::sim {
namespace {

using Table = std::array<std::array<std::array<double, 6>, 6>, 6>;

// kD[r][i][j]: coefficient of tau^i in d^r B_j / d tau^r, i.e. M[i + r][j] (i + r)! / i! / 120.
constexpr Table MakeDerivativeTable() {
  Table d{};
  for (int r = 0; r < 6; ++r) {
    for (int i = 0; i + r < 6; ++i) {
      double factor = 1.0;
      for (int k = i + 1; k <= i + r; ++k) factor *= k;
      for (int j = 0; j < 6; ++j) d[r][i][j] = kQuinticPowerMatrix[i + r][j] * factor;
    }
  }
  return d;
}

constexpr Table kD = MakeDerivativeTable();

}  // namespace

void QuinticBasis(double tau, int max_derivative, double b[][kQuinticOrder]) {
  double power[6];
  power[0] = 1.0;
  for (int i = 1; i < 6; ++i) power[i] = power[i - 1] * tau;
  for (int r = 0; r <= max_derivative; ++r) {
    for (int j = 0; j < 6; ++j) {
      double s = 0.0;
      for (int i = 0; i + r < 6; ++i) s += kD[r][i][j] * power[i];
      b[r][j] = s;
    }
  }
}

}  // namespace statebench::sim
