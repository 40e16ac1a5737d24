// Small 2D geometry on the ground plane (x east, y north), used to keep generated objects off
// the roads. Polygons are vertex lists without repeating the first vertex; any winding.
#pragma once

#include <vector>

#include "core/eigen_types.hpp"

namespace statebench::sensors::geometry2d {

double PointSegmentDistance(const Vec2& p, const Vec2& a, const Vec2& b);
bool SegmentsIntersect(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d);
double SegmentSegmentDistance(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d);

// Even-odd rule; points exactly on an edge may fall either way.
bool PointInPolygon(const Vec2& p, const std::vector<Vec2>& polygon);

// 0 when the segment touches or lies inside the polygon.
double SegmentPolygonDistance(const Vec2& a, const Vec2& b, const std::vector<Vec2>& polygon);
// 0 when the polygons overlap or one contains the other.
double PolygonPolygonDistance(const std::vector<Vec2>& p, const std::vector<Vec2>& q);

// Rectangle centred at `centre` whose length axis points along `heading_rad` (CCW from x).
std::vector<Vec2> OrientedRectangle(const Vec2& centre, double heading_rad, double half_length,
                                    double half_width);

// Axis-aligned bounds of a polygon as (min, max).
void PolygonBounds(const std::vector<Vec2>& polygon, Vec2* min, Vec2* max);

}  // namespace statebench::sensors::geometry2d
