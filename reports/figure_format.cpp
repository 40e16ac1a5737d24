#include "reports/figure_format.hpp"

#include <cmath>
#include <cstdio>

namespace statebench::reports {

std::string FormatFigure(double value) {
  if (!std::isfinite(value)) return "-";
  char text[32];
  const double a = std::abs(value);
  std::snprintf(text, sizeof(text), a != 0.0 && (a < 1e-3 || a >= 1e5) ? "%.3e" : "%.4g",
                value);
  return text;
}

}  // namespace statebench::reports
