// Conversions between ROS1 messages and StateBench measurements (docs/real-data.md says what
// each field becomes). PRIVATE to the ROS1 bag sources of sensors/ (rosbag_*.cpp, ros1_*.cpp):
// it includes ROS1 message headers, which compile only as C++17 (cmake/StateBenchRosbag.cmake),
// so no public header includes it.
//
// Conventions (REP-103, REP-105, REP-145): vectors of a message are in its header.frame_id (an
// Odometry's twist in its child_frame_id), FLU; NavSatFix covariances in ENU, row-major, m^2;
// 6x6 twist covariances ordered (vx, vy, vz, wx, wy, wz), as BodyVelocity's. Header stamps carry
// the measurement stamp; the caller sets it and the arrival (the bag's receive time).
//
// The importers throw InputError with a message that names the field (the caller prefixes the
// bag, topic and message index).
#pragma once

#include <geometry_msgs/TwistStamped.h>
#include <geometry_msgs/TwistWithCovarianceStamped.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/NavSatFix.h>
#include <sensor_msgs/PointCloud2.h>

#include <optional>
#include <string>
#include <vector>

#include "core/measurements.hpp"
#include "sensors/rosbag_topic_map.hpp"

namespace statebench::sensors::ros1 {

// ---- ROS -> StateBench (the header of the result is left for the caller) ----

ImuSample ImuFromRos(const sensor_msgs::Imu& msg);

// nullopt for a NO_FIX message without a finite position (drivers publish NaN then). Status:
// NO_FIX -> none, FIX and SBAS_FIX -> single, GBAS_FIX -> rtk_fixed when the horizontal sigma is
// at most kRtkFixedMaxSigmaM, else rtk_float. Covariance: the message's (COVARIANCE_TYPE_UNKNOWN
// needs entry.position_sigma_m), replaced by entry.position_sigma_m when that is given.
inline constexpr double kRtkFixedMaxSigmaM = 0.1;
std::optional<GnssFix> GnssFixFromRos(const sensor_msgs::NavSatFix& msg,
                                      const RosTopicEntry& entry);

// The twist with its covariance (entry.twist_sigma replaces it; an all-zero covariance means
// "unknown" and needs entry.twist_sigma).
BodyVelocity BodyVelocityFromRos(const geometry_msgs::TwistWithCovariance& twist,
                                 const RosTopicEntry& entry);
BodyVelocity BodyVelocityFromRos(const geometry_msgs::Twist& twist, const RosTopicEntry& entry);
double SpeedFromRos(const geometry_msgs::Twist& twist);  // linear.x

// A receiver's ENU velocity (gnss_velocity topic): linear (x east, y north, z up) with the square
// roots of the covariance's linear diagonal (nullptr: a TwistStamped, no covariance), replaced by
// entry.velocity_sigma_mps when that is given; an all-zero linear block is "unknown" and needs it.
GnssVelocity GnssVelocityFromRos(const geometry_msgs::Twist& twist,
                                 const boost::array<double, 36>* covariance,
                                 const RosTopicEntry& entry);

// nullopt when the message names none of the entry's joints (a JointState topic may carry other
// joints in separate messages).
std::optional<SteeringAngle> SteeringFromRos(const sensor_msgs::JointState& msg,
                                             const RosTopicEntry& entry);
std::optional<WheelSpeeds> WheelsFromRos(const sensor_msgs::JointState& msg,
                                         const RosTopicEntry& entry);

// A sweep: its points (non-finite ones skipped, counted in *skipped) with per-point times in
// seconds after *stamp_ns. *stamp_ns comes in as the header stamp and is moved back to the
// earliest point time when points are earlier than it (drivers that stamp the end of a sweep).
struct PointCloudTiming {
  std::string field;  // the time field used, empty when the cloud has none (all t = 0)
  double scale_s = 1.0;
  bool absolute = false;  // values are absolute times (seconds since the epoch after scaling)
};
std::vector<LidarPoint> PointsFromRos(const sensor_msgs::PointCloud2& msg,
                                      const RosTopicEntry& entry, TimeNs* stamp_ns,
                                      std::size_t* skipped, PointCloudTiming* timing);

// ---- StateBench -> ROS ----

// ros::Time of a stamp; throws InputError when it is negative (ROS1 time is unsigned).
ros::Time RosTime(TimeNs t_ns);

sensor_msgs::Imu ImuToRos(const ImuSample& m, const std::string& frame_id);
sensor_msgs::NavSatFix GnssFixToRos(const GnssFix& m, const std::string& frame_id);
geometry_msgs::TwistWithCovarianceStamped BodyVelocityToRos(const BodyVelocity& m,
                                                            const std::string& frame_id);
// The fix's velocity (it must have one) with diag(sigma^2) as the linear covariance and the
// unmeasured angular velocity at variance -1 (not used by the import).
geometry_msgs::TwistWithCovarianceStamped GnssVelocityToRos(const GnssFix& m,
                                                            const std::string& frame_id);
geometry_msgs::TwistStamped SpeedToRos(const VehicleSpeed& m, const std::string& frame_id);
// JointStates carry the sensor's frame too (empty in most drivers), so that its mount survives.
sensor_msgs::JointState SteeringToRos(const SteeringAngle& m, const std::string& joint,
                                      const std::string& frame_id);
sensor_msgs::JointState WheelsToRos(const WheelSpeeds& m, const std::array<std::string, 4>& joints,
                                    const std::string& frame_id);
// Fields x y z intensity t (float32) ring (uint16), packed (22 bytes a point), one row.
sensor_msgs::PointCloud2 PointsToRos(const LidarScan& m, const std::string& frame_id);

}  // namespace statebench::sensors::ros1
