#include "core/transform_config.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "core/csv.hpp"

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
    const double norm = q.norm();
    if (std::abs(norm - 1.0) > 1e-3) quat->Fail("quaternion is not of unit norm");
    // A quaternion already unit to rounding (as TransformYaml writes one) is kept bit for bit;
    // dividing it by its rounded norm would move its last bits.
    if (std::abs(norm - 1.0) > 4.0 * std::numeric_limits<double>::epsilon()) q.normalize();
  }
  return SE3(q, t);
}

std::string TransformYaml(const SE3& T) {
  const Vec3& t = T.translation();
  std::string out = "{translation: [" + NumberText(t.x()) + ", " + NumberText(t.y()) + ", " +
                    NumberText(t.z()) + "]";
  const Quat& q = T.rotation();
  if (q.w() != 1.0 || q.x() != 0.0 || q.y() != 0.0 || q.z() != 0.0) {
    out += ", quaternion_wxyz: [" + NumberText(q.w()) + ", " + NumberText(q.x()) + ", " +
           NumberText(q.y()) + ", " + NumberText(q.z()) + "]";
  }
  return out + "}";
}

}  // namespace statebench
