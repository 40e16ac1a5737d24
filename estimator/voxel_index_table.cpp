#include "estimator/voxel_index_table.hpp"

#include <algorithm>
#include <bit>
#include <utility>

namespace statebench::est {
namespace {

constexpr std::size_t kMinCapacity = 16;

// Smallest power of two with room for `keys` at a load of at most one half.
std::size_t CapacityFor(std::size_t keys) {
  return std::max(kMinCapacity, std::bit_ceil(2 * keys + 1));
}

}  // namespace

VoxelIndexTable::VoxelIndexTable(std::size_t expected) { Rehash(CapacityFor(expected)); }

void VoxelIndexTable::Rehash(std::size_t capacity) {
  std::vector<Slot> old = std::exchange(slots_, std::vector<Slot>(capacity));
  mask_ = capacity - 1;
  shift_ = 64 - std::countr_zero(capacity);
  for (const Slot& s : old) {
    if (s.index == kNone) continue;
    std::size_t i = Home(s.key);
    while (slots_[i].index != kNone) i = (i + 1) & mask_;
    slots_[i] = s;
  }
}

std::uint32_t VoxelIndexTable::Insert(const VoxelKey& key, std::uint32_t index) {
  if (2 * (size_ + 1) > slots_.size()) Rehash(2 * slots_.size());
  std::size_t i = Home(key);
  for (; slots_[i].index != kNone; i = (i + 1) & mask_) {
    if (slots_[i].key == key) return slots_[i].index;
  }
  slots_[i] = {key, index};
  ++size_;
  return index;
}

void VoxelIndexTable::Assign(const VoxelKey& key, std::uint32_t index) {
  for (std::size_t i = Home(key); slots_[i].index != kNone; i = (i + 1) & mask_) {
    if (slots_[i].key == key) {
      slots_[i].index = index;
      return;
    }
  }
}

void VoxelIndexTable::Erase(const VoxelKey& key) {
  std::size_t hole = Home(key);
  while (true) {
    if (slots_[hole].index == kNone) return;
    if (slots_[hole].key == key) break;
    hole = (hole + 1) & mask_;
  }
  // Backward-shift deletion: move each following entry of the run into the hole when the hole
  // lies on its probe path (cyclically between its home slot and its slot).
  for (std::size_t j = (hole + 1) & mask_; slots_[j].index != kNone; j = (j + 1) & mask_) {
    const std::size_t home = Home(slots_[j].key);
    const std::size_t from_home_to_j = (j - home) & mask_;
    const std::size_t from_home_to_hole = (hole - home) & mask_;
    if (from_home_to_hole < from_home_to_j) {
      slots_[hole] = slots_[j];
      hole = j;
    }
  }
  slots_[hole] = Slot{};
  --size_;
}

void VoxelIndexTable::Clear() {
  std::fill(slots_.begin(), slots_.end(), Slot{});
  size_ = 0;
}

}  // namespace statebench::est
