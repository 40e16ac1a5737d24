#include "sensors/gnss_options.hpp"

namespace statebench::sensors {

std::optional<GnssMode> ParseGnssMode(std::string_view name) {
  if (name == "single") return GnssMode::kSingle;
  if (name == "rtk_float") return GnssMode::kRtkFloat;
  if (name == "rtk_fixed") return GnssMode::kRtkFixed;
  return std::nullopt;
}

GnssFixStatus ToFixStatus(GnssMode mode) {
  switch (mode) {
    case GnssMode::kSingle:
      return GnssFixStatus::kSingle;
    case GnssMode::kRtkFloat:
      return GnssFixStatus::kRtkFloat;
    case GnssMode::kRtkFixed:
      return GnssFixStatus::kRtkFixed;
  }
  return GnssFixStatus::kNone;
}

GnssAccuracy DefaultAccuracy(GnssMode mode) {
  double sigma_h = 0.0;
  switch (mode) {
    case GnssMode::kSingle:
      sigma_h = 2.0 / kCep50PerSigma;
      break;
    case GnssMode::kRtkFloat:
      sigma_h = 0.25;
      break;
    case GnssMode::kRtkFixed:
      sigma_h = 0.01;
      break;
  }
  return GnssAccuracy{sigma_h * kCep50PerSigma, 1.5 * sigma_h};
}

}  // namespace statebench::sensors
