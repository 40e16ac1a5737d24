#include "sensors/lidar_world.hpp"

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <btBulletCollisionCommon.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "sensors/road_clearance.hpp"
#include "sensors/tile_grid.hpp"
#include "sensors/world_mesh.hpp"
#include "sensors/world_tiles.hpp"

namespace statebench::sensors {
namespace {

// Bullet's BVH walk tests the segment against node boxes grown by this much (in float, so the
// culling stays conservative for the exact double test even on flat, zero-thickness boxes).
constexpr btScalar kWalkPadM = 1e-3f;

static_assert(sizeof(std::array<int, 3>) == 3 * sizeof(int), "triangles are handed to Bullet");

// One tile: its triangles in double (world frame, for exact intersections) and in float
// (origin-shifted, for Bullet's BVH).
struct Tile {
  TriangleMesh mesh;
  std::vector<btScalar> vertices_bt;
  Eigen::AlignedBox3d bounds;  // world frame, slightly padded
  std::unique_ptr<btTriangleIndexVertexArray> mesh_interface;
  std::unique_ptr<btBvhTriangleMeshShape> shape;
  std::unique_ptr<btCollisionObject> object;
};

btVector3 ToBt(const Vec3& v) {
  return btVector3(static_cast<btScalar>(v.x()), static_cast<btScalar>(v.y()),
                   static_cast<btScalar>(v.z()));
}

// Closest triangle of one tile along the clipped ray o + r d, r in [r0, r1]: Bullet's BVH walk
// proposes the triangles whose (conservatively quantized, padded) boxes the segment touches; each
// is intersected exactly in double against the tile's double mesh. Bullet's own float triangle
// test is not used: it is inclusive by ~1e-4 of the triangle's size at the edges (millimetres on
// a facade), which picks the wrong face near corners.
class ClosestTriangle : public btNodeOverlapCallback {
 public:
  ClosestTriangle(const TriangleMesh& mesh, const Vec3& o, const Vec3& d, double r0, double r1)
      : mesh_(mesh), o_(o), d_(d), r0_(r0 - kWindowSlackM), r1_(r1 + kWindowSlackM) {}

  void processNode(int /*sub_part*/, int triangle_index) override {
    const auto& t = mesh_.triangles[static_cast<std::size_t>(triangle_index)];
    const Vec3& v0 = mesh_.vertices[t[0]];
    const double r = IntersectTriangle(o_, d_, v0, mesh_.vertices[t[1]] - v0,
                                       mesh_.vertices[t[2]] - v0);
    if (r < r0_ || r > r1_ || r <= 0.0 || r >= range) return;
    range = r;
    triangle = triangle_index;
  }

  int triangle = -1;
  double range = std::numeric_limits<double>::infinity();

 private:
  static constexpr double kWindowSlackM = 1e-6;
  const TriangleMesh& mesh_;
  Vec3 o_;
  Vec3 d_;
  double r0_;
  double r1_;
};

struct Candidate {
  double entry;
  double exit;
  int tile;
};

// Per-thread work space of CastStatic.
struct Scratch {
  std::vector<int> seen;           // tiles already considered for this ray
  std::vector<Candidate> pending;  // met by the ray, not walked yet, sorted by entry
};

// Ray / axis-aligned box in double: entry and exit ranges (entry may be negative when the origin
// is inside). False when missed.
bool RayBox(const Eigen::AlignedBox3d& box, const Vec3& o, const Vec3& d, double* entry,
            double* exit) {
  double t0 = -std::numeric_limits<double>::infinity();
  double t1 = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0.0) {
      if (o[i] < box.min()[i] || o[i] > box.max()[i]) return false;
      continue;
    }
    double a = (box.min()[i] - o[i]) / d[i];
    double b = (box.max()[i] - o[i]) / d[i];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  *entry = t0;
  *exit = t1;
  return t0 <= t1;
}

void Validate(const LidarWorldOptions& o) {
  const auto require = [](bool ok, const std::string& field, const std::string& what) {
    if (!ok) throw InputError("lidar world option '" + field + "': " + what);
  };
  require(o.ground_spacing_m > 0.0, "ground_spacing_m", "must be > 0");
  require(o.ground_margin_m >= 0.0, "ground_margin_m", "must be >= 0");
  require(o.ground_tile_size_m >= o.ground_spacing_m, "ground_tile_size_m",
          "must be >= ground_spacing_m");
  require(o.object_tile_size_m > 0.0, "object_tile_size_m", "must be > 0");
  require(o.cylinder_sides >= 3, "cylinder_sides", "must be >= 3");
  require(o.sphere_subdivisions >= 0 && o.sphere_subdivisions <= 4, "sphere_subdivisions",
          "must be in [0, 4]");
}

// Ground-plane bounds of everything that must stand on the terrain.
Eigen::AlignedBox2d Footprint(const RoadGeometry& roads, const WorldLayout& layout) {
  Eigen::AlignedBox2d box;
  for (const LaneShape& lane : roads.lanes) {
    for (const Vec3& p : lane.centre) {
      box.extend(p.head<2>() + Vec2::Constant(lane.width_m));
      box.extend(p.head<2>() - Vec2::Constant(lane.width_m));
    }
  }
  for (const auto& junction : roads.junctions) {
    for (const Vec3& p : junction) box.extend(p.head<2>());
  }
  for (const WorldBox& b : layout.boxes) {
    const Vec2 r = Vec2::Constant(0.5 * b.size_m.head<2>().norm());
    box.extend(b.centre_world.head<2>() + r);
    box.extend(b.centre_world.head<2>() - r);
  }
  for (const WorldCylinder& c : layout.cylinders) {
    box.extend(c.base_world.head<2>() + Vec2::Constant(c.radius_m));
    box.extend(c.base_world.head<2>() - Vec2::Constant(c.radius_m));
  }
  for (const WorldSphere& s : layout.spheres) {
    box.extend(s.centre_world.head<2>() + Vec2::Constant(s.radius_m));
    box.extend(s.centre_world.head<2>() - Vec2::Constant(s.radius_m));
  }
  return box;
}

}  // namespace

