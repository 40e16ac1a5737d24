#include "core/transform_config.hpp"

#include <numbers>

namespace statebench {

SE3 ParseTransform(const YamlNode& node) {
  node.ExpectOnlyKeys({"translation", "rpy_deg", "quaternion_wxyz"});
  const Vec3 t = node.Get<Vec3>("translation", Vec3::Zero());
  if (node.Has("rpy_deg") && node.Has("quaternion_wxyz")) {
    node.Fail("give either rpy_deg or quaternion_wxyz, not both");
  }
  Quat q = Quat::Identity();
  if (const auto rpy = node.Find("rpy_deg")) {
    const Vec3 a = rpy->As<Vec3>() * (std::numbers::pi / 180.0);
    q = so3::FromRollPitchYaw(a.x(), a.y(), a.z());
  } else if (const auto quat = node.Find("quaternion_wxyz")) {
    const std::vector<double> v = quat->As<std::vector<double>>();
    if (v.size() != 4) quat->Fail("expected 4 numbers [w, x, y, z]");
    q = Quat(v[0], v[1], v[2], v[3]);
    if (std::abs(q.norm() - 1.0) > 1e-3) quat->Fail("quaternion is not of unit norm");
    q.normalize();
  }
  return SE3(q, t);
}

}  // namespace statebench
