// sensor_msgs/PointCloud2 <-> lidar sweeps (compiled as C++17: ros1_messages.hpp).
//
// Import: x y z (float32 or float64) are required; intensity and ring are read when present (any
// numeric type); the per-point time comes from the topic's time_field or the first of t, time,
// timestamp that the cloud has. Its unit is time_scale_s seconds, by default 1 s for a floating
// field and 1 ns for an integer one (Ouster's t). Values above 1e6 s are absolute times (Hesai's
// timestamp, seconds since the epoch) and are taken relative to the header stamp.
#include <cmath>
#include <cstring>
#include <limits>

#include "core/error.hpp"
#include "sensors/ros1_messages.hpp"

namespace statebench::sensors::ros1 {
namespace {

using sensor_msgs::PointField;

constexpr double kAbsoluteTimeS = 1e6;  // per-point times above this are absolute

std::size_t FieldSize(std::uint8_t datatype) {
  switch (datatype) {
    case PointField::INT8:
    case PointField::UINT8:
      return 1;
    case PointField::INT16:
    case PointField::UINT16:
      return 2;
    case PointField::INT32:
    case PointField::UINT32:
    case PointField::FLOAT32:
      return 4;
    case PointField::FLOAT64:
      return 8;
    default:
      return 0;
  }
}

bool IsFloating(std::uint8_t datatype) {
  return datatype == PointField::FLOAT32 || datatype == PointField::FLOAT64;
}

// A field of the cloud located and checked against the point layout.
struct Field {
  std::uint32_t offset = 0;
  std::uint8_t datatype = 0;

  template <typename T>
  T Load(const std::uint8_t* point) const {
    T v;
    std::memcpy(&v, point + offset, sizeof(T));
    return v;
  }
  // Exact for every type (float32 widens to double exactly).
  double Value(const std::uint8_t* point) const {
    switch (datatype) {
      case PointField::INT8:
        return Load<std::int8_t>(point);
      case PointField::UINT8:
        return Load<std::uint8_t>(point);
      case PointField::INT16:
        return Load<std::int16_t>(point);
      case PointField::UINT16:
        return Load<std::uint16_t>(point);
      case PointField::INT32:
        return Load<std::int32_t>(point);
      case PointField::UINT32:
        return Load<std::uint32_t>(point);
      case PointField::FLOAT32:
        return Load<float>(point);
      default:
        return Load<double>(point);
    }
  }
};

std::optional<Field> FindField(const sensor_msgs::PointCloud2& msg, const std::string& name) {
  for (const PointField& f : msg.fields) {
    if (f.name != name) continue;
    const std::size_t size = FieldSize(f.datatype);
    if (size == 0) {
      throw InputError("field '" + name + "' has an unknown datatype " +
                       std::to_string(f.datatype));
    }
    if (std::size_t{f.offset} + size > msg.point_step) {
      throw InputError("field '" + name + "' (offset " + std::to_string(f.offset) +
                       ") does not fit in point_step " + std::to_string(msg.point_step));
    }
    return Field{f.offset, f.datatype};
  }
  return std::nullopt;
}

Field CoordinateField(const sensor_msgs::PointCloud2& msg, const std::string& name) {
  const std::optional<Field> f = FindField(msg, name);
  if (!f) throw InputError("the cloud has no field '" + name + "'");
  if (!IsFloating(f->datatype)) {
    throw InputError("field '" + name + "' is not float32 or float64");
  }
  return *f;
}

void CheckLayout(const sensor_msgs::PointCloud2& msg) {
  if (msg.is_bigendian) throw InputError("big-endian clouds are not supported");
  const std::uint64_t row_bytes = std::uint64_t{msg.width} * msg.point_step;
  if (msg.row_step < row_bytes) {
    throw InputError("row_step " + std::to_string(msg.row_step) + " is less than width " +
                     std::to_string(msg.width) + " x point_step " + std::to_string(msg.point_step));
  }
  const std::uint64_t needed = std::uint64_t{msg.height} * msg.row_step;
  if (msg.data.size() < needed) {
    throw InputError("data holds " + std::to_string(msg.data.size()) + " bytes, height " +
                     std::to_string(msg.height) + " x row_step " + std::to_string(msg.row_step) +
                     " need " + std::to_string(needed));
  }
}

// The time field and its unit (see the file comment).
std::optional<Field> TimeField(const sensor_msgs::PointCloud2& msg, const RosTopicEntry& entry,
                               PointCloudTiming* timing) {
  timing->field.clear();
  if (entry.time_field) {
    const std::optional<Field> f = FindField(msg, *entry.time_field);
    if (!f) throw InputError("the cloud has no time field '" + *entry.time_field + "'");
    timing->field = *entry.time_field;
    timing->scale_s = entry.time_scale_s.value_or(IsFloating(f->datatype) ? 1.0 : 1e-9);
    return f;
  }
  for (const char* name : {"t", "time", "timestamp"}) {
    if (const std::optional<Field> f = FindField(msg, name)) {
      timing->field = name;
      timing->scale_s = entry.time_scale_s.value_or(IsFloating(f->datatype) ? 1.0 : 1e-9);
      return f;
    }
  }
  return std::nullopt;
}

template <typename T>
void StoreField(std::uint8_t* point, std::uint32_t offset, T value) {
  std::memcpy(point + offset, &value, sizeof(T));
}

}  // namespace

std::vector<LidarPoint> PointsFromRos(const sensor_msgs::PointCloud2& msg,
                                      const RosTopicEntry& entry, TimeNs* stamp_ns,
                                      std::size_t* skipped, PointCloudTiming* timing) {
  CheckLayout(msg);
  const Field x = CoordinateField(msg, "x");
  const Field y = CoordinateField(msg, "y");
  const Field z = CoordinateField(msg, "z");
  const std::optional<Field> intensity = FindField(msg, "intensity");
  const std::optional<Field> ring = FindField(msg, "ring");
  const std::optional<Field> time = TimeField(msg, entry, timing);

  std::vector<LidarPoint> points;
  std::vector<double> t_s;  // per kept point, relative to the header stamp
  points.reserve(std::size_t{msg.width} * msg.height);
  timing->absolute = false;
  const double stamp_s = ToSeconds(*stamp_ns);
  for (std::uint32_t row = 0; row < msg.height; ++row) {
    for (std::uint32_t col = 0; col < msg.width; ++col) {
      const std::uint8_t* p =
          msg.data.data() + std::size_t{row} * msg.row_step + std::size_t{col} * msg.point_step;
      LidarPoint q;
      q.x = static_cast<float>(x.Value(p));
      q.y = static_cast<float>(y.Value(p));
      q.z = static_cast<float>(z.Value(p));
      if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z)) {
        ++*skipped;
        continue;
      }
      if (intensity) q.intensity = static_cast<float>(intensity->Value(p));
      if (ring) {
        const double r = ring->Value(p);
        if (!(r >= 0.0 && r <= std::numeric_limits<std::uint16_t>::max())) {
          throw InputError("ring " + std::to_string(r) + " is not in [0, 65535]");
        }
        q.ring = static_cast<std::uint16_t>(r);
      }
      double t = 0.0;
      if (time) {
        t = time->Value(p) * timing->scale_s;
        if (!std::isfinite(t)) throw InputError("point time is not finite");
        if (points.empty()) timing->absolute = t > kAbsoluteTimeS;
        if (timing->absolute) t -= stamp_s;
      }
      points.push_back(q);
      t_s.push_back(t);
    }
  }
  // Points before the stamp: the stamp moves back to the earliest (rounded down to the
  // nanosecond, so that no time is negative).
  double earliest = 0.0;
  for (double t : t_s) earliest = std::min(earliest, t);
  const TimeNs shift_ns = static_cast<TimeNs>(std::floor(earliest * 1e9));
  *stamp_ns += shift_ns;
  const double shift_s = static_cast<double>(shift_ns) / 1e9;
  for (std::size_t i = 0; i < points.size(); ++i) {
    points[i].t = static_cast<float>(t_s[i] - shift_s);
  }
  return points;
}

