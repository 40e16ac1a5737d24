#include "sensors/world_layout.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <unordered_map>

#include "core/error.hpp"
#include "core/random.hpp"
#include "sensors/geometry2d.hpp"
#include "sensors/road_boundary.hpp"
#include "sensors/road_clearance.hpp"

namespace statebench::sensors {
namespace {

constexpr double kBuildingEmbedM = 1.0;  // buildings reach below the lowest ground corner
constexpr double kSmallEmbedM = 0.3;     // kerbs, poles, trunks
constexpr double kObjectGapM = 0.3;      // minimum distance between placed objects

// Footprints of the objects placed so far, bucketed on a grid.
class FootprintIndex {
 public:
  bool Overlaps(const std::vector<Vec2>& polygon, double gap_m) const {
    Vec2 min, max;
    geometry2d::PolygonBounds(polygon, &min, &max);
    std::vector<int> seen;
    ForCells(min - Vec2::Constant(gap_m), max + Vec2::Constant(gap_m), [&](std::int64_t key) {
      const auto it = cells_.find(key);
      if (it != cells_.end()) seen.insert(seen.end(), it->second.begin(), it->second.end());
    });
    std::sort(seen.begin(), seen.end());
    seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
    return std::any_of(seen.begin(), seen.end(), [&](int i) {
      return geometry2d::PolygonPolygonDistance(polygon, polygons_[i]) < gap_m;
    });
  }

  void Add(std::vector<Vec2> polygon) {
    Vec2 min, max;
    geometry2d::PolygonBounds(polygon, &min, &max);
    const int id = static_cast<int>(polygons_.size());
    ForCells(min, max, [&](std::int64_t key) { cells_[key].push_back(id); });
    polygons_.push_back(std::move(polygon));
  }

 private:
  static constexpr double kCellM = 20.0;

  template <typename F>
  static void ForCells(const Vec2& min, const Vec2& max, F&& f) {
    for (auto ix = static_cast<std::int64_t>(std::floor(min.x() / kCellM));
         ix <= static_cast<std::int64_t>(std::floor(max.x() / kCellM)); ++ix) {
      for (auto iy = static_cast<std::int64_t>(std::floor(min.y() / kCellM));
           iy <= static_cast<std::int64_t>(std::floor(max.y() / kCellM)); ++iy) {
        f((ix << 32) ^ (iy & 0xffffffff));
      }
    }
  }

  std::vector<std::vector<Vec2>> polygons_;
  std::unordered_map<std::int64_t, std::vector<int>> cells_;
};

// Straight stand-in for the boundary between arc lengths s0 and s1 of a run.
struct Chord {
  Vec2 start;
  Vec2 end;
  Vec2 outward;  // unit, perpendicular to the chord, away from the road
  double Heading() const { return std::atan2(end.y() - start.y(), end.x() - start.x()); }
  double Length() const { return (end - start).norm(); }
  Vec2 Mid() const { return 0.5 * (start + end); }
};

Chord RunChord(const BoundaryRun& run, double s0, double s1) {
  const BoundarySample& a = run.At(s0);
  const BoundarySample& b = run.At(s1);
  Chord c;
  c.start = run.PointAt(s0);
  c.end = run.PointAt(s1);
  const Vec2 along = (c.end - c.start).normalized();
  c.outward = Vec2(-along.y(), along.x());
  if (c.outward.dot(a.outward + b.outward) < 0.0) c.outward = -c.outward;
  return c;
}

// Lowest and highest ground under a polygon (vertices and centroid).
void GroundRange(const GroundHeightFn& ground, const std::vector<Vec2>& polygon, double* z_min,
                 double* z_max) {
  Vec2 centroid = Vec2::Zero();
  *z_min = std::numeric_limits<double>::infinity();
  *z_max = -*z_min;
  for (const Vec2& v : polygon) {
    const double z = ground(v.x(), v.y());
    *z_min = std::min(*z_min, z);
    *z_max = std::max(*z_max, z);
    centroid += v / static_cast<double>(polygon.size());
  }
  const double z = ground(centroid.x(), centroid.y());
  *z_min = std::min(*z_min, z);
  *z_max = std::max(*z_max, z);
}

// Upright box over a footprint from z_bottom to z_top.
WorldBox BoxOn(const Vec2& centre, double heading, double length, double width, double z_bottom,
               double z_top, SurfaceMaterial material) {
  WorldBox box;
  box.centre_world = Vec3(centre.x(), centre.y(), 0.5 * (z_bottom + z_top));
  box.yaw_rad = heading;
  box.size_m = Vec3(length, width, z_top - z_bottom);
  box.material = material;
  return box;
}

class Placer {
 public:
  Placer(const RoadClearance& roads, const GroundHeightFn& ground, std::uint64_t seed,
         WorldLayout* out)
      : roads_(roads), ground_(ground), rng_(MakeRng(seed, "world")), out_(out) {}

  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform01(rng_); }

