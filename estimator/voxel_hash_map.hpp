// Voxel-hash local map for lidar odometry (KISS-ICP style, Vizzo et al., RA-L 2023).
//
// Points are stored in the map's world frame, grouped by the integer voxel index
// floor(p / voxel_size). Each voxel keeps at most max_points_per_voxel points (the first ones
// that arrived: the map is refreshed by removal, not by replacement), and voxels whose first
// point lies farther than max_range from the current sensor position are dropped, which keeps
// the map local and its size bounded.
//
// Nearest-neighbour queries search the 27 voxels around the query's voxel, so a neighbour is
// always found when it is within one voxel size of the query (and possibly farther).
#pragma once

#include <cstddef>
#include <unordered_map>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/se3.hpp"

namespace statebench::est {

struct VoxelHashMapOptions {
  double voxel_size_m = 1.0;
  int max_points_per_voxel = 20;
  double max_range_m = 100.0;
};

class VoxelHashMap {
 public:
  explicit VoxelHashMap(const VoxelHashMapOptions& options);

  // Adds world-frame points (each voxel stops accepting once full).
  void AddPoints(const std::vector<Vec3>& points_world);
  // Transforms lidar-frame points by T_world_lidar, adds them, then removes the voxels farther
  // than max_range from the lidar position.
  void Update(const std::vector<Vec3>& points_lidar, const SE3& T_world_lidar);
  void RemoveVoxelsFarFrom(const Vec3& origin_world);

  // Closest stored point to query_world among the 27 neighbouring voxels. Returns false when
  // they are all empty.
  bool NearestNeighbor(const Vec3& query_world, Vec3* nearest_world, double* distance_m) const;
  // All stored points within radius_m of query_world (searching ceil(radius / voxel) voxels
  // around the query's voxel, at least the 27 neighbours).
  void NeighborsWithin(const Vec3& query_world, double radius_m, std::vector<Vec3>* out) const;

  std::vector<Vec3> Points() const;
  bool Empty() const { return voxels_.empty(); }
  std::size_t NumVoxels() const { return voxels_.size(); }
  void Clear() { voxels_.clear(); }
  const VoxelHashMapOptions& options() const { return options_; }

 private:
  using Voxel = Eigen::Vector3i;
  struct VoxelHash {
    std::size_t operator()(const Voxel& v) const {
      // Teschner et al. (2003) spatial hash primes.
      return static_cast<std::size_t>(static_cast<std::uint32_t>(v.x()) * 73856093u ^
                                      static_cast<std::uint32_t>(v.y()) * 19349669u ^
                                      static_cast<std::uint32_t>(v.z()) * 83492791u);
    }
  };
  Voxel VoxelOf(const Vec3& p) const;

  VoxelHashMapOptions options_;
  std::unordered_map<Voxel, std::vector<Vec3>, VoxelHash> voxels_;
};

}  // namespace statebench::est
