#include "apps/progress_bar.hpp"

#include <algorithm>
#include <unistd.h>

namespace statebench::app {

ProgressBar::ProgressBar(std::string label)
    : label_(std::move(label)),
      is_tty_(isatty(fileno(stderr)) != 0),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_ - std::chrono::seconds(1)) {}

void ProgressBar::Update(double fraction, const std::string& detail) {
  fraction = std::clamp(fraction, 0.0, 1.0);
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (is_tty_) {
    if (now - last_draw_ < std::chrono::milliseconds(100) && fraction < 1.0) return;
    last_draw_ = now;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(fraction * kWidth);
    std::string bar(filled, '#');
    bar.resize(kWidth, '.');
    std::fprintf(stderr, "\r%s [%s] %5.1f%% %6.1fs %s\033[K", label_.c_str(), bar.c_str(),
                 100.0 * fraction, elapsed, detail.c_str());
  } else {
    const int decile = static_cast<int>(fraction * 10.0);
    if (decile == last_decile_) return;
    last_decile_ = decile;
    std::fprintf(stderr, "%s %3d%% %6.1fs %s\n", label_.c_str(), decile * 10, elapsed,
                 detail.c_str());
  }
  std::fflush(stderr);
}

void ProgressBar::Finish(const std::string& detail) {
  Update(1.0, detail);
  if (is_tty_) std::fprintf(stderr, "\n");
}

}  // namespace statebench::app
