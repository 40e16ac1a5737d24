// The stage cache's entries: a pending entry becomes the entry only when published; one dropped
// unpublished (its stage did not complete), or whose writer throws, leaves nothing behind.
#include "core/stage_cache.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace statebench {
namespace {

namespace fs = std::filesystem;

class StageCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() /
            ("statebench_stage_cache_" + std::to_string(getpid()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
  }
  void TearDown() override { fs::remove_all(root_); }

  // Everything under the stage's folder (entries and unfinished folders alike).
  std::vector<fs::path> StageFolder(const std::string& stage) const {
    std::vector<fs::path> found;
    if (fs::exists(root_ / stage)) {
      for (const auto& e : fs::directory_iterator(root_ / stage)) found.push_back(e.path());
    }
    return found;
  }

  fs::path root_;
};

TEST_F(StageCacheTest, APublishedEntryIsFoundAndAnUnpublishedOneLeavesNothing) {
  StageCache cache(root_, 0);
  {
    StageCache::PendingEntry entry = cache.Begin("stage", "kept");
    std::ofstream(entry.folder() / "data") << "bits";
    StageCache::PendingEntry moved = std::move(entry);  // a moved-from entry removes nothing
    const fs::path published = moved.Publish();
    EXPECT_EQ(published, root_ / "stage" / "kept");
  }
  {
    StageCache::PendingEntry entry = cache.Begin("stage", "dropped");
    std::ofstream(entry.folder() / "data") << "half";
    EXPECT_TRUE(fs::exists(entry.folder()));
  }
  EXPECT_THROW(cache.Write("stage", "thrown",
                           [](const fs::path& folder) {
                             std::ofstream(folder / "data") << "half";
                             throw std::runtime_error("the stage failed");
                           }),
               std::runtime_error);
  EXPECT_EQ(StageFolder("stage"), std::vector<fs::path>{root_ / "stage" / "kept"});
  const auto found = cache.Find("stage", "kept");
  ASSERT_TRUE(found.has_value());
  std::string bits;
  std::ifstream(*found / "data") >> bits;
  EXPECT_EQ(bits, "bits");
  EXPECT_FALSE(cache.Find("stage", "dropped").has_value());
  EXPECT_EQ(cache.counts().at("stage").hits, 1);
  EXPECT_EQ(cache.counts().at("stage").misses, 1);
}

}  // namespace
}  // namespace statebench
