// Temporary folders a test program hands out under fixed names (so a failed run can be looked
// at while it lasts) and removes when the program ends.
#pragma once

#include <filesystem>
#include <vector>

namespace statebench::testing {

struct FoldersRemovedAtExit {
  std::vector<std::filesystem::path> dirs;
  ~FoldersRemovedAtExit() {
    std::error_code ec;
    for (const auto& dir : dirs) std::filesystem::remove_all(dir, ec);
  }
};

// Registers `dir` for removal when the test program ends; returns it.
inline std::filesystem::path RemovedAtExit(const std::filesystem::path& dir) {
  static FoldersRemovedAtExit folders;
  folders.dirs.push_back(dir);
  return dir;
}

}  // namespace statebench::testing
