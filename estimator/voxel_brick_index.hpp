// Map from integer voxel keys to 32-bit voxel indices, stored in bricks of 8 x 8 x 8 voxels, for
// the neighbourhood queries of the lidar odometry's voxel map.
//
// A brick holds the indices of its 512 voxels (kNone where empty) and an occupancy bit per
// voxel; a VoxelIndexTable maps a brick's key (the voxel key divided by 8, rounded down) to its
// position in a dense array of bricks. A neighbourhood query looks each brick of its box up once
// (a Window) and then reads voxel indices out of the bricks' arrays, where a voxel-keyed hash
// table would probe once per voxel: 27 probes for the 3 x 3 x 3 voxels around a point become 1
// (42 % of the time) to 8, the 7 x 7 x 7 voxels of a 3-voxel radius 1 to 8. A Window's Column
// gives the occupied voxels of a stretch along z as bits, so that a query skips empty voxels (9
// of 10 in a 3-voxel radius around a lidar map point) without visiting them. Which brick or slot
// holds a key changes nothing that callers see. (Bricks of 4 x 4 x 4 voxels made the odometry
// step 3 % slower; of 16 x 16 x 16, no faster.) A brick takes 2 KB: this suits maps whose
// occupied voxels cluster on surfaces, as a lidar map's do.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "estimator/voxel_index_table.hpp"

namespace statebench::est {

class VoxelBrickIndex {
  struct Brick;

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
    static constexpr int kMaxColumn = 32;  // voxels per Column call
    Window(const VoxelBrickIndex& index, const VoxelKey& lo, const VoxelKey& hi);
    // key must lie in the box.
    std::uint32_t Find(const VoxelKey& key) const {
      if (!small_) return index_.Find(key);
      const Brick* brick = bricks_[BrickAt(key.x, key.y, key.z)];
      return brick ? brick->slots[SlotOf(key)] : kNone;
    }
    // Which voxels (x, y, z_lo + k), 0 <= k <= z_hi - z_lo < kMaxColumn, hold an index: bit k.
    // The voxels must lie in the box. Lets a caller skip empty voxels without looking at them.
    std::uint32_t Column(int x, int y, int z_lo, int z_hi) const {
      if (!small_) return ColumnByLookups(x, y, z_lo, z_hi);
      // A brick's occupancy holds the column's kSide voxels as kSide adjacent bits of a word.
      const int column_bit = ColumnBit(x, y);
      const int at = BrickAt(x, y, z_lo);
      std::uint64_t bits = 0;
      for (int b = z_lo >> kBits; b <= z_hi >> kBits; ++b) {
        const Brick* brick = bricks_[at + b - (z_lo >> kBits)];
        if (brick == nullptr) continue;
        const std::uint64_t column =
            (brick->occupied[column_bit / 64] >> (column_bit % 64)) & ((1u << kSide) - 1);
        const int offset = b * kSide - z_lo;  // bit of the brick's first voxel, may be < 0
        bits |= offset >= 0 ? column << offset : column >> -offset;
      }
      return static_cast<std::uint32_t>(bits & ((std::uint64_t{2} << (z_hi - z_lo)) - 1));
    }

   private:
    int BrickAt(int x, int y, int z) const {
      return ((x >> kBits) - lo_.x) * stride_x_ + ((y >> kBits) - lo_.y) * stride_y_ +
             ((z >> kBits) - lo_.z);
    }
    std::uint32_t ColumnByLookups(int x, int y, int z_lo, int z_hi) const;

    const VoxelBrickIndex& index_;
    VoxelKey lo_;  // brick key of the box's low corner
    int stride_x_ = 0;
    int stride_y_ = 0;
    bool small_ = false;
    std::array<const Brick*, kMaxBricks> bricks_{};  // nullptr where absent
  };

 private:
  static constexpr int kBits = 3;  // bricks of 2^kBits voxels per axis
  static constexpr int kSide = 1 << kBits;
  static constexpr int kSlots = kSide * kSide * kSide;

  struct Brick {
    VoxelKey key;
    std::array<std::uint64_t, kSlots / 64> occupied{};  // bit SlotOf(k): slot k holds an index
    std::array<std::uint32_t, kSlots> slots;
  };

  // Arithmetic shifts and masks: floor division and the non-negative remainder for negative
  // keys too. z is the fastest-varying coordinate of a slot, so that a column of a brick is a
  // run of kSide bits of its occupancy (never across two words: kSide divides 64).
  static VoxelKey BrickOf(const VoxelKey& k) { return {k.x >> kBits, k.y >> kBits, k.z >> kBits}; }
  static int ColumnBit(int x, int y) {
    constexpr int m = kSide - 1;
    return ((y & m) << kBits) | ((x & m) << (2 * kBits));
  }
  static int SlotOf(const VoxelKey& k) { return ColumnBit(k.x, k.y) | (k.z & (kSide - 1)); }
  static void SetOccupied(Brick* brick, int slot, bool occupied) {
    const std::uint64_t bit = std::uint64_t{1} << (slot % 64);
    std::uint64_t& word = brick->occupied[slot / 64];
    word = occupied ? word | bit : word & ~bit;
  }

  VoxelIndexTable table_;  // brick key -> position in bricks_
  std::vector<Brick> bricks_;
  std::size_t size_ = 0;
};

}  // namespace statebench::est
