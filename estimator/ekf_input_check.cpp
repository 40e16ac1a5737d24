#include "estimator/ekf_input_check.hpp"

#include <cmath>
#include <cstdio>

namespace statebench::est {
namespace {

std::string Metres(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f m", v);
  return text;
}

const char* KindName(SensorKind kind) {
  switch (kind) {
    case SensorKind::kWheelEncoders: return "wheel_encoders";
    case SensorKind::kLidar: return "lidar";
    default: return "";
  }
}

// The encoder `id` sits at body x = mount_x; the vehicle file's axle is at axle_x.
void CheckAxle(const std::string& id, const char* axle, double mount_x, double axle_x,
               std::vector<std::string>* out) {
  if (std::abs(mount_x - axle_x) <= kAxleMountToleranceM) return;
  out->push_back("'" + id + "' is mounted at x = " + Metres(mount_x) + " but the vehicle file's " +
                 axle + " axle is at x = " + Metres(axle_x) +
                 " (body frame, origin below the centre of gravity): the vehicle file may "
                 "describe another vehicle");
}

}  // namespace

std::vector<std::string> EkfInputWarnings(const EstimatorSensorSetup& setup,
                                          const SingleTrackParams& vehicle) {
  std::vector<std::string> out;
  bool speed = false, steering = false, gnss = false;
  std::string unused;
  for (const EstimatorSensor& s : setup.sensors) {
    const double x = s.T_body_sensor.translation().x();
    if (s.kind == SensorKind::kSpeedEncoder) {
      speed = true;
      CheckAxle(s.id, "rear", x, -vehicle.cg_to_rear_axle_m, &out);
    } else if (s.kind == SensorKind::kBodyVelocity) {
      speed = true;  // its measured components, at its mount
    } else if (s.kind == SensorKind::kGnss) {
      gnss = true;
    } else if (s.kind == SensorKind::kSteeringEncoder) {
      steering = true;
      CheckAxle(s.id, "front", x, vehicle.cg_to_front_axle_m, &out);
    } else if (*KindName(s.kind) != '\0') {
      unused += (unused.empty() ? "" : ", ") + s.id + " (" + KindName(s.kind) + ")";
    }
  }
  if (!gnss) {
    out.push_back("no GNSS antenna: a local frame (the IMU at 0, the vehicle's forward axis along "
                  "x at the start); position and yaw drift without bound");
  }
  if (!speed) {
    out.push_back(std::string("no speed input (speed_encoder or body_velocity): the speed comes "
                              "from the IMU's longitudinal acceleration ") +
                  (gnss ? "between GNSS fixes only" : "alone and drifts without bound"));
  }
  if (!steering) {
    out.push_back("no steering input (steering_encoder): no single-track lateral dynamics; the "
                  "yaw rate follows the gyro and the side slip is taken as zero");
  }
  if (!unused.empty()) out.push_back("not used by this estimator: " + unused);
  return out;
}

}  // namespace statebench::est