sensor_msgs::PointCloud2 PointsToRos(const LidarScan& m, const std::string& frame_id) {
  sensor_msgs::PointCloud2 msg;
  msg.header.stamp = RosTime(m.header.stamp_ns);
  msg.header.frame_id = frame_id;
  const std::size_t n = m.points ? m.points->size() : 0;
  if (n > std::numeric_limits<std::uint32_t>::max() / 22) {
    throw InputError("sweep of " + std::to_string(n) + " points is too large for a PointCloud2");
  }
  const auto field = [](const char* name, std::uint32_t offset, std::uint8_t type) {
    PointField f;
    f.name = name;
    f.offset = offset;
    f.datatype = type;
    f.count = 1;
    return f;
  };
  msg.fields = {field("x", 0, PointField::FLOAT32),  field("y", 4, PointField::FLOAT32),
                field("z", 8, PointField::FLOAT32),  field("intensity", 12, PointField::FLOAT32),
                field("t", 16, PointField::FLOAT32), field("ring", 20, PointField::UINT16)};
  msg.point_step = 22;
  msg.height = 1;
  msg.width = static_cast<std::uint32_t>(n);
  msg.row_step = msg.point_step * msg.width;
  msg.is_bigendian = false;
  msg.is_dense = true;
  msg.data.resize(std::size_t{msg.row_step});
  for (std::size_t i = 0; i < n; ++i) {
    const LidarPoint& q = (*m.points)[i];
    std::uint8_t* p = msg.data.data() + i * msg.point_step;
    StoreField(p, 0, q.x);
    StoreField(p, 4, q.y);
    StoreField(p, 8, q.z);
    StoreField(p, 12, q.intensity);
    StoreField(p, 16, q.t);
    StoreField(p, 20, q.ring);
  }
  return msg;
}

}  // namespace statebench::sensors::ros1
