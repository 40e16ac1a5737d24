// Test helper: whether one of the lines (e.g. EstimatorDiagnostics::warnings) contains a text.
#pragma once

#include <string>
#include <vector>

namespace statebench::est::testing {

inline bool AnyContains(const std::vector<std::string>& lines, const std::string& text) {
  for (const std::string& l : lines) {
    if (l.find(text) != std::string::npos) return true;
  }
  return false;
}

}  // namespace statebench::est::testing
