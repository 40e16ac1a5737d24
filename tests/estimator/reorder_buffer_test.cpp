#include "estimator/reorder_buffer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

namespace statebench::est {
namespace {

ImuSample Imu(TimeNs t) {
  ImuSample s;
  s.header.sensor_id = "imu";
  s.header.stamp_ns = t;
  return s;
}

GnssFix Fix(const std::string& id, TimeNs t) {
  GnssFix f;
  f.header.sensor_id = id;
  f.header.stamp_ns = t;
  return f;
}

std::vector<std::pair<TimeNs, std::string>> Keys(const std::vector<Measurement>& v) {
  std::vector<std::pair<TimeNs, std::string>> out;
  for (const auto& m : v) out.emplace_back(HeaderOf(m).stamp_ns, HeaderOf(m).sensor_id);
  return out;
}

TEST(ReorderBuffer, ReleasesInStampOrderWhateverTheArrivalOrder) {
  std::vector<Measurement> arrivals = {Imu(10), Fix("b", 30), Imu(20), Fix("a", 30), Fix("b", 10),
                                       Imu(30), Fix("a", 25), Imu(40), Fix("a", 45)};
  std::vector<std::vector<std::pair<TimeNs, std::string>>> results;
  std::sort(arrivals.begin(), arrivals.end(), [](const auto& x, const auto& y) {
    return HeaderOf(x).sensor_id < HeaderOf(y).sensor_id;
  });
  do {
    ReorderBuffer buffer;
    for (const auto& m : arrivals) buffer.Push(m);
    auto first = Keys(buffer.Release(30));
    EXPECT_EQ(buffer.size(), 2u);  // 40 and 45 held
    EXPECT_EQ(buffer.watermark_ns(), 30);
    EXPECT_TRUE(buffer.Release(29).empty());  // the watermark does not move back
    auto rest = Keys(buffer.Release(100));
    first.insert(first.end(), rest.begin(), rest.end());
    results.push_back(first);
  } while (std::next_permutation(
      arrivals.begin(), arrivals.end(),
      [](const auto& x, const auto& y) { return HeaderOf(x).sensor_id < HeaderOf(y).sensor_id; }));
  const std::vector<std::pair<TimeNs, std::string>> expected = {
      {10, "imu"}, {10, "b"}, {20, "imu"}, {25, "a"}, {30, "imu"},
      {30, "a"},   {30, "b"}, {40, "imu"}, {45, "a"}};
  ASSERT_GT(results.size(), 10u);
  for (const auto& r : results) EXPECT_EQ(r, expected);
}

}  // namespace
}  // namespace statebench::est
