// A uniform 2D grid over the ground plane that lists, per cell, the tiles whose bounding boxes
// overlap it, and walks the cells a ray crosses in order (2D DDA, Amanatides & Woo 1987). Every
// tile whose box a ray meets above a cell is listed in that cell, so after the cells up to range r
// have been visited, every tile that could hold a hit closer than r is known: the caster can stop
// as soon as its best hit lies before the end of the current cell.
#pragma once

#include <cmath>
#include <limits>
#include <vector>

#include "core/eigen_types.hpp"

namespace statebench::sensors {

class TileGrid {
 public:
  TileGrid() = default;
  TileGrid(const std::vector<Eigen::AlignedBox3d>& tile_bounds, double cell_m);

  // Calls visit(ids, cell_exit_range) for each cell crossed by origin + r * direction,
  // r in [r_begin, r_end], in order; `ids` are the tiles listed in the cell. Stops when visit
  // returns false.
  template <typename Visit>
  void Walk(const Vec3& origin, const Vec3& direction, double r_begin, double r_end,
            Visit&& visit) const;

 private:
  const std::vector<int>& Cell(int ix, int iy) const {
    return cells_[static_cast<std::size_t>(iy) * nx_ + ix];
  }

  Vec2 min_ = Vec2::Zero();
  double cell_m_ = 1.0;
  int nx_ = 0;
  int ny_ = 0;
  std::vector<std::vector<int>> cells_;
};

template <typename Visit>
void TileGrid::Walk(const Vec3& o, const Vec3& d, double r_begin, double r_end,
                    Visit&& visit) const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // Clip the segment to the grid's extent in x and y.
  double r0 = r_begin, r1 = r_end;
  for (int a = 0; a < 2; ++a) {
    const double lo = min_[a];
    const double hi = min_[a] + cell_m_ * (a == 0 ? nx_ : ny_);
    if (d[a] == 0.0) {
      if (o[a] < lo || o[a] > hi) return;
      continue;
    }
    double ta = (lo - o[a]) / d[a], tb = (hi - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    r0 = std::max(r0, ta);
    r1 = std::min(r1, tb);
  }
  if (r0 > r1) return;

  int cell[2];
  int step[2];
  double next[2];   // range at which the ray crosses into the next cell along each axis
  double delta[2];  // range between successive crossings
  for (int a = 0; a < 2; ++a) {
    const int n = a == 0 ? nx_ : ny_;
    const double p = o[a] + r0 * d[a];
    cell[a] = std::clamp(static_cast<int>(std::floor((p - min_[a]) / cell_m_)), 0, n - 1);
    if (d[a] > 0.0) {
      step[a] = 1;
      next[a] = (min_[a] + (cell[a] + 1) * cell_m_ - o[a]) / d[a];
      delta[a] = cell_m_ / d[a];
    } else if (d[a] < 0.0) {
      step[a] = -1;
      next[a] = (min_[a] + cell[a] * cell_m_ - o[a]) / d[a];
      delta[a] = -cell_m_ / d[a];
    } else {
      step[a] = 0;
      next[a] = kInf;
      delta[a] = kInf;
    }
  }
  while (true) {
    const int a = next[0] < next[1] ? 0 : 1;
    const double exit = std::min(next[a], r1);
    if (!visit(Cell(cell[0], cell[1]), exit) || exit >= r1) return;
    cell[a] += step[a];
    if (cell[a] < 0 || cell[a] >= (a == 0 ? nx_ : ny_)) return;
    next[a] += delta[a];
  }
}

}  // namespace statebench::sensors
