// Terminal progress bar for long commands (apps/ only: the libraries report progress through
// callbacks and never print).
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

namespace statebench::app {

class ProgressBar {
 public:
  // Draws on stderr; redraws at most every 100 ms. When stderr is not a terminal (CI logs) it
  // prints a line every 10 %.
  explicit ProgressBar(std::string label);
  void Update(double fraction, const std::string& detail = "");
  void Finish(const std::string& detail = "");

 private:
  std::string label_;
  bool is_tty_;
  int last_decile_ = -1;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace statebench::app
