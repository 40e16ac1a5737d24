#include "estimator/voxel_hash_map.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace statebench::est {

VoxelHashMap::VoxelHashMap(const VoxelHashMapOptions& options)
    : options_(options),
      capacity_(static_cast<std::size_t>(std::max(0, options.max_points_per_voxel))) {}

VoxelKey VoxelHashMap::VoxelOf(const Vec3& p) const {
  // Clamped into the int range (a far or non-finite point lands in an edge voxel; the cast of an
  // out-of-range double is undefined).
  const Vec3 s = (p / options_.voxel_size_m).cwiseMax(-1e9).cwiseMin(1e9);
  return {static_cast<int>(std::floor(s.x())), static_cast<int>(std::floor(s.y())),
          static_cast<int>(std::floor(s.z()))};
}

void VoxelHashMap::AddPoints(const std::vector<Vec3>& points_world) {
  for (const Vec3& p : points_world) {
    const VoxelKey key = VoxelOf(p);
    const auto next = static_cast<std::uint32_t>(keys_.size());
    const std::uint32_t i = index_.Insert(key, next);
    if (i == next) {
      keys_.push_back(key);
      counts_.push_back(0);
      points_.resize(keys_.size() * capacity_);
    }
    std::uint32_t& count = counts_[i];
    if (count < capacity_) points_[i * capacity_ + count++] = p;
  }
}

void VoxelHashMap::Update(const std::vector<Vec3>& points_lidar, const SE3& T_world_lidar) {
  std::vector<Vec3> points_world;
  points_world.reserve(points_lidar.size());
  for (const Vec3& p : points_lidar) points_world.push_back(T_world_lidar * p);
  AddPoints(points_world);
  RemoveVoxelsFarFrom(T_world_lidar.translation());
}

void VoxelHashMap::RemoveVoxel(std::uint32_t i) {
  index_.Erase(keys_[i]);
  const auto last = static_cast<std::uint32_t>(keys_.size() - 1);
  if (i != last) {
    keys_[i] = keys_[last];
    counts_[i] = counts_[last];
    std::copy_n(points_.begin() + last * capacity_, counts_[last], points_.begin() + i * capacity_);
    index_.Assign(keys_[i], i);
  }
  keys_.pop_back();
  counts_.pop_back();
  points_.resize(keys_.size() * capacity_);
}

void VoxelHashMap::RemoveVoxelsFarFrom(const Vec3& origin_world) {
  const double max_range2 = options_.max_range_m * options_.max_range_m;
  for (std::uint32_t i = 0; i < keys_.size();) {
    if (counts_[i] == 0 || (VoxelPoints(i)[0] - origin_world).squaredNorm() > max_range2) {
      RemoveVoxel(i);  // the last voxel moves to i: look at i again
    } else {
      ++i;
    }
  }
}

void VoxelHashMap::Clear() {
  index_.Clear();
  keys_.clear();
  counts_.clear();
  points_.clear();
}

bool VoxelHashMap::NearestNeighbor(const Vec3& query_world, Vec3* nearest_world, double* distance_m,
                                   NearestNeighborProof* proof) const {
  const VoxelKey center = VoxelOf(query_world);
  // Offset of the query inside its voxel, in [0, v) per axis: a neighbour voxel at offset
  // d in {-1, 0, 1} is at least (v - s) (d = 1), s (d = -1) or 0 (d = 0) away along that axis.
  // Voxels that cannot beat the best distance so far are skipped before the lookup; the
  // query's own voxel is searched first to make that bound tight early.
  const double v = options_.voxel_size_m;
  const Vec3 s = query_world - Eigen::Vector3i(center.x, center.y, center.z).cast<double>() * v;
  auto gap2 = [&](int axis, int d) {
    const double g = d > 0 ? v - s(axis) : (d < 0 ? s(axis) : 0.0);
    return g * g;
  };
  static constexpr int kOrder[3] = {0, -1, 1};
  const VoxelBrickIndex::Window window(index_, {center.x - 1, center.y - 1, center.z - 1},
                                       {center.x + 1, center.y + 1, center.z + 1});
  double best2 = std::numeric_limits<double>::infinity();
  const Vec3* best = nullptr;
  // A lower bound of the squared distance of every point but the best: the points seen and
  // displaced or beaten, and the gap bound of the voxels skipped.
  double others2 = std::numeric_limits<double>::infinity();
  for (const int dx : kOrder) {
    const double gx = gap2(0, dx);
    if (gx >= best2) {
      others2 = std::min(others2, gx);
      continue;
    }
    for (const int dy : kOrder) {
      const double gxy = gx + gap2(1, dy);
      if (gxy >= best2) {
        others2 = std::min(others2, gxy);
        continue;
      }
      for (const int dz : kOrder) {
        const double g = gxy + gap2(2, dz);
        if (g >= best2) {
          others2 = std::min(others2, g);
          continue;
        }
        const std::uint32_t i = window.Find({center.x + dx, center.y + dy, center.z + dz});
        if (i == VoxelBrickIndex::kNone) continue;
        // Without branches: which point wins is data, not a prediction the CPU can learn.
        const Vec3* points = VoxelPoints(i);
        for (std::uint32_t k = 0; k < counts_[i]; ++k) {
          const double d2 = (points[k] - query_world).squaredNorm();
          const bool closer = d2 < best2;
          others2 = std::min(others2, closer ? best2 : d2);
          best2 = closer ? d2 : best2;
          best = closer ? points + k : best;
        }
      }
    }
  }
  if (!std::isfinite(best2)) {
    if (proof != nullptr) proof->valid = false;
    return false;
  }
  *nearest_world = *best;
  *distance_m = std::sqrt(best2);
  if (proof != nullptr) {
    *proof = {.valid = true,
              .query_world = query_world,
              .center = center,
              .nearest_world = *best,
              .distance_m = *distance_m,
              .others_m = std::sqrt(others2)};
  }
  return true;
}

