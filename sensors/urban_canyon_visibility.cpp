#include "sensors/urban_canyon_visibility.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.hpp"

namespace statebench::sensors {

double Pdop(const std::vector<Vec3>& unit_los) {
  if (unit_los.size() < 4) return std::numeric_limits<double>::infinity();
  // Pseudorange geometry: rows (-e^T, 1), unknowns (position, clock).
  Eigen::Matrix4d normal = Eigen::Matrix4d::Zero();
  for (const Vec3& e : unit_los) {
    const Vec4 row(-e.x(), -e.y(), -e.z(), 1.0);
    normal += row * row.transpose();
  }
  const Eigen::FullPivLU<Eigen::Matrix4d> lu(normal);
  if (lu.rank() < 4) return std::numeric_limits<double>::infinity();
  const Eigen::Matrix4d q = lu.inverse();
  return std::sqrt(q(0, 0) + q(1, 1) + q(2, 2));
}

GnssFixStatus FixQualityFromSky(const SkyView& sky, const SkyFixThresholds& th) {
  const int n = static_cast<int>(sky.visible.size());
  if (n >= th.rtk_fixed_min && sky.pdop <= th.rtk_fixed_max_pdop) return GnssFixStatus::kRtkFixed;
  if (n >= th.rtk_float_min && sky.pdop <= th.rtk_float_max_pdop) return GnssFixStatus::kRtkFloat;
  if (n >= th.single_min && sky.pdop <= th.single_max_pdop) return GnssFixStatus::kSingle;
  return GnssFixStatus::kNone;
}

UrbanCanyonVisibility::UrbanCanyonVisibility(std::shared_ptr<const LidarWorld> world,
                                             const GnssConstellationOptions& constellation,
                                             const SkyViewOptions& options)
    : world_(std::move(world)), constellation_(constellation), options_(options) {
  if (!world_) throw InputError("urban canyon visibility: no world");
  if (!(options_.blocking_range_m > 0.0)) {
    throw InputError("urban canyon visibility: blocking_range_m must be > 0");
  }
}

SkyView UrbanCanyonVisibility::Evaluate(const Vec3& p_world_antenna, TimeNs t_ns) const {
  const double sin_mask = std::sin(options_.elevation_mask_deg * std::numbers::pi / 180.0);
  const std::vector<Vec3> los = constellation_.DirectionsEnu(t_ns);
  SkyView sky;
  std::vector<Vec3> visible_los;
  for (std::size_t i = 0; i < los.size(); ++i) {
    if (los[i].z() < sin_mask) continue;
    if (world_->CastStatic(p_world_antenna, los[i], options_.blocking_range_m)) {
      sky.blocked.push_back(static_cast<int>(i));
    } else {
      sky.visible.push_back(static_cast<int>(i));
      visible_los.push_back(los[i]);
    }
  }
  sky.pdop = Pdop(visible_los);
  return sky;
}

int UrbanCanyonVisibility::VisibleSatellites(const Vec3& p_world_antenna, TimeNs t_ns) const {
  return static_cast<int>(Evaluate(p_world_antenna, t_ns).visible.size());
}

}  // namespace statebench::sensors
