#include "estimator/voxel_hash_map.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace statebench::est {

VoxelHashMap::VoxelHashMap(const VoxelHashMapOptions& options) : options_(options) {}

VoxelHashMap::Voxel VoxelHashMap::VoxelOf(const Vec3& p) const {
  const Vec3 s = p / options_.voxel_size_m;
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
  double best2 = std::numeric_limits<double>::infinity();
  for (int dx = -1; dx <= 1; ++dx) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dz = -1; dz <= 1; ++dz) {
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
