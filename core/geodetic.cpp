#include "core/geodetic.hpp"

#include <GeographicLib/LocalCartesian.hpp>

namespace statebench {

struct LocalEnuFrame::Impl {
  GeographicLib::LocalCartesian proj;
};

LocalEnuFrame::LocalEnuFrame(const GeodeticPoint& origin)
    : origin_(origin),
      impl_(std::make_unique<Impl>(Impl{GeographicLib::LocalCartesian(
          origin.latitude_deg, origin.longitude_deg, origin.altitude_m)})) {}

LocalEnuFrame::~LocalEnuFrame() = default;

LocalEnuFrame::LocalEnuFrame(const LocalEnuFrame& other)
    : origin_(other.origin_), impl_(std::make_unique<Impl>(*other.impl_)) {}

LocalEnuFrame& LocalEnuFrame::operator=(const LocalEnuFrame& other) {
  origin_ = other.origin_;
  impl_ = std::make_unique<Impl>(*other.impl_);
  return *this;
}

Vec3 LocalEnuFrame::ToEnu(const GeodeticPoint& p) const {
  Vec3 enu;
  impl_->proj.Forward(p.latitude_deg, p.longitude_deg, p.altitude_m, enu.x(), enu.y(), enu.z());
  return enu;
}

GeodeticPoint LocalEnuFrame::ToGeodetic(const Vec3& enu) const {
  GeodeticPoint p;
  impl_->proj.Reverse(enu.x(), enu.y(), enu.z(), p.latitude_deg, p.longitude_deg, p.altitude_m);
  return p;
}

}  // namespace statebench
