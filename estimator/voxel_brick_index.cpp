#include "estimator/voxel_brick_index.hpp"

#include <algorithm>

namespace statebench::est {

std::uint32_t VoxelBrickIndex::Insert(const VoxelKey& key, std::uint32_t index) {
  const auto next = static_cast<std::uint32_t>(bricks_.size());
  const std::uint32_t b = table_.Insert(BrickOf(key), next);
  if (b == next) {
    Brick& brick = bricks_.emplace_back();
    brick.key = BrickOf(key);
    brick.slots.fill(kNone);
  }
  Brick& brick = bricks_[b];
  std::uint32_t& slot = brick.slots[SlotOf(key)];
  if (slot != kNone) return slot;
  slot = index;
  SetOccupied(&brick, SlotOf(key), true);
  ++size_;
  return index;
}

void VoxelBrickIndex::Assign(const VoxelKey& key, std::uint32_t index) {
  const std::uint32_t b = table_.Find(BrickOf(key));
  if (b == kNone) return;
  std::uint32_t& slot = bricks_[b].slots[SlotOf(key)];
  if (slot != kNone) slot = index;
}

void VoxelBrickIndex::Erase(const VoxelKey& key) {
  const std::uint32_t b = table_.Find(BrickOf(key));
  if (b == kNone) return;
  Brick& brick = bricks_[b];
  std::uint32_t& slot = brick.slots[SlotOf(key)];
  if (slot == kNone) return;
  slot = kNone;
  SetOccupied(&brick, SlotOf(key), false);
  --size_;
  if (std::any_of(brick.occupied.begin(), brick.occupied.end(),
                  [](std::uint64_t word) { return word != 0; })) {
    return;
  }
  // The brick is empty: the last brick moves into its place.
  table_.Erase(bricks_[b].key);
  if (b + 1 != bricks_.size()) {
    bricks_[b] = bricks_.back();
    table_.Assign(bricks_[b].key, b);
  }
  bricks_.pop_back();
}

void VoxelBrickIndex::Clear() {
  table_.Clear();
  bricks_.clear();
  size_ = 0;
}

VoxelBrickIndex::Window::Window(const VoxelBrickIndex& index, const VoxelKey& lo,
                                const VoxelKey& hi)
    : index_(index), lo_(BrickOf(lo)) {
  const VoxelKey top = BrickOf(hi);
  // Bricks per axis in 64 bits (a box may span most of the int range).
  const long long nx = top.x - static_cast<long long>(lo_.x) + 1;
  const long long ny = top.y - static_cast<long long>(lo_.y) + 1;
  const long long nz = top.z - static_cast<long long>(lo_.z) + 1;
  small_ = nx <= kMaxBricks && ny <= kMaxBricks && nz <= kMaxBricks && nx * ny * nz <= kMaxBricks;
  if (!small_) return;
  stride_y_ = static_cast<int>(nz);
  stride_x_ = static_cast<int>(ny * nz);
  int i = 0;
  for (int x = lo_.x; x <= top.x; ++x) {
    for (int y = lo_.y; y <= top.y; ++y) {
      for (int z = lo_.z; z <= top.z; ++z, ++i) {
        const std::uint32_t b = index.table_.Find({x, y, z});
        bricks_[i] = b == kNone ? nullptr : &index.bricks_[b];
      }
    }
  }
}

std::uint32_t VoxelBrickIndex::Window::ColumnByLookups(int x, int y, int z_lo, int z_hi) const {
  std::uint32_t bits = 0;
  for (int z = z_lo; z <= z_hi; ++z) {
    if (index_.Find({x, y, z}) != kNone) bits |= std::uint32_t{1} << (z - z_lo);
  }
  return bits;
}

}  // namespace statebench::est
