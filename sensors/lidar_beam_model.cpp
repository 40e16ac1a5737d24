#include "sensors/lidar_beam_model.hpp"

#include <cmath>
#include <numbers>

namespace statebench::sensors {
namespace {

LidarBeamModel Uniform(const std::string& name, int channels, double lowest_deg, double step_deg,
                       int columns) {
  LidarBeamModel m;
  m.name = name;
  for (int i = 0; i < channels; ++i) {
    m.elevations_rad.push_back((lowest_deg + step_deg * i) * std::numbers::pi / 180.0);
  }
  m.columns = columns;
  return m;
}

}  // namespace

TimeNs LidarBeamModel::ColumnOffsetNs(int column) const {
  const TimeNs period = PeriodNs();
  return (static_cast<TimeNs>(column) * period + columns / 2) / columns;
}

double LidarBeamModel::ColumnAzimuthRad(int column) const {
  const double step = 2.0 * std::numbers::pi / columns;
  return azimuth_start_rad + (clockwise ? -step : step) * column;
}

Vec3 LidarBeamModel::Direction(int column, int ring) const {
  const double a = ColumnAzimuthRad(column);
  const double e = elevations_rad[static_cast<std::size_t>(ring)];
  return Vec3(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
}

std::vector<Vec3> LidarBeamModel::Directions() const {
  std::vector<Vec3> out;
  out.reserve(static_cast<std::size_t>(columns) * elevations_rad.size());
  for (int c = 0; c < columns; ++c) {
    for (int r = 0; r < channels(); ++r) out.push_back(Direction(c, r));
  }
  return out;
}

LidarBeamModel HesaiXt32BeamModel() { return Uniform("hesai_xt32", 32, -16.0, 1.0, 2000); }

LidarBeamModel VelodyneVlp16BeamModel() { return Uniform("velodyne_vlp16", 16, -15.0, 2.0, 1800); }

}  // namespace statebench::sensors
