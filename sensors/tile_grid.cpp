#include "sensors/tile_grid.hpp"

#include <algorithm>

namespace statebench::sensors {

TileGrid::TileGrid(const std::vector<Eigen::AlignedBox3d>& tile_bounds, double cell_m)
    : cell_m_(cell_m) {
  Eigen::AlignedBox2d all;
  for (const auto& b : tile_bounds) {
    all.extend(Vec2(b.min().head<2>()));
    all.extend(Vec2(b.max().head<2>()));
  }
  if (all.isEmpty()) return;
  min_ = all.min();
  nx_ = std::max(1, static_cast<int>(std::ceil((all.max().x() - min_.x()) / cell_m)));
  ny_ = std::max(1, static_cast<int>(std::ceil((all.max().y() - min_.y()) / cell_m)));
  cells_.resize(static_cast<std::size_t>(nx_) * ny_);
  for (std::size_t id = 0; id < tile_bounds.size(); ++id) {
    const auto& b = tile_bounds[id];
    const int x0 =
        std::clamp(static_cast<int>(std::floor((b.min().x() - min_.x()) / cell_m)), 0, nx_ - 1);
    const int x1 =
        std::clamp(static_cast<int>(std::floor((b.max().x() - min_.x()) / cell_m)), 0, nx_ - 1);
    const int y0 =
        std::clamp(static_cast<int>(std::floor((b.min().y() - min_.y()) / cell_m)), 0, ny_ - 1);
    const int y1 =
        std::clamp(static_cast<int>(std::floor((b.max().y() - min_.y()) / cell_m)), 0, ny_ - 1);
    for (int iy = y0; iy <= y1; ++iy) {
      for (int ix = x0; ix <= x1; ++ix) {
        cells_[static_cast<std::size_t>(iy) * nx_ + ix].push_back(static_cast<int>(id));
      }
    }
  }
}

}  // namespace statebench::sensors
