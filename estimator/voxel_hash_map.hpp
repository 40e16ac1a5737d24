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
//
// Layout (for speed; no result depends on it): a brick index (voxel_brick_index.hpp) maps a
// voxel to its dense index i, and voxel i's points sit in one block of max_points_per_voxel
// slots of a single array. Removing a voxel moves the last one into its place. Queries visit
// voxels in a fixed order of offsets and each voxel's points in arrival order, so their answers
// (ties included) depend only on the map's contents.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/se3.hpp"
#include "estimator/voxel_brick_index.hpp"

namespace statebench::est {

struct VoxelHashMapOptions {
  double voxel_size_m = 1.0;
  int max_points_per_voxel = 20;
  double max_range_m = 100.0;
};

// What a nearest-neighbour search proves about the queries near its own: while the map is
// unchanged, the nearest neighbour of a query q in the same voxel as query_world stays
// nearest_world when distance_m + 2 |q - query_world| < others_m (every other point of the 27
// voxels is at least others_m from query_world, so at least others_m - |q - query_world| from
// q, while nearest_world is at most distance_m + |q - query_world| from it).
struct NearestNeighborProof {
  bool valid = false;
  Vec3 query_world = Vec3::Zero();
  VoxelKey center;
  Vec3 nearest_world = Vec3::Zero();
  double distance_m = 0.0;
  double others_m = 0.0;
};

class VoxelHashMap {
 public:
  explicit VoxelHashMap(const VoxelHashMapOptions& options);

  // Adds world-frame points (each voxel stops accepting once full).
  void AddPoints(const std::vector<Vec3>& points_world);
  // Transforms lidar-frame points by T_world_lidar, adds them, then removes the voxels farther
  // than max_range from the lidar position.
  void Update(const std::vector<Vec3>& points_lidar, const SE3& T_world_lidar);
  // Removes the voxels whose first point lies farther than max_range from origin_world.
  void RemoveVoxelsFarFrom(const Vec3& origin_world);

  // Closest stored point to query_world among the 27 neighbouring voxels (visited from the
  // query's own voxel outwards, offsets in the order 0, -1, 1 per axis, x outermost; the first
  // of equally close points wins). Returns false when they are all empty.
  // With a proof, also fills it (valid when a neighbour was found).
  bool NearestNeighbor(const Vec3& query_world, Vec3* nearest_world, double* distance_m,
                       NearestNeighborProof* proof = nullptr) const;
  // The answer NearestNeighbor would give for query_world (the same point, the same distance
  // bits), from a proof made by a search on this map unchanged since, when the proof covers
  // query_world (with a margin far above rounding); false when it does not: search then.
  bool NearestNeighborFromProof(const NearestNeighborProof& proof, const Vec3& query_world,
                                Vec3* nearest_world, double* distance_m) const;
  // All stored points within radius_m of query_world, searching ceil(radius / voxel) voxels
  // around the query's voxel (at least the 27 neighbours). Order: voxels by offset (dx, dy, dz)
  // from -reach to reach, z innermost, each voxel's points in arrival order.
  void NeighborsWithin(const Vec3& query_world, double radius_m, std::vector<Vec3>* out) const;

  // Every stored point (voxels in an unspecified order).
  std::vector<Vec3> Points() const;
  bool Empty() const { return keys_.empty(); }
  std::size_t NumVoxels() const { return keys_.size(); }
  void Clear();
  const VoxelHashMapOptions& options() const { return options_; }

 private:
  VoxelKey VoxelOf(const Vec3& p) const;
  const Vec3* VoxelPoints(std::uint32_t i) const { return points_.data() + i * capacity_; }
  void RemoveVoxel(std::uint32_t i);

  VoxelHashMapOptions options_;
  std::size_t capacity_;               // points per voxel block
  VoxelBrickIndex index_;              // voxel key -> dense voxel index
  std::vector<VoxelKey> keys_;         // per voxel, dense
  std::vector<std::uint32_t> counts_;  // per voxel: points in its block
  std::vector<Vec3> points_;           // voxel i's points: [i * capacity_, i * capacity_ + count)
};

}  // namespace statebench::est
