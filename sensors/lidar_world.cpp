#include "sensors/lidar_world.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <btBulletCollisionCommon.h>
#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/NarrowPhaseCollision/btRaycastCallback.h>

#include "core/error.hpp"
#include "sensors/road_clearance.hpp"
#include "sensors/world_mesh.hpp"

namespace statebench::sensors {
namespace {

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

// Closest triangle along a segment; processTriangle only reports hits closer than the current
// m_hitFraction, so the last report is the closest.
class ClosestTriangle : public btTriangleRaycastCallback {
 public:
  ClosestTriangle(const btVector3& from, const btVector3& to)
      : btTriangleRaycastCallback(from, to, 0) {}
  btScalar reportHit(const btVector3& /*normal*/, btScalar fraction, int /*part*/,
                     int triangle_index) override {
    triangle = triangle_index;
    return fraction;
  }
  int triangle = -1;
};

struct Candidate {
  double entry;
  double exit;
  int tile;
};

struct Scratch {
  btAlignedObjectArray<const btDbvtNode*> stack;
  std::vector<Candidate> candidates;
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

btVector3 ToBt(const Vec3& v) {
  return btVector3(static_cast<btScalar>(v.x()), static_cast<btScalar>(v.y()),
                   static_cast<btScalar>(v.z()));
}

void Validate(const LidarWorldOptions& o) {
  const auto require = [](bool ok, const std::string& field, const std::string& what) {
    if (!ok) throw InputError("lidar world option '" + field + "': " + what);
  };
  require(o.ground_spacing_m > 0.0, "ground_spacing_m", "must be > 0");
  require(o.ground_margin_m >= 0.0, "ground_margin_m", "must be >= 0");
  require(o.tile_size_m >= o.ground_spacing_m, "tile_size_m", "must be >= ground_spacing_m");
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

  // Terrain grid nodes (x0 + i s, y0 + j s), i in [0, nx], j in [0, ny].
  const double s = options.ground_spacing_m;
  const double x0 = std::floor((footprint.min().x() - options.ground_margin_m) / s) * s;
  const double y0 = std::floor((footprint.min().y() - options.ground_margin_m) / s) * s;
  const int nx = static_cast<int>(std::ceil((footprint.max().x() + options.ground_margin_m - x0) / s));
  const int ny = static_cast<int>(std::ceil((footprint.max().y() + options.ground_margin_m - y0) / s));
  std::vector<double> heights(static_cast<std::size_t>(nx + 1) * (ny + 1));
  const auto node = [&](int i, int j) {
    return Vec3(x0 + i * s, y0 + j * s, heights[static_cast<std::size_t>(j) * (nx + 1) + i]);
  };
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      heights[static_cast<std::size_t>(j) * (nx + 1) + i] = ground_(x0 + i * s, y0 + j * s);
    }
  }

  const int tile_cells = std::max(1, static_cast<int>(std::lround(options.tile_size_m / s)));
  const int tiles_x = (nx + tile_cells - 1) / tile_cells;
  const int tiles_y = (ny + tile_cells - 1) / tile_cells;
  std::vector<TriangleMesh> meshes(static_cast<std::size_t>(tiles_x) * tiles_y);
  const auto tile_of = [&](const Vec3& p) {
    const int tx = std::clamp(static_cast<int>(std::floor((p.x() - x0) / (s * tile_cells))), 0,
                              tiles_x - 1);
    const int ty = std::clamp(static_cast<int>(std::floor((p.y() - y0) / (s * tile_cells))), 0,
                              tiles_y - 1);
    return static_cast<std::size_t>(ty) * tiles_x + tx;
  };

