#include "estimator/voxel_hash_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace statebench::est {

VoxelHashMap::VoxelHashMap(const VoxelHashMapOptions& options) : options_(options) {}

VoxelHashMap::Voxel VoxelHashMap::VoxelOf(const Vec3& p) const {
  // Clamped into the int range (a far or non-finite point lands in an edge voxel; the cast of an
  // out-of-range double is undefined).
  const Vec3 s = (p / options_.voxel_size_m).cwiseMax(-1e9).cwiseMin(1e9);
  return Voxel(static_cast<int>(std::floor(s.x())), static_cast<int>(std::floor(s.y())),
               static_cast<int>(std::floor(s.z())));
}

void VoxelHashMap::AddPoints(const std::vector<Vec3>& points_world) {
  const auto max_points = static_cast<std::size_t>(options_.max_points_per_voxel);
  for (const Vec3& p : points_world) {
    std::vector<Vec3>& voxel = voxels_[VoxelOf(p)];
    if (voxel.size() < max_points) {
      if (voxel.empty()) voxel.reserve(max_points);
      voxel.push_back(p);
    }
  }
}

void VoxelHashMap::Update(const std::vector<Vec3>& points_lidar, const SE3& T_world_lidar) {
  std::vector<Vec3> points_world;
  points_world.reserve(points_lidar.size());
  for (const Vec3& p : points_lidar) points_world.push_back(T_world_lidar * p);
  AddPoints(points_world);
  RemoveVoxelsFarFrom(T_world_lidar.translation());
}

void VoxelHashMap::RemoveVoxelsFarFrom(const Vec3& origin_world) {
  const double max_range2 = options_.max_range_m * options_.max_range_m;
  for (auto it = voxels_.begin(); it != voxels_.end();) {
    if (it->second.empty() || (it->second.front() - origin_world).squaredNorm() > max_range2) {
      it = voxels_.erase(it);
    } else {
      ++it;
    }
  }
}

bool VoxelHashMap::NearestNeighbor(const Vec3& query_world, Vec3* nearest_world,
                                   double* distance_m) const {
  const Voxel center = VoxelOf(query_world);
  // Offset of the query inside its voxel, in [0, v) per axis: a neighbour voxel at offset
  // d in {-1, 0, 1} is at least (v - s) (d = 1), s (d = -1) or 0 (d = 0) away along that axis.
  // Voxels that cannot beat the best distance so far are skipped before the hash lookup; the
  // query's own voxel is searched first to make that bound tight early.
  const double v = options_.voxel_size_m;
  const Vec3 s = query_world - center.cast<double>() * v;
  auto gap2 = [&](int axis, int d) {
    const double g = d > 0 ? v - s(axis) : (d < 0 ? s(axis) : 0.0);
    return g * g;
  };
  static constexpr int kOrder[3] = {0, -1, 1};
  double best2 = std::numeric_limits<double>::infinity();
  for (const int dx : kOrder) {
    const double gx = gap2(0, dx);
    if (gx >= best2) continue;
    for (const int dy : kOrder) {
      const double gxy = gx + gap2(1, dy);
      if (gxy >= best2) continue;
      for (const int dz : kOrder) {
        if (gxy + gap2(2, dz) >= best2) continue;
        const auto it = voxels_.find(center + Voxel(dx, dy, dz));
        if (it == voxels_.end()) continue;
        for (const Vec3& p : it->second) {
          const double d2 = (p - query_world).squaredNorm();
          if (d2 < best2) {
            best2 = d2;
            *nearest_world = p;
          }
        }
      }
    }
  }
  if (!std::isfinite(best2)) return false;
  *distance_m = std::sqrt(best2);
  return true;
}

void VoxelHashMap::NeighborsWithin(const Vec3& query_world, double radius_m,
                                   std::vector<Vec3>* out) const {
  out->clear();
  const Voxel center = VoxelOf(query_world);
  const double r2 = radius_m * radius_m;
  const int reach = std::max(1, static_cast<int>(std::ceil(radius_m / options_.voxel_size_m)));
  for (int dx = -reach; dx <= reach; ++dx) {
    for (int dy = -reach; dy <= reach; ++dy) {
      for (int dz = -reach; dz <= reach; ++dz) {
        const auto it = voxels_.find(center + Voxel(dx, dy, dz));
        if (it == voxels_.end()) continue;
        for (const Vec3& p : it->second) {
          if ((p - query_world).squaredNorm() <= r2) out->push_back(p);
        }
      }
    }
  }
}

std::vector<Vec3> VoxelHashMap::Points() const {
  std::vector<Vec3> points;
  for (const auto& [voxel, voxel_points] : voxels_) {
    points.insert(points.end(), voxel_points.begin(), voxel_points.end());
  }
  return points;
}

}  // namespace statebench::est
