// Flat hash table from integer voxel keys to 32-bit indices, for the lidar odometry's voxel
// downsampling and the brick index of its voxel map (voxel_brick_index.hpp).
//
// Open addressing with linear probing in a power-of-two array of 16-byte slots (key and index
// side by side: a lookup is one hash and, at the table's load of at most one half, one or two
// neighbouring slots), grown by doubling. Erasing shifts the following slots of the probe run
// back (no tombstones), so a lookup never searches past the run its key belongs to.
//
// The hash mixes Teschner et al.'s (2003) spatial-hash primes with a multiplicative (Fibonacci)
// step and takes the high bits, so neighbouring voxels spread over the table. Which slot a key
// lands in changes nothing that callers see: they reach their data by key, never by position.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace statebench::est {

struct VoxelKey {
  int x = 0;
  int y = 0;
  int z = 0;
  bool operator==(const VoxelKey&) const = default;
};

// static_cast<int>(std::floor(s)) for finite |s| < 2^31 (callers bound s first), without the
// libm call (the build targets baseline x86-64, where floor is not an instruction): truncation
// toward zero is one step too high exactly for negative non-integers.
inline int FloorToInt(double s) {
  const int truncated = static_cast<int>(s);
  return truncated - static_cast<int>(s < truncated);  // no branch: the sign is data
}

class VoxelIndexTable {
 public:
  static constexpr std::uint32_t kNone = 0xffffffffu;

  // Room for `expected` keys before the first growth.
  explicit VoxelIndexTable(std::size_t expected = 0);

  // The index stored under key, or kNone.
  std::uint32_t Find(const VoxelKey& key) const {
    for (std::size_t i = Home(key);; i = (i + 1) & mask_) {
      const Slot& s = slots_[i];
      if (s.index == kNone || s.key == key) return s.index;
    }
  }
  // Stores index under key when the key is new and returns it; returns the stored index
  // otherwise (index is then ignored). index must not be kNone.
  std::uint32_t Insert(const VoxelKey& key, std::uint32_t index);
  // Replaces the index stored under an existing key.
  void Assign(const VoxelKey& key, std::uint32_t index);
  // Removes key (no effect when absent).
  void Erase(const VoxelKey& key);

  std::size_t size() const { return size_; }
  // Removes every key (the table keeps its size).
  void Clear();

 private:
  struct Slot {
    VoxelKey key;
    std::uint32_t index = kNone;
  };

  std::size_t Home(const VoxelKey& k) const {
    const auto u = [](int c) { return static_cast<std::uint64_t>(static_cast<std::uint32_t>(c)); };
    const std::uint64_t h = (u(k.x) * 73856093u) ^ (u(k.y) * 19349669u) ^ (u(k.z) * 83492791u);
    return static_cast<std::size_t>((h * 0x9E3779B97F4A7C15ull) >> shift_);
  }
  void Rehash(std::size_t capacity);

  std::vector<Slot> slots_;
  std::size_t mask_ = 0;
  int shift_ = 64;
  std::size_t size_ = 0;
};

}  // namespace statebench::est
