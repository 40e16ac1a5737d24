// WGS84 <-> local ENU around a fixed origin (GeographicLib's LocalCartesian, exact to
// floating-point precision; no flat-earth approximation).
#pragma once

#include <memory>

#include "core/eigen_types.hpp"

namespace statebench {

struct GeodeticPoint {
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  double altitude_m = 0.0;  // WGS84 ellipsoidal height
};

class LocalEnuFrame {
 public:
  explicit LocalEnuFrame(const GeodeticPoint& origin);
  ~LocalEnuFrame();
  LocalEnuFrame(const LocalEnuFrame& other);
  LocalEnuFrame& operator=(const LocalEnuFrame& other);

  Vec3 ToEnu(const GeodeticPoint& p) const;
  GeodeticPoint ToGeodetic(const Vec3& enu) const;
  const GeodeticPoint& origin() const { return origin_; }

 private:
  struct Impl;
  GeodeticPoint origin_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace statebench
