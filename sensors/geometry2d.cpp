#include "sensors/geometry2d.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace statebench::sensors::geometry2d {
namespace {

double Cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Sign of the turn a -> b -> c: > 0 counter-clockwise.
double Orientation(const Vec2& a, const Vec2& b, const Vec2& c) { return Cross(b - a, c - a); }

bool OnSegment(const Vec2& a, const Vec2& b, const Vec2& p) {
  return std::min(a.x(), b.x()) <= p.x() && p.x() <= std::max(a.x(), b.x()) &&
         std::min(a.y(), b.y()) <= p.y() && p.y() <= std::max(a.y(), b.y());
}

}  // namespace

double PointSegmentDistance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double len_sq = ab.squaredNorm();
  if (len_sq == 0.0) return (p - a).norm();
  const double u = std::clamp((p - a).dot(ab) / len_sq, 0.0, 1.0);
  return (p - (a + u * ab)).norm();
}

bool SegmentsIntersect(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const double o1 = Orientation(a, b, c);
  const double o2 = Orientation(a, b, d);
  const double o3 = Orientation(c, d, a);
  const double o4 = Orientation(c, d, b);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) {
    return true;
  }
  return (o1 == 0 && OnSegment(a, b, c)) || (o2 == 0 && OnSegment(a, b, d)) ||
         (o3 == 0 && OnSegment(c, d, a)) || (o4 == 0 && OnSegment(c, d, b));
}

double SegmentSegmentDistance(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  if (SegmentsIntersect(a, b, c, d)) return 0.0;
  return std::min({PointSegmentDistance(a, c, d), PointSegmentDistance(b, c, d),
                   PointSegmentDistance(c, a, b), PointSegmentDistance(d, a, b)});
}

bool PointInPolygon(const Vec2& p, const std::vector<Vec2>& polygon) {
  bool inside = false;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2& a = polygon[i];
    const Vec2& b = polygon[j];
    if ((a.y() > p.y()) != (b.y() > p.y())) {
      const double x_cross = a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
      if (p.x() < x_cross) inside = !inside;
    }
  }
  return inside;
}

double SegmentPolygonDistance(const Vec2& a, const Vec2& b, const std::vector<Vec2>& polygon) {
  if (PointInPolygon(a, polygon)) return 0.0;
  double best = std::numeric_limits<double>::infinity();
  const std::size_t n = polygon.size();
  for (std::size_t i = 0; i < n; ++i) {
    best = std::min(best, SegmentSegmentDistance(a, b, polygon[i], polygon[(i + 1) % n]));
    if (best == 0.0) break;
  }
  return best;
}

double PolygonPolygonDistance(const std::vector<Vec2>& p, const std::vector<Vec2>& q) {
  if (p.empty() || q.empty()) return std::numeric_limits<double>::infinity();
  if (PointInPolygon(p.front(), q) || PointInPolygon(q.front(), p)) return 0.0;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < p.size(); ++i) {
    best = std::min(best, SegmentPolygonDistance(p[i], p[(i + 1) % p.size()], q));
    if (best == 0.0) break;
  }
  return best;
}

std::vector<Vec2> OrientedRectangle(const Vec2& centre, double heading_rad, double half_length,
                                    double half_width) {
  const Vec2 u(std::cos(heading_rad), std::sin(heading_rad));
  const Vec2 v(-u.y(), u.x());
  return {centre + half_length * u + half_width * v, centre - half_length * u + half_width * v,
          centre - half_length * u - half_width * v, centre + half_length * u - half_width * v};
}

void PolygonBounds(const std::vector<Vec2>& polygon, Vec2* min, Vec2* max) {
  *min = Vec2::Constant(std::numeric_limits<double>::infinity());
  *max = -*min;
  for (const Vec2& v : polygon) {
    *min = min->cwiseMin(v);
    *max = max->cwiseMax(v);
  }
}

}  // namespace statebench::sensors::geometry2d
