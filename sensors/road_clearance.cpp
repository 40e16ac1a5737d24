#include "sensors/road_clearance.hpp"

#include <algorithm>
#include <cmath>

#include "sensors/geometry2d.hpp"

namespace statebench::sensors {
namespace {

void SortUnique(std::vector<int>* ids) {
  std::sort(ids->begin(), ids->end());
  ids->erase(std::unique(ids->begin(), ids->end()), ids->end());
}

}  // namespace

RoadClearance::RoadClearance(const RoadGeometry& roads, double cell_size_m)
    : cell_size_m_(cell_size_m) {
  for (const LaneShape& lane : roads.lanes) {
    for (std::size_t i = 0; i + 1 < lane.centre.size(); ++i) {
      const LaneSegment s{lane.centre[i].head<2>(), lane.centre[i + 1].head<2>(),
                          0.5 * lane.width_m};
      const Vec2 pad = Vec2::Constant(s.half_width_m);
      Insert(s.a.cwiseMin(s.b) - pad, s.a.cwiseMax(s.b) + pad, static_cast<int>(segments_.size()),
             false);
      segments_.push_back(s);
    }
  }
  for (const std::vector<Vec3>& junction : roads.junctions) {
    if (junction.size() < 3) continue;
    std::vector<Vec2> polygon;
    for (const Vec3& v : junction) polygon.push_back(v.head<2>());
    Vec2 min, max;
    geometry2d::PolygonBounds(polygon, &min, &max);
    Insert(min, max, static_cast<int>(junctions_.size()), true);
    junctions_.push_back(std::move(polygon));
  }
}

std::int64_t RoadClearance::CellKey(int ix, int iy) const {
  return (static_cast<std::int64_t>(ix) << 32) ^ static_cast<std::uint32_t>(iy);
}

void RoadClearance::Insert(const Vec2& min, const Vec2& max, int id, bool junction) {
  const int x0 = static_cast<int>(std::floor(min.x() / cell_size_m_));
  const int x1 = static_cast<int>(std::floor(max.x() / cell_size_m_));
  const int y0 = static_cast<int>(std::floor(min.y() / cell_size_m_));
  const int y1 = static_cast<int>(std::floor(max.y() / cell_size_m_));
  for (int ix = x0; ix <= x1; ++ix) {
    for (int iy = y0; iy <= y1; ++iy) {
      Candidates& c = cells_[CellKey(ix, iy)];
      (junction ? c.junctions : c.segments).push_back(id);
    }
  }
}

RoadClearance::Candidates RoadClearance::Query(const Vec2& min, const Vec2& max) const {
  Candidates out;
  const int x0 = static_cast<int>(std::floor(min.x() / cell_size_m_));
  const int x1 = static_cast<int>(std::floor(max.x() / cell_size_m_));
  const int y0 = static_cast<int>(std::floor(min.y() / cell_size_m_));
  const int y1 = static_cast<int>(std::floor(max.y() / cell_size_m_));
  for (int ix = x0; ix <= x1; ++ix) {
    for (int iy = y0; iy <= y1; ++iy) {
      const auto it = cells_.find(CellKey(ix, iy));
      if (it == cells_.end()) continue;
      out.segments.insert(out.segments.end(), it->second.segments.begin(),
                          it->second.segments.end());
      out.junctions.insert(out.junctions.end(), it->second.junctions.begin(),
                           it->second.junctions.end());
    }
  }
  SortUnique(&out.segments);
  SortUnique(&out.junctions);
  return out;
}

bool RoadClearance::OnRoad(const Vec2& p) const {
  // A point lies in exactly one cell, and every corridor or junction covering it is listed there.
  const auto it = cells_.find(CellKey(static_cast<int>(std::floor(p.x() / cell_size_m_)),
                                      static_cast<int>(std::floor(p.y() / cell_size_m_))));
  if (it == cells_.end()) return false;
  for (const int i : it->second.segments) {
    const LaneSegment& s = segments_[i];
    if (geometry2d::PointSegmentDistance(p, s.a, s.b) < s.half_width_m) return true;
  }
  for (const int i : it->second.junctions) {
    if (geometry2d::PointInPolygon(p, junctions_[i])) return true;
  }
  return false;
}

bool RoadClearance::PolygonClear(const std::vector<Vec2>& polygon, double clearance_m) const {
  Vec2 min, max;
  geometry2d::PolygonBounds(polygon, &min, &max);
  // Segments are indexed with their half width as padding, so a query padded by the clearance
  // finds every corridor that could come within clearance_m.
  const Vec2 pad = Vec2::Constant(clearance_m);
  const Candidates c = Query(min - pad, max + pad);
  for (const int i : c.segments) {
    const LaneSegment& s = segments_[i];
    if (geometry2d::SegmentPolygonDistance(s.a, s.b, polygon) < s.half_width_m + clearance_m) {
      return false;
    }
  }
  for (const int i : c.junctions) {
    if (geometry2d::PolygonPolygonDistance(polygon, junctions_[i]) < clearance_m) return false;
  }
  return true;
}

}  // namespace statebench::sensors
