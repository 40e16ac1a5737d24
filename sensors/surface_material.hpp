// Surface classes of the lidar world and their diffuse reflectivity near 905 nm (the lidar
// wavelength), used for return intensity and for the reflectivity-limited detection range.
#pragma once

#include <cstdint>

namespace statebench::sensors {

enum class SurfaceMaterial : std::uint8_t {
  kGround,  // soil and grass beside the road
  kRoad,    // asphalt (lanes and junctions)
  kKerb,    // concrete
  kBuilding,
  kPole,
  kTreeTrunk,
  kTreeCrown,
  kParkedCar,
  kVehicle,  // moving traffic
};

// Lambertian reflectivity in [0, 1]. Rough class values (asphalt ~0.15, concrete ~0.35, foliage
// is bright in the near infrared).
inline double Reflectivity(SurfaceMaterial m) {
  switch (m) {
    case SurfaceMaterial::kGround:
      return 0.30;
    case SurfaceMaterial::kRoad:
      return 0.15;
    case SurfaceMaterial::kKerb:
      return 0.35;
    case SurfaceMaterial::kBuilding:
      return 0.45;
    case SurfaceMaterial::kPole:
      return 0.50;
    case SurfaceMaterial::kTreeTrunk:
      return 0.30;
    case SurfaceMaterial::kTreeCrown:
      return 0.55;
    case SurfaceMaterial::kParkedCar:
      return 0.40;
    case SurfaceMaterial::kVehicle:
      return 0.40;
  }
  return 0.3;
}

}  // namespace statebench::sensors
