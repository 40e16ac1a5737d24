// Beam patterns of spinning lidars: channel elevations, columns per revolution and firing times.
//
// Lidar frame: FLU (x forward, y left, z up). A beam of elevation e fired at azimuth a (CCW from
// x) points along (cos e cos a, cos e sin a, sin e). Rings are numbered from the lowest beam up
// (ring 0 = lowest elevation), as the ROS drivers do.
//
// Timing: the head spins at rotation_rate_hz; column k (k = 0 .. columns-1) fires at
//   t_k = k * period / columns  after the scan start,
// all channels of a column at the same instant (real heads fire channels in a few-microsecond
// sequence within the column; that spread is below the column period and is not modelled).
// Spinning is clockwise seen from above (azimuth decreases with k), starting at azimuth_start_rad.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/measurements.hpp"
#include "core/time.hpp"

namespace statebench::sensors {

struct LidarBeamModel {
  std::string name;
  std::vector<double> elevations_rad;  // by ring, ascending
  int columns = 0;                     // per revolution
  double rotation_rate_hz = 10.0;
  double azimuth_start_rad = 3.141592653589793;  // first column points backwards
  bool clockwise = true;

  int channels() const { return static_cast<int>(elevations_rad.size()); }
  TimeNs PeriodNs() const { return FromSeconds(1.0 / rotation_rate_hz); }
  // Firing time of a column after the scan start, rounded to the nanosecond.
  TimeNs ColumnOffsetNs(int column) const;
  // A point's t: the column's firing time in seconds after the scan start, as float.
  float ColumnTimeS(int column) const { return static_cast<float>(ToSeconds(ColumnOffsetNs(column))); }
  double ColumnAzimuthRad(int column) const;
  Vec3 Direction(int column, int ring) const;  // unit, lidar frame
  // Direction(column, ring) of every beam, column-major: [column * channels() + ring].
  std::vector<Vec3> Directions() const;
};

// The return of a beam (unit direction d_lidar) at range_m, as the simulator makes it and a
// lidar packets file rebuilds it (lidar_packet_file.hpp): each coordinate is the double product
// range_m * d, rounded once to float. One function, so both give the same bits.
inline LidarPoint BeamReturn(const Vec3& d_lidar, double range_m, float intensity, float t_s,
                             std::uint16_t ring) {
  LidarPoint point;
  point.x = static_cast<float>(range_m * d_lidar.x());
  point.y = static_cast<float>(range_m * d_lidar.y());
  point.z = static_cast<float>(range_m * d_lidar.z());
  point.intensity = intensity;
  point.t = t_s;
  point.ring = ring;
  return point;
}

// Hesai PandarXT32: 32 channels from -16 to +15 deg in 1 deg steps, 2000 columns at 10 Hz.
LidarBeamModel HesaiXt32BeamModel();
// Velodyne VLP-16: 16 channels from -15 to +15 deg in 2 deg steps, 1800 columns at 10 Hz.
LidarBeamModel VelodyneVlp16BeamModel();

}  // namespace statebench::sensors
