// Urban canyon: which satellites of a GnssConstellation an antenna sees through the static lidar
// world. A satellite above the elevation mask is blocked (NLOS, dropped) when the ray from the
// antenna towards it hits a building, tree, terrain or any other static surface within
// blocking_range_m. Implements the GNSS receivers' SatelliteVisibility hook; the receiver maps the
// visible count to its fix mode. FixQualityFromSky is a richer mapping (count and PDOP).
#pragma once

#include <memory>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/measurements.hpp"
#include "core/time.hpp"
#include "sensors/gnss_constellation.hpp"
#include "sensors/lidar_world.hpp"
#include "sensors/satellite_visibility.hpp"

namespace statebench::sensors {

struct SkyViewOptions {
  double elevation_mask_deg = 10.0;
  double blocking_range_m = 1000.0;  // obstacles farther than this are ignored
};

struct SkyView {
  std::vector<int> visible;  // satellite ids above the mask with a clear line of sight
  std::vector<int> blocked;  // above the mask but blocked
  double pdop = 0.0;         // of the visible set; infinity with fewer than 4
  int above_mask() const { return static_cast<int>(visible.size() + blocked.size()); }
};

// Fix quality by visible count and geometry: the best level whose count and PDOP limits hold.
struct SkyFixThresholds {
  int rtk_fixed_min = 7;
  double rtk_fixed_max_pdop = 4.0;
  int rtk_float_min = 5;
  double rtk_float_max_pdop = 8.0;
  int single_min = 4;
  double single_max_pdop = 20.0;
};

GnssFixStatus FixQualityFromSky(const SkyView& sky, const SkyFixThresholds& thresholds);

// Position dilution of precision of a set of unit line-of-sight vectors (infinity if < 4 or
// degenerate).
double Pdop(const std::vector<Vec3>& unit_los);

class UrbanCanyonVisibility : public SatelliteVisibility {
 public:
  UrbanCanyonVisibility(std::shared_ptr<const LidarWorld> world,
                        const GnssConstellationOptions& constellation,
                        const SkyViewOptions& options = {});

  // Thread-safe (static world only; traffic does not block satellites).
  SkyView Evaluate(const Vec3& p_world_antenna, TimeNs t_ns) const;
  int VisibleSatellites(const Vec3& p_world_antenna, TimeNs t_ns) const override;

  const GnssConstellation& constellation() const { return constellation_; }

 private:
  std::shared_ptr<const LidarWorld> world_;
  GnssConstellation constellation_;
  SkyViewOptions options_;
};

}  // namespace statebench::sensors
