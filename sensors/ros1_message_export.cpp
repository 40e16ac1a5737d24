// Measurements -> ROS1 messages (compiled as C++17: ros1_messages.hpp). Lidar sweeps are in
// ros1_point_cloud.cpp.
#include "core/error.hpp"
#include "sensors/ros1_messages.hpp"

namespace statebench::sensors::ros1 {
namespace {

geometry_msgs::Vector3 RosVector(const Vec3& v) {
  geometry_msgs::Vector3 out;
  out.x = v.x();
  out.y = v.y();
  out.z = v.z();
  return out;
}

std_msgs::Header RosHeader(const MeasurementHeader& h, const std::string& frame_id) {
  std_msgs::Header out;
  out.stamp = RosTime(h.stamp_ns);
  out.frame_id = frame_id;
  return out;
}

std::int8_t RosStatus(GnssFixStatus status) {
  using Status = sensor_msgs::NavSatStatus;
  switch (status) {
    case GnssFixStatus::kNone:
      return Status::STATUS_NO_FIX;
    case GnssFixStatus::kSingle:
      return Status::STATUS_FIX;
    case GnssFixStatus::kRtkFloat:
    case GnssFixStatus::kRtkFixed:
      return Status::STATUS_GBAS_FIX;
  }
  return Status::STATUS_NO_FIX;
}

}  // namespace

ros::Time RosTime(TimeNs t_ns) {
  if (t_ns < 0) {
    throw InputError("stamp " + std::to_string(t_ns) +
                     " ns is negative: ROS1 times are unsigned (shift them with a time offset)");
  }
  ros::Time t;
  t.fromNSec(static_cast<std::uint64_t>(t_ns));
  return t;
}

sensor_msgs::Imu ImuToRos(const ImuSample& m, const std::string& frame_id) {
  sensor_msgs::Imu msg;
  msg.header = RosHeader(m.header, frame_id);
  msg.orientation.w = 1.0;
  msg.orientation_covariance[0] = -1.0;  // REP-145: no orientation estimate
  msg.angular_velocity = RosVector(m.gyro);
  msg.linear_acceleration = RosVector(m.accel);
  // Covariances stay zero: "unknown" (the noise is in the sensor setup, not per sample).
  return msg;
}

sensor_msgs::NavSatFix GnssFixToRos(const GnssFix& m, const std::string& frame_id) {
  sensor_msgs::NavSatFix msg;
  msg.header = RosHeader(m.header, frame_id);
  msg.status.status = RosStatus(m.status);
  msg.status.service = sensor_msgs::NavSatStatus::SERVICE_GPS;
  msg.latitude = m.latitude_deg;
  msg.longitude = m.longitude_deg;
  msg.altitude = m.altitude_m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      msg.position_covariance[static_cast<std::size_t>(3 * r + c)] = m.covariance_enu(r, c);
    }
  }
  msg.position_covariance_type = sensor_msgs::NavSatFix::COVARIANCE_TYPE_KNOWN;
  return msg;
}

geometry_msgs::TwistWithCovarianceStamped BodyVelocityToRos(const BodyVelocity& m,
                                                            const std::string& frame_id) {
  geometry_msgs::TwistWithCovarianceStamped msg;
  msg.header = RosHeader(m.header, frame_id);
  msg.twist.twist.linear = RosVector(m.velocity);
  msg.twist.twist.angular = RosVector(m.angular_velocity);
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) {
      msg.twist.covariance[static_cast<std::size_t>(6 * r + c)] = m.covariance(r, c);
    }
  }
  return msg;
}

geometry_msgs::TwistWithCovarianceStamped GnssVelocityToRos(const GnssFix& m,
                                                            const std::string& frame_id) {
  geometry_msgs::TwistWithCovarianceStamped msg;
  msg.header = RosHeader(m.header, frame_id);
  msg.twist.twist.linear = RosVector(m.velocity->v_enu);
  for (int i = 0; i < 3; ++i) {
    const double sigma = m.velocity->sigma_enu[i];
    msg.twist.covariance[static_cast<std::size_t>(7 * i)] = sigma * sigma;
    msg.twist.covariance[static_cast<std::size_t>(7 * (i + 3))] = -1.0;
  }
  return msg;
}

geometry_msgs::TwistStamped SpeedToRos(const VehicleSpeed& m, const std::string& frame_id) {
  geometry_msgs::TwistStamped msg;
  msg.header = RosHeader(m.header, frame_id);
  msg.twist.linear.x = m.speed_mps;
  return msg;
}

sensor_msgs::JointState SteeringToRos(const SteeringAngle& m, const std::string& joint,
                                      const std::string& frame_id) {
  sensor_msgs::JointState msg;
  msg.header = RosHeader(m.header, frame_id);
  msg.name = {joint};
  msg.position = {m.angle_rad};
  return msg;
}

sensor_msgs::JointState WheelsToRos(const WheelSpeeds& m, const std::array<std::string, 4>& joints,
                                    const std::string& frame_id) {
  sensor_msgs::JointState msg;
  msg.header = RosHeader(m.header, frame_id);
  msg.name.assign(joints.begin(), joints.end());
  msg.velocity.assign(m.omega_radps.begin(), m.omega_radps.end());
  return msg;
}

}  // namespace statebench::sensors::ros1