  void Kerbs(const BoundaryRun& run, const KerbOptions& o) {
    const double length = run.Length();
    for (double s = 0.0; s < length - 1e-9; s += o.piece_length_m) {
      const Chord c = RunChord(run, s, std::min(length, s + o.piece_length_m));
      const Vec2 centre = c.Mid() + (o.gap_to_lane_m + 0.5 * o.width_m) * c.outward;
      const auto footprint =
          geometry2d::OrientedRectangle(centre, c.Heading(), 0.5 * c.Length(), 0.5 * o.width_m);
      if (!roads_.PolygonClear(footprint, 0.5 * o.gap_to_lane_m)) continue;
      const double z = ground_(centre.x(), centre.y());
      out_->boxes.push_back(BoxOn(centre, c.Heading(), c.Length(), o.width_m, z - kSmallEmbedM,
                                  z + o.height_m, SurfaceMaterial::kKerb));
    }
  }

  void Buildings(const BoundaryRun& run, const BuildingOptions& o) {
    const double length = run.Length();
    double s = Uniform(0.0, o.gap_max_m);
    while (true) {
      const double facade = Uniform(o.facade_min_m, o.facade_max_m);
      const double setback = Uniform(o.setback_min_m, o.setback_max_m);
      const double depth = Uniform(o.depth_min_m, o.depth_max_m);
      const double height = Uniform(o.height_min_m, o.height_max_m);
      const bool wanted = Uniform01(rng_) < o.probability;
      const double gap = Uniform(o.gap_min_m, o.gap_max_m);
      if (s + facade > length) break;
      if (wanted) {
        const Chord c = RunChord(run, s, s + facade);
        const Vec2 centre = c.Mid() + (setback + 0.5 * depth) * c.outward;
        auto footprint =
            geometry2d::OrientedRectangle(centre, c.Heading(), 0.5 * c.Length(), 0.5 * depth);
        if (roads_.PolygonClear(footprint, o.road_clearance_m) &&
            !placed_.Overlaps(footprint, kObjectGapM)) {
          double z_min, z_max;
          GroundRange(ground_, footprint, &z_min, &z_max);
          out_->boxes.push_back(BoxOn(centre, c.Heading(), c.Length(), depth,
                                      z_min - kBuildingEmbedM, z_max + height,
                                      SurfaceMaterial::kBuilding));
          placed_.Add(std::move(footprint));
        }
      }
      s += facade + gap;
    }
  }

  void ParkedCars(const BoundaryRun& run, const ParkedCarOptions& o) {
    const double length = run.Length();
    double s = Uniform(0.0, o.gap_max_m);
    while (s + o.length_m <= length) {
      const bool wanted = Uniform01(rng_) < o.probability;
      const double gap = Uniform(o.gap_min_m, o.gap_max_m);
      if (wanted) {
        const Chord c = RunChord(run, s, s + o.length_m);
        const Vec2 centre = c.Mid() + (o.offset_m + 0.5 * o.width_m) * c.outward;
        auto footprint =
            geometry2d::OrientedRectangle(centre, c.Heading(), 0.5 * o.length_m, 0.5 * o.width_m);
        if (TryReserve(footprint, 0.3)) {
          double z_min, z_max;
          GroundRange(ground_, footprint, &z_min, &z_max);
          out_->boxes.push_back(BoxOn(centre, c.Heading(), o.length_m, o.width_m, z_min,
                                      z_min + o.height_m, SurfaceMaterial::kParkedCar));
        }
      }
      s += o.length_m + gap;
    }
  }

  void Poles(const BoundaryRun& run, const PoleOptions& o) {
    const double length = run.Length();
    for (double s = Uniform(0.0, o.spacing_m); s < length; s += Uniform(0.8, 1.2) * o.spacing_m) {
      const double height = Uniform(o.height_min_m, o.height_max_m);
      const BoundarySample& b = run.At(s);
      const Vec2 axis = b.p_edge + o.offset_m * b.outward;
      const double heading = std::atan2(b.tangent.y(), b.tangent.x());
      if (!TryReserve(geometry2d::OrientedRectangle(axis, heading, o.radius_m, o.radius_m), 0.3)) {
        continue;
      }
      const double z = ground_(axis.x(), axis.y());
      out_->cylinders.push_back({Vec3(axis.x(), axis.y(), z - kSmallEmbedM), o.radius_m,
                                 height + kSmallEmbedM, SurfaceMaterial::kPole});
    }
  }

  void Trees(const BoundaryRun& run, const TreeOptions& o) {
    const double length = run.Length();
    for (double s = Uniform(0.0, o.spacing_m); s < length; s += Uniform(0.7, 1.3) * o.spacing_m) {
      const bool wanted = Uniform01(rng_) < o.probability;
      const double offset = Uniform(o.offset_min_m, o.offset_max_m);
      const double trunk_height = Uniform(o.trunk_height_min_m, o.trunk_height_max_m);
      const double crown = Uniform(o.crown_radius_min_m, o.crown_radius_max_m);
      if (!wanted) continue;
      const BoundarySample& b = run.At(s);
      const Vec2 axis = b.p_edge + offset * b.outward;
      const double heading = std::atan2(b.tangent.y(), b.tangent.x());
      if (!TryReserve(geometry2d::OrientedRectangle(axis, heading, crown, crown), 0.2)) continue;
      const double z = ground_(axis.x(), axis.y());
      out_->cylinders.push_back({Vec3(axis.x(), axis.y(), z - kSmallEmbedM), o.trunk_radius_m,
                                 trunk_height + kSmallEmbedM, SurfaceMaterial::kTreeTrunk});
      out_->spheres.push_back({Vec3(axis.x(), axis.y(), z + trunk_height + 0.7 * crown), crown,
                               SurfaceMaterial::kTreeCrown});
    }
  }