  // Terrain: each tile its own sub-grid of nodes; triangles on a lane or junction are road.
  const RoadClearance clearance(roads);
  for (int ty = 0; ty < tiles_y; ++ty) {
    for (int tx = 0; tx < tiles_x; ++tx) {
      TriangleMesh& mesh = meshes[static_cast<std::size_t>(ty) * tiles_x + tx];
      const int i0 = tx * tile_cells, i1 = std::min(nx, i0 + tile_cells);
      const int j0 = ty * tile_cells, j1 = std::min(ny, j0 + tile_cells);
      const int w = i1 - i0 + 1;
      for (int j = j0; j <= j1; ++j) {
        for (int i = i0; i <= i1; ++i) mesh.AddVertex(node(i, j));
      }
      for (int j = 0; j < j1 - j0; ++j) {
        for (int i = 0; i < i1 - i0; ++i) {
          const int a = j * w + i, b = a + 1, c = a + w + 1, d = a + w;
          for (const std::array<int, 3> t : {std::array<int, 3>{a, b, c}, {a, c, d}}) {
            const Vec3 centroid =
                (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.0;
            mesh.AddTriangle(t[0], t[1], t[2],
                             clearance.OnRoad(centroid.head<2>()) ? SurfaceMaterial::kRoad
                                                                  : SurfaceMaterial::kGround);
          }
        }
      }
    }
  }
  for (const WorldBox& b : layout_.boxes) meshes[tile_of(b.centre_world)].AddBox(b);
  for (const WorldCylinder& c : layout_.cylinders) {
    meshes[tile_of(c.base_world)].AddCylinder(c, options.cylinder_sides);
  }
  for (const WorldSphere& sp : layout_.spheres) {
    meshes[tile_of(sp.centre_world)].AddSphere(sp, options.sphere_subdivisions);
  }

  origin_ = Vec3(0.5 * (footprint.min().x() + footprint.max().x()),
                 0.5 * (footprint.min().y() + footprint.max().y()), 0.0);
  for (TriangleMesh& mesh : meshes) {
    auto tile = std::make_unique<Tile>();
    tile->mesh = std::move(mesh);
    for (const Vec3& v : tile->mesh.vertices) {
      tile->bounds.extend(v);
      const Vec3 shifted = v - origin_;
      tile->vertices_bt.insert(tile->vertices_bt.end(),
                               {static_cast<btScalar>(shifted.x()),
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
    tile->shape = std::make_unique<btBvhTriangleMeshShape>(tile->mesh_interface.get(), true);
    tile->shape->setMargin(0.05f);  // pads the broadphase box only; ray hits are unaffected
    tile->object = std::make_unique<btCollisionObject>();
    tile->object->setCollisionShape(tile->shape.get());
    tile->object->setCollisionFlags(btCollisionObject::CF_STATIC_OBJECT);
    tile->object->setUserIndex(static_cast<int>(bullet_->tiles.size()));
    bullet_->world.addCollisionObject(tile->object.get());
    bullet_->tiles.push_back(std::move(tile));
  }
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

std::size_t LidarWorld::tile_count() const { return bullet_->tiles.size(); }

btCollisionWorld& LidarWorld::collision_world() { return bullet_->world; }

std::optional<RayHit> LidarWorld::CastStatic(const Vec3& origin_world,
                                             const Vec3& unit_direction_world,
                                             double max_range_m) const {
  thread_local Scratch scratch;
  const Vec3& o = origin_world;
  const Vec3& d = unit_direction_world;

  // 1. Tiles whose broadphase boxes the ray crosses, with entry/exit ranges in double.
  struct Collector : btDbvt::ICollide {
    Collector(const std::vector<std::unique_ptr<Tile>>& t, const Vec3& o, const Vec3& d,
              double max_range, std::vector<Candidate>* out)
        : tiles(t), origin(o), direction(d), max_range_m(max_range), candidates(out) {}
    void Process(const btDbvtNode* leaf) override {
      const auto* proxy = static_cast<const btBroadphaseProxy*>(leaf->data);
      const auto* object = static_cast<const btCollisionObject*>(proxy->m_clientObject);
      const int id = object->getUserIndex();
      double entry, exit;
      if (RayBox(tiles[id]->bounds, origin, direction, &entry, &exit) && exit > 0.0 &&
          entry < max_range_m) {
        candidates->push_back({std::max(entry, 0.0), std::min(exit, max_range_m), id});
      }
    }
    const std::vector<std::unique_ptr<Tile>>& tiles;
    const Vec3& origin;
    const Vec3& direction;
    double max_range_m;
    std::vector<Candidate>* candidates;
  };
  scratch.candidates.clear();
  Collector collector(bullet_->tiles, o, d, max_range_m, &scratch.candidates);
  const btVector3 from = ToBt(o - origin_);
  const btVector3 to = ToBt(o - origin_ + max_range_m * d);
  const btVector3 dir = ToBt(d);
  btVector3 inv;
  unsigned int signs[3];
  for (int i = 0; i < 3; ++i) {
    inv[i] = dir[i] == btScalar(0) ? btScalar(BT_LARGE_FLOAT) : btScalar(1) / dir[i];
    signs[i] = inv[i] < 0 ? 1u : 0u;
  }
  for (const btDbvt& set : bullet_->broadphase.m_sets) {
    if (set.m_root == nullptr) continue;
    set.rayTestInternal(set.m_root, from, to, inv, signs, static_cast<btScalar>(max_range_m),
                        btVector3(0, 0, 0), btVector3(0, 0, 0), scratch.stack, collector);
  }
  std::sort(scratch.candidates.begin(), scratch.candidates.end(),
            [](const Candidate& a, const Candidate& b) {
              return a.entry < b.entry || (a.entry == b.entry && a.tile < b.tile);
            });

  // 2. Nearest tile first; stop once the next tile starts beyond the best hit.
  double best = max_range_m;
  const Tile* best_tile = nullptr;
  int best_triangle = -1;
  for (const Candidate& c : scratch.candidates) {
    if (c.entry >= best) break;
    const double t0 = c.entry;
    const double t1 = std::min(c.exit, best);
    Tile& tile = *bullet_->tiles[c.tile];
    ClosestTriangle callback(ToBt(o + t0 * d - origin_), ToBt(o + t1 * d - origin_));
    tile.shape->performRaycast(&callback, callback.m_from, callback.m_to);
    if (callback.triangle < 0) continue;
    // 3. Exact range to the triangle's plane in double.
    const auto& tri = tile.mesh.triangles[static_cast<std::size_t>(callback.triangle)];
    const Vec3& v0 = tile.mesh.vertices[tri[0]];
    const Vec3 n = (tile.mesh.vertices[tri[1]] - v0).cross(tile.mesh.vertices[tri[2]] - v0);
    const double denom = n.dot(d);
    double range = t0 + static_cast<double>(callback.m_hitFraction) * (t1 - t0);
    if (std::abs(denom) > 1e-12 * n.norm()) range = n.dot(v0 - o) / denom;
    if (range > 0.0 && range < best) {
      best = range;
      best_tile = &tile;
      best_triangle = callback.triangle;
    }
  }
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
