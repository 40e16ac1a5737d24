// Analytic lidar scenes for the odometry tests: a ground plane, axis-aligned boxes (walls,
// buildings) and vertical poles, scanned by a 32-beam spinning lidar (elevations -16..+15 deg,
// like an XT32) with exact ray intersections. The sensor may move during the sweep: the column
// fired at time t sees the scene from T_world_lidar(t), and its points are reported in that
// frame with their time offset, as a real motion-distorted scan.
#pragma once

#include <cmath>
#include <functional>
#include <limits>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/measurements.hpp"
#include "core/random.hpp"
#include "core/se3.hpp"

namespace statebench::est::testing {

struct Box {
  Vec3 min, max;
};
struct Pole {
  double x, y, radius, height;
};

struct Scene {
  bool ground = true;  // z = 0
  std::vector<Box> boxes;
  std::vector<Pole> poles;

  // Distance along the unit ray (origin o, direction d) to the first surface, or +inf.
  double Cast(const Vec3& o, const Vec3& d) const {
    double best = std::numeric_limits<double>::infinity();
    if (ground && d.z() < -1e-9) {
      const double t = -o.z() / d.z();
      if (t > 0) best = std::min(best, t);
    }
    for (const Box& b : boxes) {
      double t0 = 0.0, t1 = best;
      bool hit = true;
      for (int i = 0; i < 3 && hit; ++i) {
        if (std::abs(d[i]) < 1e-12) {
          if (o[i] < b.min[i] || o[i] > b.max[i]) hit = false;
          continue;
        }
        double ta = (b.min[i] - o[i]) / d[i], tb = (b.max[i] - o[i]) / d[i];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
        if (t0 > t1) hit = false;
      }
      if (hit && t0 > 0) best = std::min(best, t0);
    }
    for (const Pole& p : poles) {
      // |o_xy + t d_xy - c|^2 = r^2
      const double ox = o.x() - p.x, oy = o.y() - p.y;
      const double a = d.x() * d.x() + d.y() * d.y();
      if (a < 1e-12) continue;
      const double b = 2 * (ox * d.x() + oy * d.y());
      const double c = ox * ox + oy * oy - p.radius * p.radius;
      const double disc = b * b - 4 * a * c;
      if (disc < 0) continue;
      const double t = (-b - std::sqrt(disc)) / (2 * a);
      if (t <= 0 || t >= best) continue;
      const double z = o.z() + t * d.z();
      if (z >= 0 && z <= p.height) best = t;
    }
    return best;
  }

  // Distance from a world point to the nearest surface of the scene.
  double SurfaceDistance(const Vec3& p) const {
    double best = ground ? std::abs(p.z()) : std::numeric_limits<double>::infinity();
    for (const Box& b : boxes) {
      const Vec3 outside = (b.min - p).cwiseMax(p - b.max).cwiseMax(0.0);
      const double inside = std::min((p - b.min).minCoeff(), (b.max - p).minCoeff());
      best = std::min(best, outside.norm() > 0 ? outside.norm() : std::max(inside, 0.0));
    }
    for (const Pole& c : poles) {
      const double radial = std::hypot(p.x() - c.x, p.y() - c.y) - c.radius;
      const double above = std::max(p.z() - c.height, 0.0);
      best = std::min(best, std::hypot(std::abs(radial), above));
    }
    return best;
  }
};

// An urban-like street: ground, building rows on both sides with gaps, parked-car boxes, poles.
inline Scene StructuredStreet() {
  Scene s;
  for (int i = -6; i <= 6; ++i) {
    const double x0 = i * 16.0;
    s.boxes.push_back({Vec3(x0, 9.0, 0.0), Vec3(x0 + 11.0 + (i % 3), 20.0, 8.0 + 2 * (i % 2))});
    s.boxes.push_back({Vec3(x0 + 4.0, -22.0, 0.0), Vec3(x0 + 14.0, -10.0, 12.0 - 3 * (i % 2))});
    s.poles.push_back({x0 + 2.0, 7.5, 0.15, 6.0});
    s.poles.push_back({x0 + 9.0, -8.0, 0.12, 5.0});
    if (i % 2 == 0) s.boxes.push_back({Vec3(x0 + 6.0, 5.0, 0.0), Vec3(x0 + 10.5, 6.8, 1.5)});
  }
  return s;
}

// A straight featureless corridor along x: ground and two parallel walls at y = +-4 m.
inline Scene Corridor() {
  Scene s;
  s.boxes.push_back({Vec3(-1000, 4.0, 0.0), Vec3(1000, 5.0, 6.0)});
  s.boxes.push_back({Vec3(-1000, -5.0, 0.0), Vec3(1000, -4.0, 6.0)});
  return s;
}

struct ScannerModel {
  int rings = 32;
  double min_elevation_deg = -16.0, max_elevation_deg = 15.0;
  int columns = 720;  // 0.5 deg azimuth step
  double sweep_s = 0.1;
  double max_range_m = 100.0;
  double range_noise_m = 0.0;
};

// T_world_lidar(t) for t in [0, sweep_s]; points in the lidar frame at their time.
inline std::vector<LidarPoint> Scan(const Scene& scene, const std::function<SE3(double)>& pose,
                                    const ScannerModel& m = {}, std::uint64_t seed = 1) {
  std::mt19937_64 rng = MakeRng(seed, "synthetic_lidar");
  NormalSampler normal;
  std::vector<LidarPoint> points;
  for (int c = 0; c < m.columns; ++c) {
    const double t = m.sweep_s * c / m.columns;
    const SE3 T_world_lidar = pose(t);
    const double az = 2 * M_PI * c / m.columns;
    for (int r = 0; r < m.rings; ++r) {
      const double el =
          (m.min_elevation_deg + (m.max_elevation_deg - m.min_elevation_deg) * r / (m.rings - 1)) *
          M_PI / 180.0;
      const Vec3 d_lidar(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
      const Vec3 d_world = T_world_lidar.rotation() * d_lidar;
      double range = scene.Cast(T_world_lidar.translation(), d_world);
      if (!(range <= m.max_range_m)) continue;
      if (m.range_noise_m > 0) range += m.range_noise_m * normal(rng);
      const Vec3 p = range * d_lidar;
      points.push_back({static_cast<float>(p.x()), static_cast<float>(p.y()),
                        static_cast<float>(p.z()), 1.0f, static_cast<float>(t),
                        static_cast<std::uint16_t>(r)});
    }
  }
  return points;
}

inline std::vector<LidarPoint> StaticScan(const Scene& scene, const SE3& T_world_lidar,
                                          const ScannerModel& m = {}, std::uint64_t seed = 1) {
  return Scan(
      scene, [&](double) { return T_world_lidar; }, m, seed);
}

}  // namespace statebench::est::testing