 private:
  bool TryReserve(std::vector<Vec2> footprint, double road_clearance_m) {
    if (!roads_.PolygonClear(footprint, road_clearance_m) ||
        placed_.Overlaps(footprint, kObjectGapM)) {
      return false;
    }
    placed_.Add(std::move(footprint));
    return true;
  }

  const RoadClearance& roads_;
  const GroundHeightFn& ground_;
  std::mt19937_64 rng_;
  FootprintIndex placed_;
  WorldLayout* out_;
};

void Require(bool ok, const std::string& field, const std::string& what) {
  if (!ok) throw InputError("world layout option '" + field + "': " + what);
}

void RequireRange(double lo, double hi, const std::string& field) {
  Require(std::isfinite(lo) && std::isfinite(hi) && lo >= 0.0 && lo <= hi, field,
          "needs 0 <= min <= max (got " + std::to_string(lo) + ", " + std::to_string(hi) + ")");
}

void Validate(const WorldLayoutOptions& o) {
  Require(o.boundary_step_m > 0.0, "boundary_step_m", "must be > 0");
  if (o.kerbs.enabled) {
    Require(o.kerbs.height_m > 0.0 && o.kerbs.width_m > 0.0 && o.kerbs.piece_length_m > 0.0,
            "kerbs", "height, width and piece length must be > 0");
  }
  const BuildingOptions& b = o.buildings;
  if (b.enabled) {
    RequireRange(b.setback_min_m, b.setback_max_m, "buildings.setback");
    RequireRange(b.facade_min_m, b.facade_max_m, "buildings.facade");
    RequireRange(b.depth_min_m, b.depth_max_m, "buildings.depth");
    RequireRange(b.height_min_m, b.height_max_m, "buildings.height");
    RequireRange(b.gap_min_m, b.gap_max_m, "buildings.gap");
    Require(b.facade_min_m > 0.0 && b.depth_min_m > 0.0 && b.height_min_m > 0.0, "buildings",
            "facade, depth and height minima must be > 0");
    Require(b.probability >= 0.0 && b.probability <= 1.0, "buildings.probability", "in [0, 1]");
  }
  if (o.poles.spacing_m > 0.0) {
    RequireRange(o.poles.height_min_m, o.poles.height_max_m, "poles.height");
    Require(o.poles.radius_m > 0.0, "poles.radius_m", "must be > 0");
  }
  if (o.trees.spacing_m > 0.0) {
    RequireRange(o.trees.offset_min_m, o.trees.offset_max_m, "trees.offset");
    RequireRange(o.trees.trunk_height_min_m, o.trees.trunk_height_max_m, "trees.trunk_height");
    RequireRange(o.trees.crown_radius_min_m, o.trees.crown_radius_max_m, "trees.crown_radius");
    Require(o.trees.trunk_radius_m > 0.0, "trees.trunk_radius_m", "must be > 0");
  }
  if (o.parked_cars.probability > 0.0) {
    RequireRange(o.parked_cars.gap_min_m, o.parked_cars.gap_max_m, "parked_cars.gap");
    Require(
        o.parked_cars.length_m > 0.0 && o.parked_cars.width_m > 0.0 && o.parked_cars.height_m > 0.0,
        "parked_cars", "length, width and height must be > 0");
  }
}

}  // namespace

WorldLayout BuildWorldLayout(const RoadGeometry& roads, const GroundHeightFn& ground,
                             const WorldLayoutOptions& options) {
  Validate(options);
  WorldLayout layout;
  const RoadClearance clearance(roads);
  const std::vector<BoundaryRun> runs =
      FindOuterBoundaries(roads, clearance, options.boundary_step_m, 0.3, 2.0);

  Placer placer(clearance, ground, options.seed, &layout);
  if (options.kerbs.enabled) {
    for (const BoundaryRun& run : runs) placer.Kerbs(run, options.kerbs);
  }
  if (options.buildings.enabled) {
    for (const BoundaryRun& run : runs) placer.Buildings(run, options.buildings);
  }
  if (options.parked_cars.probability > 0.0) {
    for (const BoundaryRun& run : runs) placer.ParkedCars(run, options.parked_cars);
  }
  if (options.poles.spacing_m > 0.0) {
    for (const BoundaryRun& run : runs) placer.Poles(run, options.poles);
  }
  if (options.trees.spacing_m > 0.0) {
    for (const BoundaryRun& run : runs) placer.Trees(run, options.trees);
  }
  layout.boxes.insert(layout.boxes.end(), options.extra_boxes.begin(), options.extra_boxes.end());
  return layout;
}

}  // namespace statebench::sensors