struct LidarWorld::Bullet {
  // Declaration order matters: the world is destroyed first, while the objects, the broadphase and
  // the dispatcher it references are still alive.
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  std::vector<std::unique_ptr<Tile>> tiles;
  btCollisionWorld world{&dispatcher, &broadphase, &configuration};
  TileGrid grid;  // tiles by ground-plane cell, for ordered ray traversal
};

LidarWorld::LidarWorld(const RoadGeometry& roads, GroundHeightFn ground, WorldLayout layout,
                       const LidarWorldOptions& options)
    : ground_(std::move(ground)), layout_(std::move(layout)), bullet_(std::make_unique<Bullet>()) {
  Validate(options);
  if (!ground_) throw InputError("lidar world: no ground height function");
  const Eigen::AlignedBox2d footprint = Footprint(roads, layout_);
  if (footprint.isEmpty()) {
    throw InputError("lidar world: no lanes, junctions or objects to size the ground from");
  }
  origin_ = Vec3(0.5 * (footprint.min().x() + footprint.max().x()),
                 0.5 * (footprint.min().y() + footprint.max().y()), 0.0);

  // Terrain and objects are separate tiles: the terrain's bounding boxes stay thin, so rays above
  // the ground skip it, and rays that hit the ground skip the objects behind the hit.
  const TerrainGrid grid =
      SampleTerrain(ground_, footprint, options.ground_spacing_m, options.ground_margin_m);
  const int tile_cells = std::max(
      1, static_cast<int>(std::lround(options.ground_tile_size_m / options.ground_spacing_m)));
  for (TriangleMesh& mesh : TerrainTiles(grid, RoadClearance(roads), tile_cells)) {
    AddTile(std::move(mesh));
  }
  for (TriangleMesh& mesh : ObjectTiles(layout_, options.object_tile_size_m, options)) {
    AddTile(std::move(mesh));
  }
  std::vector<Eigen::AlignedBox3d> tile_bounds;
  for (const auto& tile : bullet_->tiles) tile_bounds.push_back(tile->bounds);
  bullet_->grid = TileGrid(tile_bounds, options.object_tile_size_m);
  bvh_ = std::make_unique<TriangleBvh>(tile_meshes(), origin_);
}

void LidarWorld::AddTile(TriangleMesh mesh) {
  if (mesh.triangles.empty()) return;
  auto tile = std::make_unique<Tile>();
  tile->mesh = std::move(mesh);
  for (const Vec3& v : tile->mesh.vertices) {
    tile->bounds.extend(v);
    const Vec3 shifted = v - origin_;
    tile->vertices_bt.insert(tile->vertices_bt.end(), {static_cast<btScalar>(shifted.x()),
                                                       static_cast<btScalar>(shifted.y()),
                                                       static_cast<btScalar>(shifted.z())});
  }
  bounds_.extend(tile->bounds);
  tile->bounds.min() -= Vec3::Constant(1e-3);
  tile->bounds.max() += Vec3::Constant(1e-3);
  tile->mesh_interface = std::make_unique<btTriangleIndexVertexArray>(
      static_cast<int>(tile->mesh.triangles.size()),
      reinterpret_cast<int*>(tile->mesh.triangles.data()), static_cast<int>(3 * sizeof(int)),
      static_cast<int>(tile->mesh.vertices.size()), tile->vertices_bt.data(),
      static_cast<int>(3 * sizeof(btScalar)));
  // Quantized BVH nodes: 16 bytes, boxes rounded outwards (conservative culling).
  tile->shape = std::make_unique<btBvhTriangleMeshShape>(tile->mesh_interface.get(), true);
  tile->shape->setMargin(0.05f);  // pads the broadphase box only; ray hits are unaffected
  tile->object = std::make_unique<btCollisionObject>();
  tile->object->setCollisionShape(tile->shape.get());
  tile->object->setCollisionFlags(btCollisionObject::CF_STATIC_OBJECT);
  tile->object->setUserIndex(static_cast<int>(bullet_->tiles.size()));
  bullet_->world.addCollisionObject(tile->object.get());
  bullet_->tiles.push_back(std::move(tile));
}

