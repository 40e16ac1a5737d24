// The static world the lidars and GNSS antennas see, as a Bullet collision world built from the
// road network: the terrain (and road surface) as a triangle grid sampled from h(x, y), plus the
// generated WorldLayout (kerbs, buildings, poles, trees, parked cars). Traffic is kept as a
// TrafficTimeline and cast per sweep through a TrafficWindow.
//
// Bullet structure: square terrain tiles and (smaller) object tiles, each one
// btBvhTriangleMeshShape in its own btCollisionObject, all in a btCollisionWorld with a
// btDbvtBroadphase. Bullet (single precision in Debian) stores coordinates relative to
// bullet_origin_world() to keep float rounding near 1e-5 m. The world can be queried with Bullet's
// own API (collision_world(), single-threaded).
//
// CastStatic, the fast thread-safe path: one flat BVH over all the tiles' triangles (our own,
// sensors/triangle_bvh.hpp: float culling, exact double ranging), about 2.5x faster than the
// Bullet walk below (bench/sensors/lidar_raycast_bench) with the same ranges; CastStaticPacket
// casts close rays together through it (another 1.7x for a lidar channel over adjacent columns).
//
// CastStaticBullet, the reference kernel: a 2D grid lists the tiles per ground cell; the ray walks
// the cells in order (DDA), walks each tile it meets with Bullet's BVH (clipped to the tile and to
// the best hit so far) and stops once the best hit lies before the end of the current cell.
// Bullet's BVH only proposes triangles; every candidate is intersected in double precision with
// the double copy of the mesh, so ranges are exact (~1e-9 m relative), whatever the float
// geometry. (Bullet's btCollisionWorld::rayTest shares one traversal stack in Debian's build and is
// not thread-safe; it is also ~2.5x slower per CPU-second, see bench/sensors/lidar_raycast_bench.)
//
// The mesh is the world: cylinders are prisms, spheres icospheres, the terrain a triangle
// grid (exact for planar ground, within ~k s^2 / 8 of a smooth h with curvature k and spacing s).
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "core/eigen_types.hpp"
#include "sensors/ray_hit.hpp"
#include "sensors/traffic_timeline.hpp"
#include "sensors/triangle_bvh.hpp"
#include "sensors/world_inputs.hpp"
#include "sensors/world_layout.hpp"

class btCollisionWorld;

namespace statebench::sensors {

struct TriangleMesh;

struct LidarWorldOptions {
  double ground_spacing_m = 2.0;   // terrain grid step
  double ground_margin_m = 100.0;  // terrain beyond the bounding box of roads and objects
  // Tile sizes: fastest measured with bench/sensors/lidar_raycast_bench (urban grid, XT32).
  double ground_tile_size_m = 64.0;  // terrain tiles
  double object_tile_size_m = 12.0;  // tiles of buildings, kerbs, poles, trees, parked cars
  int cylinder_sides = 8;
  int sphere_subdivisions = 1;  // icosahedron split once: 80 triangles per crown
};

class LidarWorld {
 public:
  // Throws InputError on bad options or when there is nothing to size the ground from.
  LidarWorld(const RoadGeometry& roads, GroundHeightFn ground, WorldLayout layout,
             const LidarWorldOptions& options = {});
  ~LidarWorld();
  LidarWorld(const LidarWorld&) = delete;
  LidarWorld& operator=(const LidarWorld&) = delete;

  // Convenience: BuildWorldLayout then construct.
  static std::unique_ptr<LidarWorld> Build(const RoadGeometry& roads, GroundHeightFn ground,
                                           const WorldLayoutOptions& layout_options,
                                           const LidarWorldOptions& options = {});

  // Closest static surface along origin + r * direction, 0 < r <= max_range_m. Thread-safe.
  std::optional<RayHit> CastStatic(const Vec3& origin_world, const Vec3& unit_direction_world,
                                   double max_range_m) const;
  // The same for `count` (1 to kStaticPacketSize) rays walked together (TriangleBvh::CastPacket:
  // the same ranges, cheaper per ray for close rays such as one channel of adjacent columns).
  static constexpr int kStaticPacketSize = TriangleBvh::kPacketSize;
  void CastStaticPacket(
      const Vec3* origins_world, const Vec3* unit_directions_world, int count,
      double max_range_m, std::optional<RayHit>* hits,
      TriangleBvh::PacketKernel kernel = TriangleBvh::PacketKernel::kBest) const {
    bvh_->CastPacket(origins_world, unit_directions_world, count, max_range_m, hits, kernel);
  }
  // The same through the tiles' Bullet BVHs (the reference kernel; same ranges, slower).
  std::optional<RayHit> CastStaticBullet(const Vec3& origin_world,
                                         const Vec3& unit_direction_world,
                                         double max_range_m) const;

  // Traffic for the run (not thread-safe against concurrent scans: set it before simulating).
  void SetTraffic(TrafficTimeline traffic) { traffic_ = std::move(traffic); }
  const TrafficTimeline& traffic() const { return traffic_; }

  const WorldLayout& layout() const { return layout_; }
  double GroundHeight(double x, double y) const { return ground_(x, y); }
  const Eigen::AlignedBox3d& bounds() const { return bounds_; }
  std::size_t triangle_count() const;
  // The world's triangles, tile by tile (world frame, double).
  std::vector<const TriangleMesh*> tile_meshes() const;
  std::size_t tile_count() const;

  // The Bullet world, for inspection and single-threaded use with Bullet's own API; its
  // coordinates are world minus bullet_origin_world().
  btCollisionWorld& collision_world();
  const Vec3& bullet_origin_world() const { return origin_; }

 private:
  struct Bullet;
  void AddTile(TriangleMesh mesh);  // one Bullet collision object

  GroundHeightFn ground_;
  WorldLayout layout_;
  TrafficTimeline traffic_;
  Eigen::AlignedBox3d bounds_;
  Vec3 origin_ = Vec3::Zero();
  std::unique_ptr<Bullet> bullet_;
  std::unique_ptr<TriangleBvh> bvh_;  // over every tile's triangles
};

}  // namespace statebench::sensors
