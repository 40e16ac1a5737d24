#include "estimator/voxel_brick_index.hpp"

#include <gtest/gtest.h>

#include <climits>
#include <cstdint>
#include <map>
#include <random>
#include <tuple>
#include <vector>

namespace statebench::est {
namespace {

using BrickIndexReference = std::map<std::tuple<int, int, int>, std::uint32_t>;

std::uint32_t BrickReferenceIndex(const BrickIndexReference& reference, const VoxelKey& key) {
  const auto it = reference.find({key.x, key.y, key.z});
  return it == reference.end() ? VoxelBrickIndex::kNone : it->second;
}

// Every key of the cube [-half_width, half_width]^3 agrees with the reference, through Find and
// through a window over the whole cube (more than 27 bricks: the fallback) and over a window of
// random size at a random place.
void ExpectBrickIndexMatches(const VoxelBrickIndex& index, const BrickIndexReference& reference,
                             int half_width, std::mt19937* rng) {
  ASSERT_EQ(index.size(), reference.size());
  const VoxelBrickIndex::Window whole(index, {-half_width, -half_width, -half_width},
                                      {half_width, half_width, half_width});
  for (int x = -half_width; x <= half_width; ++x) {
    for (int y = -half_width; y <= half_width; ++y) {
      for (int z = -half_width; z <= half_width; ++z) {
        const std::uint32_t expected = BrickReferenceIndex(reference, {x, y, z});
        ASSERT_EQ(index.Find({x, y, z}), expected);
        ASSERT_EQ(whole.Find({x, y, z}), expected);
      }
    }
  }
  std::uniform_int_distribution<int> corner(-half_width, half_width);
  std::uniform_int_distribution<int> width(0, 8);
  const VoxelKey lo{corner(*rng), corner(*rng), corner(*rng)};
  const VoxelKey hi{lo.x + width(*rng), lo.y + width(*rng), lo.z + width(*rng)};
  const VoxelBrickIndex::Window window(index, lo, hi);
  for (int x = lo.x; x <= hi.x; ++x) {
    for (int y = lo.y; y <= hi.y; ++y) {
      for (int z = lo.z; z <= hi.z; ++z) {
        ASSERT_EQ(window.Find({x, y, z}), BrickReferenceIndex(reference, {x, y, z}));
      }
      // Occupancy of every stretch of the column, through the window and the fallback.
      for (int z_lo = lo.z; z_lo <= hi.z; ++z_lo) {
        for (int z_hi = z_lo; z_hi <= hi.z; ++z_hi) {
          std::uint32_t expected = 0;
          for (int z = z_lo; z <= z_hi; ++z) {
            if (BrickReferenceIndex(reference, {x, y, z}) != VoxelBrickIndex::kNone) {
              expected |= std::uint32_t{1} << (z - z_lo);
            }
          }
          ASSERT_EQ(window.Column(x, y, z_lo, z_hi), expected);
          ASSERT_EQ(whole.Column(x, y, z_lo, z_hi), expected);
        }
      }
    }
  }
}

// Seeded random inserts, reassignments and erasures on keys of a cube around the origin (bricks
// on both sides of zero: floor division of negative keys), dense enough that bricks fill up,
// empty out and are removed (the last brick moving into the hole).
TEST(VoxelBrickIndex, MatchesAReferenceMapUnderRandomInsertEraseAndAssign) {
  constexpr int kHalfWidth = 9;
  std::mt19937 rng(4242);
  std::uniform_int_distribution<int> coordinate(-kHalfWidth, kHalfWidth);
  std::uniform_int_distribution<int> operation(0, 9);
  VoxelBrickIndex index;
  BrickIndexReference reference;
  std::uint32_t next = 0;
  for (int step = 1; step <= 30000; ++step) {
    const VoxelKey key{coordinate(rng), coordinate(rng), coordinate(rng)};
    // Phases: mostly inserting, then mostly erasing (bricks empty out), then mixed.
    const int op = operation(rng);
    const bool insert = step <= 10000 ? op < 8 : (step <= 20000 ? op < 2 : op < 5);
    if (insert) {
      const auto [it, inserted] = reference.emplace(std::tuple{key.x, key.y, key.z}, next);
      ASSERT_EQ(index.Insert(key, next), it->second);
      if (inserted) ++next;
    } else if (op == 9) {
      const auto it = reference.find({key.x, key.y, key.z});
      if (it == reference.end()) continue;
      it->second = next;
      index.Assign(key, next++);
    } else {
      reference.erase({key.x, key.y, key.z});
      index.Erase(key);
    }
    if (step % 2000 == 0) ExpectBrickIndexMatches(index, reference, kHalfWidth, &rng);
    if (step % 5000 == 0) {  // a column across several bricks
      const VoxelBrickIndex::Window window(index, {-2, 1, -kHalfWidth}, {-1, 1, kHalfWidth});
      for (int z_lo = -kHalfWidth; z_lo <= kHalfWidth; ++z_lo) {
        std::uint32_t expected = 0;
        for (int z = z_lo; z <= kHalfWidth; ++z) {
          if (BrickReferenceIndex(reference, {-2, 1, z}) != VoxelBrickIndex::kNone) {
            expected |= std::uint32_t{1} << (z - z_lo);
          }
        }
        ASSERT_EQ(window.Column(-2, 1, z_lo, kHalfWidth), expected);
      }
    }
  }
  index.Clear();
  EXPECT_EQ(index.size(), 0u);
  EXPECT_EQ(index.Find({0, 0, 0}), VoxelBrickIndex::kNone);
}

TEST(VoxelBrickIndex, HandlesKeysAtTheEndsOfTheIntRange) {
  VoxelBrickIndex index;
  const VoxelKey low{INT_MIN, INT_MIN, INT_MIN};
  const VoxelKey high{INT_MAX, INT_MAX, INT_MAX};
  EXPECT_EQ(index.Insert(low, 1u), 1u);
  EXPECT_EQ(index.Insert(high, 2u), 2u);
  EXPECT_EQ(index.Find(low), 1u);
  EXPECT_EQ(index.Find(high), 2u);
  const VoxelBrickIndex::Window top(index, {INT_MAX - 2, INT_MAX - 2, INT_MAX - 2}, high);
  EXPECT_EQ(top.Find(high), 2u);
  EXPECT_EQ(top.Find({INT_MAX - 1, INT_MAX, INT_MAX}), VoxelBrickIndex::kNone);
  const VoxelBrickIndex::Window all(index, low, high);  // fallback, no overflow
  EXPECT_EQ(all.Find(low), 1u);
  index.Erase(low);
  EXPECT_EQ(index.Find(low), VoxelBrickIndex::kNone);
  EXPECT_EQ(index.Find(high), 2u);
}

TEST(VoxelBrickIndex, ColumnCoversItsWholeLength) {
  VoxelBrickIndex index;
  std::mt19937 rng(11);
  std::bernoulli_distribution occupied(0.5);
  std::vector<bool> present;
  for (int z = -40; z <= 40; ++z) {
    present.push_back(occupied(rng));
    if (present.back()) index.Insert({-5, 6, z}, static_cast<std::uint32_t>(z + 40));
  }
  const VoxelBrickIndex::Window window(index, {-5, 6, -40}, {-5, 6, 40});
  const int longest = VoxelBrickIndex::Window::kMaxColumn;
  for (int z_lo = -40; z_lo + longest - 1 <= 40; ++z_lo) {
    for (const int length : {1, 5, longest - 1, longest}) {
      std::uint32_t expected = 0;
      for (int k = 0; k < length; ++k) {
        if (present[z_lo + k + 40]) expected |= std::uint32_t{1} << k;
      }
      ASSERT_EQ(window.Column(-5, 6, z_lo, z_lo + length - 1), expected) << z_lo << " " << length;
    }
  }
}

TEST(VoxelBrickIndex, EmptyingABrickMovesTheLastBrickIntoItsPlace) {
  VoxelBrickIndex index;
  // Three bricks, far apart, filled in order: the first one is emptied, the last one moves.
  const std::vector<VoxelKey> first = {{0, 0, 0}, {1, 2, 3}, {7, 7, 7}};
  const std::vector<VoxelKey> second = {{100, -3, 5}, {101, -3, 5}};
  const std::vector<VoxelKey> third = {{-50, 40, -8}, {-49, 47, -1}};
  std::uint32_t next = 0;
  for (const auto* keys : {&first, &second, &third}) {
    for (const VoxelKey& key : *keys) index.Insert(key, next++);
  }
  for (const VoxelKey& key : first) index.Erase(key);
  EXPECT_EQ(index.size(), 4u);
  for (const VoxelKey& key : first) EXPECT_EQ(index.Find(key), VoxelBrickIndex::kNone);
  EXPECT_EQ(index.Find(second[0]), 3u);
  EXPECT_EQ(index.Find(second[1]), 4u);
  EXPECT_EQ(index.Find(third[0]), 5u);
  EXPECT_EQ(index.Find(third[1]), 6u);
  const VoxelBrickIndex::Window window(index, {-50, 40, -8}, {-49, 47, -1});
  EXPECT_EQ(window.Find(third[1]), 6u);
  EXPECT_EQ(window.Column(-49, 47, -8, -1), 1u << 7);
  EXPECT_EQ(index.Insert(first[1], 9u), 9u);  // the emptied brick comes back
  EXPECT_EQ(index.Find(first[1]), 9u);
  EXPECT_EQ(index.Find(third[0]), 5u);
}

}  // namespace
}  // namespace statebench::est
