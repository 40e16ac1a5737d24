// ROS1 messages -> measurements (compiled as C++17: ros1_messages.hpp).
#include <cmath>

#include "core/error.hpp"
#include "sensors/ros1_messages.hpp"

namespace statebench::sensors::ros1 {
namespace {

Vec3 FiniteVector(const geometry_msgs::Vector3& v, const char* field) {
  if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) {
    throw InputError(std::string(field) + " is not finite");
  }
  return Vec3(v.x, v.y, v.z);
}

Mat6 TwistCovariance(const boost::array<double, 36>& c, const RosTopicEntry& entry) {
  if (entry.twist_sigma) return entry.twist_sigma->cwiseAbs2().asDiagonal();
  Mat6 cov;
  bool all_zero = true;
  for (int r = 0; r < 6; ++r) {
    for (int k = 0; k < 6; ++k) {
      const double v = c[static_cast<std::size_t>(6 * r + k)];
      if (!std::isfinite(v)) throw InputError("twist covariance is not finite");
      cov(r, k) = v;
      all_zero = all_zero && v == 0.0;
    }
  }
  if (all_zero) {
    throw InputError(
        "the twist covariance is all zero (unknown): give twist_sigma for this topic in the "
        "topic map");
  }
  for (int i = 0; i < 6; ++i) {
    if (cov(i, i) < 0.0) {
      throw InputError("twist covariance diagonal element " + std::to_string(i) + " is negative (" +
                       std::to_string(cov(i, i)) + ")");
    }
  }
  return cov;
}

// Index of `name` in the message's joint names, or -1.
int JointIndex(const sensor_msgs::JointState& msg, const std::string& name) {
  for (std::size_t i = 0; i < msg.name.size(); ++i) {
    if (msg.name[i] == name) return static_cast<int>(i);
  }
  return -1;
}

double JointValue(const std::vector<double>& values, int index, const std::string& joint,
                  const char* what) {
  if (static_cast<std::size_t>(index) >= values.size()) {
    throw InputError("joint '" + joint + "' has no " + what + " (" + std::to_string(values.size()) +
                     " " + what + " values for the joint names)");
  }
  const double v = values[static_cast<std::size_t>(index)];
  if (!std::isfinite(v)) throw InputError("joint '" + joint + "': " + what + " is not finite");
  return v;
}

}  // namespace

ImuSample ImuFromRos(const sensor_msgs::Imu& msg) {
  ImuSample s;
  s.gyro = FiniteVector(msg.angular_velocity, "angular_velocity");
  s.accel = FiniteVector(msg.linear_acceleration, "linear_acceleration");
  return s;
}

std::optional<GnssFix> GnssFixFromRos(const sensor_msgs::NavSatFix& msg,
                                      const RosTopicEntry& entry) {
  using Status = sensor_msgs::NavSatStatus;
  const bool finite =
      std::isfinite(msg.latitude) && std::isfinite(msg.longitude) && std::isfinite(msg.altitude);
  GnssFix f;
  switch (msg.status.status) {
    case Status::STATUS_NO_FIX:
      if (!finite) return std::nullopt;
      f.status = GnssFixStatus::kNone;
      break;
    case Status::STATUS_FIX:
    case Status::STATUS_SBAS_FIX:
      f.status = GnssFixStatus::kSingle;
      break;
    case Status::STATUS_GBAS_FIX:
      f.status = GnssFixStatus::kRtkFixed;  // or float: decided from the covariance below
      break;
    default:
      throw InputError("status.status " + std::to_string(msg.status.status) +
                       " is not a NavSatStatus value (-1 no fix, 0 fix, 1 SBAS, 2 GBAS)");
  }
  if (!finite) {
    throw InputError("latitude, longitude or altitude is not finite in a fix of status " +
                     std::to_string(msg.status.status));
  }
  if (std::abs(msg.latitude) > 90.0 || std::abs(msg.longitude) > 180.0) {
    throw InputError("latitude " + std::to_string(msg.latitude) + " / longitude " +
                     std::to_string(msg.longitude) + " out of range");
  }
  f.latitude_deg = msg.latitude;
  f.longitude_deg = msg.longitude;
  f.altitude_m = msg.altitude;
  if (entry.position_sigma_m) {
    f.covariance_enu = entry.position_sigma_m->cwiseAbs2().asDiagonal();
  } else if (msg.position_covariance_type == sensor_msgs::NavSatFix::COVARIANCE_TYPE_UNKNOWN) {
    throw InputError(
        "position_covariance_type is UNKNOWN (0): give position_sigma_m for this topic in the "
        "topic map");
  } else {
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        const double v = msg.position_covariance[static_cast<std::size_t>(3 * r + c)];
        if (!std::isfinite(v)) throw InputError("position_covariance is not finite");
        f.covariance_enu(r, c) = v;
      }
    }
    for (int i = 0; i < 3; ++i) {
      if (!(f.covariance_enu(i, i) > 0.0)) {
        throw InputError("position_covariance diagonal element " + std::to_string(i) +
                         " is not positive (" + std::to_string(f.covariance_enu(i, i)) + ")");
      }
    }
  }
  if (f.status == GnssFixStatus::kRtkFixed &&
      std::max(f.covariance_enu(0, 0), f.covariance_enu(1, 1)) >
          kRtkFixedMaxSigmaM * kRtkFixedMaxSigmaM) {
    f.status = GnssFixStatus::kRtkFloat;
  }
  return f;
}

