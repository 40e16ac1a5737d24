// A synthetic GNSS constellation: a Walker-type arrangement of circular medium-Earth orbits (GPS
// like: 6 planes x 5 satellites, 55 deg inclination, half-sidereal-day period), with a seeded
// orientation, seen from a fixed site on a spherical Earth that rotates underneath. Gives the
// line-of-sight directions in the site's local ENU frame; satellites move by about 0.5 deg per
// minute, as real ones do.
#pragma once

#include <cstdint>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/time.hpp"

namespace statebench::sensors {

struct GnssConstellationOptions {
  std::uint64_t seed = 0;
  int planes = 6;
  int satellites_per_plane = 5;
  double inclination_deg = 55.0;
  double orbit_radius_m = 26'560e3;
  double period_s = 43'082.0;  // half a sidereal day
  double site_latitude_deg = 48.0;
  double site_longitude_deg = 11.0;
};

class GnssConstellation {
 public:
  explicit GnssConstellation(const GnssConstellationOptions& options);  // InputError on bad options

  int size() const { return static_cast<int>(satellites_.size()); }
  // Unit line-of-sight vectors from the site to every satellite (local ENU), index = satellite id.
  std::vector<Vec3> DirectionsEnu(TimeNs t_ns) const;

 private:
  struct Satellite {
    double raan_rad;              // right ascension of the ascending node
    double anomaly_at_epoch_rad;  // argument of latitude at t = 0
  };
  GnssConstellationOptions options_;
  double epoch_offset_s_ = 0.0;  // seeded Earth rotation angle at t = 0, as time
  std::vector<Satellite> satellites_;
};

}  // namespace statebench::sensors