LidarWorld::~LidarWorld() = default;

std::unique_ptr<LidarWorld> LidarWorld::Build(const RoadGeometry& roads, GroundHeightFn ground,
                                              const WorldLayoutOptions& layout_options,
                                              const LidarWorldOptions& options) {
  WorldLayout layout = BuildWorldLayout(roads, ground, layout_options);
  return std::make_unique<LidarWorld>(roads, std::move(ground), std::move(layout), options);
}

std::size_t LidarWorld::triangle_count() const {
  std::size_t n = 0;
  for (const auto& t : bullet_->tiles) n += t->mesh.size();
  return n;
}

std::vector<const TriangleMesh*> LidarWorld::tile_meshes() const {
  std::vector<const TriangleMesh*> meshes;
  for (const auto& tile : bullet_->tiles) meshes.push_back(&tile->mesh);
  return meshes;
}

std::size_t LidarWorld::tile_count() const { return bullet_->tiles.size(); }

btCollisionWorld& LidarWorld::collision_world() { return bullet_->world; }

std::optional<RayHit> LidarWorld::CastStatic(const Vec3& o, const Vec3& d,
                                             double max_range_m) const {
  return bvh_->Cast(o, d, max_range_m);
}

std::optional<RayHit> LidarWorld::CastStaticBullet(const Vec3& o, const Vec3& d,
                                                   double max_range_m) const {
  const double r_begin = 0.0;
  const double r_end = max_range_m;
  thread_local Scratch scratch;
  scratch.seen.clear();
  scratch.pending.clear();
  double best = r_end;
  const Tile* best_tile = nullptr;
  int best_triangle = -1;

  // Walks one tile's BVH over [entry, min(exit, best)]; Bullet proposes the triangles, the exact
  // double test ranges them.
  const btVector3 pad(kWalkPadM, kWalkPadM, kWalkPadM);
  const auto walk = [&](const Candidate& c) {
    const Tile& tile = *bullet_->tiles[c.tile];
    const double end = std::min(c.exit, best);
    ClosestTriangle callback(tile.mesh, o, d, c.entry, end);
    tile.shape->getOptimizedBvh()->reportBoxCastOverlappingNodex(
        &callback, ToBt(o + c.entry * d - origin_), ToBt(o + end * d - origin_), -pad, pad);
    if (callback.triangle >= 0 && callback.range < best) {
      best = callback.range;
      best_tile = &tile;
      best_triangle = callback.triangle;
    }
  };
  // Walks the pending tiles that start before `limit`, nearest first.
  const auto walk_pending_before = [&](double limit) {
    auto& pending = scratch.pending;
    std::size_t n = 0;
    while (n < pending.size() && pending[n].entry < std::min(limit, best)) walk(pending[n++]);
    pending.erase(pending.begin(), pending.begin() + static_cast<long>(n));
  };

  // Cells along the ray in order; a hit before the end of the current cell ends the search (every
  // tile that could hold a closer one is listed in this or an earlier cell).
  bullet_->grid.Walk(o, d, r_begin, r_end, [&](const std::vector<int>& ids, double cell_exit) {
    for (const int id : ids) {
      if (std::find(scratch.seen.begin(), scratch.seen.end(), id) != scratch.seen.end()) continue;
      scratch.seen.push_back(id);
      double entry, exit;
      if (RayBox(bullet_->tiles[id]->bounds, o, d, &entry, &exit) && exit > r_begin &&
          entry < best) {
        const Candidate c{std::max(entry, r_begin), std::min(exit, r_end), id};
        const auto at =
            std::upper_bound(scratch.pending.begin(), scratch.pending.end(), c,
                             [](const Candidate& a, const Candidate& b) {
                               return a.entry < b.entry || (a.entry == b.entry && a.tile < b.tile);
                             });
        scratch.pending.insert(at, c);
      }
    }
    walk_pending_before(cell_exit);
    return best > cell_exit;
  });
  walk_pending_before(std::numeric_limits<double>::infinity());

  if (best_tile == nullptr) return std::nullopt;
  const auto& tri = best_tile->mesh.triangles[static_cast<std::size_t>(best_triangle)];
  const Vec3& v0 = best_tile->mesh.vertices[tri[0]];
  Vec3 n = (best_tile->mesh.vertices[tri[1]] - v0)
               .cross(best_tile->mesh.vertices[tri[2]] - v0)
               .normalized();
  if (n.dot(d) > 0.0) n = -n;
  return RayHit{best, n, best_tile->mesh.materials[static_cast<std::size_t>(best_triangle)]};
}

}  // namespace statebench::sensors
