// Static transforms in configuration files.
//
//   T_imu_sensor:                   # maps sensor-frame points into the parent frame
//     translation: [x, y, z]        # m
//     rpy_deg: [roll, pitch, yaw]   # R = Rz(yaw) Ry(pitch) Rx(roll); or
//     quaternion_wxyz: [w, x, y, z]
#pragma once

#include "core/se3.hpp"
#include "core/yaml_node.hpp"

namespace statebench {

SE3 ParseTransform(const YamlNode& node);

}  // namespace statebench