BodyVelocity BodyVelocityFromRos(const geometry_msgs::TwistWithCovariance& twist,
                                 const RosTopicEntry& entry) {
  BodyVelocity b;
  b.velocity = FiniteVector(twist.twist.linear, "twist.linear");
  b.angular_velocity = FiniteVector(twist.twist.angular, "twist.angular");
  b.covariance = TwistCovariance(twist.covariance, entry);
  return b;
}

BodyVelocity BodyVelocityFromRos(const geometry_msgs::Twist& twist, const RosTopicEntry& entry) {
  BodyVelocity b;
  b.velocity = FiniteVector(twist.linear, "twist.linear");
  b.angular_velocity = FiniteVector(twist.angular, "twist.angular");
  if (!entry.twist_sigma) {
    throw InputError(
        "a twist without covariance: give twist_sigma for this topic in the topic map");
  }
  b.covariance = entry.twist_sigma->cwiseAbs2().asDiagonal();
  return b;
}

GnssVelocity GnssVelocityFromRos(const geometry_msgs::Twist& twist,
                                 const boost::array<double, 36>* covariance,
                                 const RosTopicEntry& entry) {
  GnssVelocity v;
  v.v_enu = FiniteVector(twist.linear, "twist.linear");
  if (entry.velocity_sigma_mps) {
    v.sigma_enu = *entry.velocity_sigma_mps;
    return v;
  }
  if (covariance == nullptr) {
    throw InputError(
        "a TwistStamped carries no covariance: give velocity_sigma_mps [east, north, up] for this "
        "topic in the topic map");
  }
  for (int i = 0; i < 3; ++i) {
    const double variance = (*covariance)[static_cast<std::size_t>(7 * i)];
    if (!std::isfinite(variance) || variance < 0.0) {
      throw InputError("twist covariance diagonal element " + std::to_string(i) +
                       " is not a variance (" + std::to_string(variance) + ")");
    }
    v.sigma_enu[i] = std::sqrt(variance);
  }
  if (!(v.sigma_enu.array() > 0.0).all()) {
    throw InputError(
        "the twist's linear covariance has a zero variance (unknown): give velocity_sigma_mps "
        "for this topic in the topic map");
  }
  return v;
}

double SpeedFromRos(const geometry_msgs::Twist& twist) {
  if (!std::isfinite(twist.linear.x)) throw InputError("twist.linear.x is not finite");
  return twist.linear.x;
}

std::optional<SteeringAngle> SteeringFromRos(const sensor_msgs::JointState& msg,
                                             const RosTopicEntry& entry) {
  const int i = JointIndex(msg, entry.joint);
  if (i < 0) return std::nullopt;
  SteeringAngle s;
  s.angle_rad = JointValue(msg.position, i, entry.joint, "position");
  return s;
}

std::optional<WheelSpeeds> WheelsFromRos(const sensor_msgs::JointState& msg,
                                         const RosTopicEntry& entry) {
  std::array<int, 4> index{};
  int found = 0;
  for (std::size_t k = 0; k < 4; ++k) {
    index[k] = JointIndex(msg, entry.joints[k]);
    found += index[k] >= 0 ? 1 : 0;
  }
  if (found == 0) return std::nullopt;
  WheelSpeeds w;
  for (std::size_t k = 0; k < 4; ++k) {
    if (index[k] < 0) {
      throw InputError("joint '" + entry.joints[k] + "' is missing (the message has " +
                       std::to_string(found) + " of the 4 wheel joints)");
    }
    w.omega_radps[k] = JointValue(msg.velocity, index[k], entry.joints[k], "velocity");
  }
  return w;
}

}  // namespace statebench::sensors::ros1
