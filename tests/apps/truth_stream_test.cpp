// LastRowStamp: the end of a log's truth for `statebench estimate`'s progress bar, read from the
// file's last 4 KiB. (TruthStream itself is checked end to end by estimate_truth_mount_test:
// `estimate` streams the truth and gives run's errors.csv row for row.)
#include "apps/truth_stream.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <string>

#include "tests/removed_at_exit.hpp"

namespace statebench::app {
namespace {

namespace fs = std::filesystem;

fs::path Write(const fs::path& dir, const std::string& name, const std::string& text) {
  const fs::path p = dir / name;
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

TEST(LastRowStamp, IsTheFirstFieldOfTheLastRow) {
  const fs::path dir = testing::RemovedAtExit(
      fs::temp_directory_path() / ("statebench_last_row_" + std::to_string(getpid())));
  fs::create_directories(dir);
  EXPECT_EQ(LastRowStamp(Write(dir, "a.csv", "t_ns,x\n0,1\n600000000000,2\n")), 600000000000);
  EXPECT_EQ(LastRowStamp(Write(dir, "b.csv", "t_ns,x\r\n5,1\r\n17,2\r\n\r\n")), 17);
  EXPECT_EQ(LastRowStamp(Write(dir, "c.csv", "t_ns,x\n0,1\n42,2")), 42);  // no final newline
  std::string many = "t_ns,x\n";
  for (int i = 0; i < 2000; ++i) many += std::to_string(i * 1000) + ",0.5\n";
  EXPECT_EQ(LastRowStamp(Write(dir, "d.csv", many)), 1999000);
  EXPECT_EQ(LastRowStamp(Write(dir, "e.csv", "t_ns,x\n")), std::nullopt);  // header only
  EXPECT_EQ(LastRowStamp(Write(dir, "f.csv", "")), std::nullopt);
  EXPECT_EQ(LastRowStamp(Write(dir, "g.csv", "t_ns,x\n0,1\n" + std::string(5000, 'y') + "\n")),
            std::nullopt);  // a last row longer than what is read
  EXPECT_EQ(LastRowStamp(dir / "missing.csv"), std::nullopt);
}

}  // namespace
}  // namespace statebench::app
