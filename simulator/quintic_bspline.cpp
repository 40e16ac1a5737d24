#include "simulator/quintic_bspline.hpp"

namespace statebench::sim {
namespace {

// Rows: powers of tau; columns: basis functions. Divided by 120.
constexpr double kM[6][6] = {{1, 26, 66, 26, 1, 0},      {-5, -50, 0, 50, 5, 0},
                             {10, 20, -60, 20, 10, 0},   {-10, 20, 0, -20, 10, 0},
                             {5, -20, 30, -20, 5, 0},    {-1, 5, -10, 10, -5, 1}};

}  // namespace

void QuinticBasis(double tau, int derivative, double b[kQuinticOrder]) {
  // coef[m] = d^r/dtau^r tau^m = m! / (m - r)! tau^(m - r).
  double coef[6] = {0, 0, 0, 0, 0, 0};
  for (int m = derivative; m < 6; ++m) {
    double factor = 1.0;
    for (int i = 0; i < derivative; ++i) factor *= m - i;
    double power = 1.0;
    for (int i = 0; i < m - derivative; ++i) power *= tau;
    coef[m] = factor * power / 120.0;
  }
  for (int j = 0; j < 6; ++j) {
    double s = 0.0;
    for (int m = derivative; m < 6; ++m) s += coef[m] * kM[m][j];
    b[j] = s;
  }
}

}  // namespace statebench::sim
