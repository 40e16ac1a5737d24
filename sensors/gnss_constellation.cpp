#include "sensors/gnss_constellation.hpp"

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "core/random.hpp"

namespace statebench::sensors {
namespace {

constexpr double kEarthRadiusM = 6'371e3;
constexpr double kEarthRateRadps = 7.2921151467e-5;
constexpr double kDeg = std::numbers::pi / 180.0;

}  // namespace

GnssConstellation::GnssConstellation(const GnssConstellationOptions& o) : options_(o) {
  if (o.planes < 1 || o.satellites_per_plane < 1) {
    throw InputError("gnss constellation: planes and satellites_per_plane must be >= 1");
  }
  if (!(o.orbit_radius_m > kEarthRadiusM) || !(o.period_s > 0.0)) {
    throw InputError("gnss constellation: orbit radius must exceed the Earth's, period > 0");
  }
  std::mt19937_64 rng = MakeRng(o.seed, "gnss_constellation");
  const double raan0 = 2.0 * std::numbers::pi * Uniform01(rng);
  const double anomaly0 = 2.0 * std::numbers::pi * Uniform01(rng);
  epoch_offset_s_ = 86'164.0 * Uniform01(rng);
  const int total = o.planes * o.satellites_per_plane;
  for (int p = 0; p < o.planes; ++p) {
    for (int s = 0; s < o.satellites_per_plane; ++s) {
      // Walker delta pattern with phasing factor 1, plus a small seeded jitter per satellite.
      const double jitter = 0.1 * (Uniform01(rng) - 0.5);
      satellites_.push_back({raan0 + 2.0 * std::numbers::pi * p / o.planes,
                             anomaly0 + 2.0 * std::numbers::pi * s / o.satellites_per_plane +
                                 2.0 * std::numbers::pi * p / total + jitter});
    }
  }
}

std::vector<Vec3> GnssConstellation::DirectionsEnu(TimeNs t_ns) const {
  const double t = ToSeconds(t_ns);
  const double n = 2.0 * std::numbers::pi / options_.period_s;
  const double inc = options_.inclination_deg * kDeg;
  const double lat = options_.site_latitude_deg * kDeg;
  // Earth rotation: the site's longitude in the inertial frame advances with time.
  const double lon = options_.site_longitude_deg * kDeg + kEarthRateRadps * (t + epoch_offset_s_);
  const Vec3 up(std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat));
  const Vec3 east(-std::sin(lon), std::cos(lon), 0.0);
  const Vec3 north = up.cross(east);
  const Vec3 site = kEarthRadiusM * up;

  std::vector<Vec3> out;
  out.reserve(satellites_.size());
  for (const Satellite& s : satellites_) {
    const double u = s.anomaly_at_epoch_rad + n * t;
    const double c_o = std::cos(s.raan_rad), s_o = std::sin(s.raan_rad);
    const Vec3 sat =
        options_.orbit_radius_m * Vec3(std::cos(u) * c_o - std::sin(u) * std::cos(inc) * s_o,
                                       std::cos(u) * s_o + std::sin(u) * std::cos(inc) * c_o,
                                       std::sin(u) * std::sin(inc));
    const Vec3 los = (sat - site).normalized();
    out.emplace_back(los.dot(east), los.dot(north), los.dot(up));
  }
  return out;
}

}  // namespace statebench::sensors
