#include "estimator/voxel_index_table.hpp"

#include <gtest/gtest.h>

#include <climits>
#include <cmath>
#include <cstdint>
#include <random>
#include <unordered_map>
#include <vector>

namespace statebench::est {
namespace {

struct IndexTableKeyHash {
  std::size_t operator()(const VoxelKey& k) const {
    auto u = [](int c) { return static_cast<std::uint64_t>(static_cast<std::uint32_t>(c)); };
    return std::hash<std::uint64_t>()((u(k.x) * 1000003u + u(k.y)) * 1000033u + u(k.z));
  }
};
using IndexTableReference = std::unordered_map<VoxelKey, std::uint32_t, IndexTableKeyHash>;

// Every key of a box around the origin and of the reference agrees with the reference.
void ExpectIndexTableMatchesReference(const VoxelIndexTable& table,
                                      const IndexTableReference& reference, int half_width) {
  ASSERT_EQ(table.size(), reference.size());
  for (const auto& [key, index] : reference) ASSERT_EQ(table.Find(key), index);
  for (int x = -half_width; x <= half_width; ++x) {
    for (int y = -half_width; y <= half_width; ++y) {
      for (int z = -half_width; z <= half_width; ++z) {
        const auto it = reference.find({x, y, z});
        ASSERT_EQ(table.Find({x, y, z}),
                  it == reference.end() ? VoxelIndexTable::kNone : it->second);
      }
    }
  }
}

// Random inserts, reassignments and erasures (seeded) on keys drawn from a small box, so that
// keys collide, probe runs form (and may wrap around the table's end) and are cut by erasures; the
// table grows from its smallest size. After every 100 operations and at the end, every key of
// the box is looked up and compared with std::unordered_map.
TEST(VoxelIndexTable, MatchesUnorderedMapUnderRandomInsertEraseAndAssign) {
  constexpr int kHalfWidth = 6;
  std::mt19937 rng(20231);
  std::uniform_int_distribution<int> coordinate(-kHalfWidth, kHalfWidth);
  std::uniform_int_distribution<int> operation(0, 9);
  VoxelIndexTable table;
  IndexTableReference reference;
  std::uint32_t next = 0;
  for (int step = 1; step <= 20000; ++step) {
    const VoxelKey key{coordinate(rng), coordinate(rng), coordinate(rng)};
    const int op = operation(rng);
    if (op < 5) {  // insert: the stored index wins when the key exists
      const auto [it, inserted] = reference.emplace(key, next);
      ASSERT_EQ(table.Insert(key, next), it->second);
      if (inserted) ++next;
    } else if (op < 6) {  // reassign an existing key
      if (reference.count(key) == 0) continue;
      reference[key] = next;
      table.Assign(key, next++);
    } else {  // erase, present or not
      reference.erase(key);
      table.Erase(key);
    }
    if (step % 100 == 0) ExpectIndexTableMatchesReference(table, reference, kHalfWidth);
  }
  ExpectIndexTableMatchesReference(table, reference, kHalfWidth);
  EXPECT_GT(reference.size(), 100u);  // the mix kept the table well filled
}

TEST(VoxelIndexTable, KeepsKeysAcrossGrowthIncludingExtremeCoordinates) {
  VoxelIndexTable table(0);
  IndexTableReference reference;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> any(INT_MIN, INT_MAX);
  for (std::uint32_t i = 0; i < 5000; ++i) {
    const VoxelKey key = i < 8 ? VoxelKey{i & 1 ? INT_MIN : INT_MAX, i & 2 ? INT_MIN : INT_MAX,
                                          i & 4 ? INT_MIN : INT_MAX}
                               : VoxelKey{any(rng), any(rng), any(rng)};
    if (reference.emplace(key, i).second) ASSERT_EQ(table.Insert(key, i), i);
  }
  ASSERT_EQ(table.size(), reference.size());
  for (const auto& [key, index] : reference) ASSERT_EQ(table.Find(key), index);
  EXPECT_EQ(table.Find({0, 0, 0}), VoxelIndexTable::kNone);
}

TEST(VoxelIndexTable, ClearEmptiesTheTable) {
  VoxelIndexTable table(4);
  for (int i = 0; i < 100; ++i) table.Insert({i, -i, 2 * i}, static_cast<std::uint32_t>(i));
  table.Clear();
  EXPECT_EQ(table.size(), 0u);
  EXPECT_EQ(table.Find({3, -3, 6}), VoxelIndexTable::kNone);
  EXPECT_EQ(table.Insert({3, -3, 6}, 9u), 9u);
  EXPECT_EQ(table.Find({3, -3, 6}), 9u);
  table.Clear();
  table.Erase({3, -3, 6});  // absent: no effect
  EXPECT_EQ(table.size(), 0u);
}

}  // namespace
}  // namespace statebench::est

namespace statebench::est {
namespace {

// FloorToInt is the cast of std::floor over the range the voxel keys use (|s| <= 1e9), at
// integers, just beside them and at signed zeros.
TEST(VoxelIndexTable, FloorToIntIsTheCastOfTheFloor) {
  std::vector<double> values = {0.0, -0.0, 1e9, -1e9, 0.5, -0.5, 1e-300, -1e-300};
  for (int k = -1000; k <= 1000; ++k) {
    values.push_back(k);
    values.push_back(std::nextafter(static_cast<double>(k), -2e9));
    values.push_back(std::nextafter(static_cast<double>(k), 2e9));
  }
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> wide(-1e9, 1e9);
  std::uniform_real_distribution<double> near(-50.0, 50.0);
  for (int i = 0; i < 100000; ++i) {
    values.push_back(wide(rng));
    values.push_back(near(rng));
  }
  for (const double s : values) {
    EXPECT_EQ(FloorToInt(s), static_cast<int>(std::floor(s))) << s;
  }
}

}  // namespace
}  // namespace statebench::est
