// A figure as printed in the tables of `results summary` and `compare`: four significant
// digits, exponent form below 1e-3 and from 1e5, "-" when not finite.
#pragma once

#include <string>

namespace statebench::reports {

std::string FormatFigure(double value);

}  // namespace statebench::reports
