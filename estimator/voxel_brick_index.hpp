// Map from integer voxel keys to 32-bit voxel indices, stored in bricks of 4 x 4 x 4 voxels, for
// the neighbourhood queries of the lidar odometry's voxel map.
//
// A brick holds the indices of its 64 voxels (kNone where empty); a VoxelIndexTable maps a
// brick's key (the voxel key divided by 4, rounded down) to its position in a dense array of
// bricks. A neighbourhood query looks each brick of its box up once (a Window) and then reads
// voxel indices out of the bricks' arrays, where a voxel-keyed hash table would probe once per
// voxel: 27 probes for the 3 x 3 x 3 voxels around a point become 1 to 8, the 7 x 7 x 7 voxels
// of a 3-voxel radius 8 to 27. Which brick or slot holds a key changes nothing that callers see.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "estimator/voxel_index_table.hpp"

namespace statebench::est {

class VoxelBrickIndex {
 public:
  static constexpr std::uint32_t kNone = VoxelIndexTable::kNone;

  // The index stored under key, or kNone.
  std::uint32_t Find(const VoxelKey& key) const {
    const std::uint32_t b = table_.Find(BrickOf(key));
    return b == kNone ? kNone : bricks_[b].slots[SlotOf(key)];
  }
  // Stores index under key when the key is new and returns it; returns the stored index
  // otherwise (index is then ignored). index must not be kNone.
  std::uint32_t Insert(const VoxelKey& key, std::uint32_t index);
  // Replaces the index stored under an existing key.
  void Assign(const VoxelKey& key, std::uint32_t index);
  // Removes key (no effect when absent).
  void Erase(const VoxelKey& key);

  std::size_t size() const { return size_; }
  void Clear();

  // Lookups of the keys in the box [lo, hi] (inclusive per axis), each of the box's bricks
  // looked up once when the window is made. A box of more than kMaxBricks bricks falls back
  // to one table lookup per key (same answers).
  class Window {
   public:
    static constexpr int kMaxBricks = 27;
    Window(const VoxelBrickIndex& index, const VoxelKey& lo, const VoxelKey& hi);
    // key must lie in the box.
    std::uint32_t Find(const VoxelKey& key) const {
      if (!small_) return index_.Find(key);
      const int i = ((key.x >> kBits) - lo_.x) * stride_x_ +
                    ((key.y >> kBits) - lo_.y) * stride_y_ + ((key.z >> kBits) - lo_.z);
      return bricks_[i] ? bricks_[i][SlotOf(key)] : kNone;
    }

   private:
    const VoxelBrickIndex& index_;
    VoxelKey lo_;  // brick key of the box's low corner
    int stride_x_ = 0;
    int stride_y_ = 0;
    bool small_ = false;
    std::array<const std::uint32_t*, kMaxBricks> bricks_{};  // slots, nullptr where absent
  };

 private:
  static constexpr int kBits = 2;  // bricks of 2^kBits voxels per axis
  static constexpr int kSide = 1 << kBits;
  static constexpr int kSlots = kSide * kSide * kSide;

  struct Brick {
    VoxelKey key;
    std::uint32_t used = 0;  // slots holding an index
    std::array<std::uint32_t, kSlots> slots;
  };

  // Arithmetic shifts and masks: floor division and the non-negative remainder for negative
  // keys too.
  static VoxelKey BrickOf(const VoxelKey& k) { return {k.x >> kBits, k.y >> kBits, k.z >> kBits}; }
  static int SlotOf(const VoxelKey& k) {
    constexpr int m = kSide - 1;
    return (k.x & m) | ((k.y & m) << kBits) | ((k.z & m) << (2 * kBits));
  }

  VoxelIndexTable table_;  // brick key -> position in bricks_
  std::vector<Brick> bricks_;
  std::size_t size_ = 0;
};

}  // namespace statebench::est
