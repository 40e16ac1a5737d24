// Static transforms in configuration files.
//
//   T_imu_sensor:                   # maps sensor-frame points into the parent frame
//     translation: [x, y, z]        # m
//     rpy_deg: [roll, pitch, yaw]   # R = Rz(yaw) Ry(pitch) Rx(roll); or
//     quaternion_wxyz: [w, x, y, z]
#pragma once

#include <string>

#include "core/se3.hpp"
#include "core/yaml_node.hpp"

namespace statebench {

SE3 ParseTransform(const YamlNode& node);

// The transform as a flow map ParseTransform reads back bit for bit: `{translation: [x, y, z],
// quaternion_wxyz: [w, x, y, z]}` (the rotation left out when it is the identity), numbers in
// shortest round-trip form.
std::string TransformYaml(const SE3& T);

}  // namespace statebench