bool VoxelHashMap::NearestNeighborFromProof(const NearestNeighborProof& proof,
                                            const Vec3& query_world, Vec3* nearest_world,
                                            double* distance_m) const {
  if (!proof.valid) return false;
  // The margin dwarfs the rounding of the distances (relative 1e-15) at any coordinate.
  const double moved = (query_world - proof.query_world).norm();
  const double margin = 1e-9 * (1.0 + query_world.cwiseAbs().maxCoeff());
  if (!(proof.distance_m + 2.0 * moved + margin < proof.others_m)) return false;
  if (!(VoxelOf(query_world) == proof.center)) return false;
  *nearest_world = proof.nearest_world;
  // As the search computes it (same expression, same bits).
  *distance_m = std::sqrt((proof.nearest_world - query_world).squaredNorm());
  return true;
}

void VoxelHashMap::NeighborsWithin(const Vec3& query_world, double radius_m,
                                   std::vector<Vec3>* out) const {
  const VoxelKey center = VoxelOf(query_world);
  const double r2 = radius_m * radius_m;
  const double v = options_.voxel_size_m;
  const int reach = std::max(1, static_cast<int>(std::ceil(radius_m / v)));
  // Voxels entirely outside the ball are skipped before the hash lookup: along each axis a voxel
  // at offset d is at least gap(d) = max(0, d v - s) (d > 0) or max(0, s - (d + 1) v) (d < 0)
  // from the query, s its offset inside its own voxel. The ball is widened by a margin far
  // above the rounding of s (relative 1e-9 of the coordinates), so no voxel holding a point
  // within the radius is ever skipped and the output is that of the full cube scan.
  const Vec3 s = query_world - Eigen::Vector3i(center.x, center.y, center.z).cast<double>() * v;
  const double margin = 1e-9 * (1.0 + query_world.cwiseAbs().maxCoeff());
  const double limit2 = (radius_m + margin) * (radius_m + margin);
  auto gap2 = [&](int axis, int d) {
    const double g = d > 0 ? d * v - s(axis) : (d < 0 ? s(axis) - (d + 1) * v : 0.0);
    return g > 0.0 ? g * g : 0.0;
  };
  const VoxelBrickIndex::Window window(index_,
                                       {center.x - reach, center.y - reach, center.z - reach},
                                       {center.x + reach, center.y + reach, center.z + reach});
  std::size_t found = 0;
  for (int dx = -reach; dx <= reach; ++dx) {
    const double gx = gap2(0, dx);
    if (gx > limit2) continue;
    for (int dy = -reach; dy <= reach; ++dy) {
      const double gxy = gx + gap2(1, dy);
      if (gxy > limit2) continue;
      // The column's occupied voxels only, in increasing dz, a window's column at a time.
      for (int dz0 = -reach; dz0 <= reach; dz0 += VoxelBrickIndex::Window::kMaxColumn) {
        const int dz1 = std::min(reach, dz0 + VoxelBrickIndex::Window::kMaxColumn - 1);
        for (std::uint32_t occupied =
                 window.Column(center.x + dx, center.y + dy, center.z + dz0, center.z + dz1);
             occupied != 0; occupied &= occupied - 1) {
          const int dz = dz0 + std::countr_zero(occupied);
          if (gxy + gap2(2, dz) > limit2) continue;
          const std::uint32_t i = window.Find({center.x + dx, center.y + dy, center.z + dz});
          // Every point is written and the count advanced only for those within the radius:
          // no branch to mispredict on the roughly even split.
          const Vec3* points = VoxelPoints(i);
          const std::uint32_t count = counts_[i];
          if (out->size() < found + count) out->resize(std::max(2 * out->size(), found + count));
          Vec3* dst = out->data();
          for (std::uint32_t k = 0; k < count; ++k) {
            dst[found] = points[k];
            found += (points[k] - query_world).squaredNorm() <= r2 ? 1 : 0;
          }
        }
      }
    }
  }
  out->resize(found);
}

std::vector<Vec3> VoxelHashMap::Points() const {
  std::vector<Vec3> points;
  for (std::uint32_t i = 0; i < keys_.size(); ++i) {
    points.insert(points.end(), VoxelPoints(i), VoxelPoints(i) + counts_[i]);
  }
  return points;
}

}  // namespace statebench::est
