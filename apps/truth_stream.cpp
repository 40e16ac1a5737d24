#include "apps/truth_stream.hpp"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <limits>
#include <span>

#include "core/stage_profile.hpp"

namespace statebench::app {
namespace {

// Samples per block: one stage switch per block, not two per sample.
constexpr std::size_t kTruthBlock = 1024;

}  // namespace

TruthStream::TruthStream(const std::filesystem::path& truth_csv) : reader_(truth_csv) {
  const StageScope stage(Stage::kReading);
  block_.reserve(kTruthBlock);
  if (std::optional<TruthSample> s = reader_.Next()) {
    first_ns_ = s->t_ns;
    block_.push_back(*s);
  } else {
    done_ = true;
  }
}

void TruthStream::FeedUpTo(TimeNs t_ns, EstimatorFeed& feed) {
  while (!(newest_fed_ns_ && *newest_fed_ns_ >= t_ns)) {
    if (block_.empty()) {
      if (done_) return;
      const StageScope stage(Stage::kReading);
      while (block_.size() < kTruthBlock) {
        std::optional<TruthSample> s = reader_.Next();
        if (!s) {
          done_ = true;
          break;
        }
        block_.push_back(*s);
      }
      if (block_.empty()) return;
    }
    feed.AddTruth(std::span<const TruthSample>(block_));
    newest_fed_ns_ = block_.back().t_ns;
    block_.clear();
  }
}

std::optional<TimeNs> LastRowStamp(const std::filesystem::path& csv) {
  std::ifstream in(csv, std::ios::binary | std::ios::ate);
  if (!in) return std::nullopt;
  const std::streamoff size = in.tellg();
  const std::streamoff take = std::min<std::streamoff>(size, 4096);
  std::string tail(static_cast<std::size_t>(take), '\0');
  in.seekg(size - take);
  if (!in.read(tail.data(), take)) return std::nullopt;
  while (!tail.empty() && (tail.back() == '\n' || tail.back() == '\r')) tail.pop_back();
  const std::size_t begin = tail.rfind('\n');
  if (begin == std::string::npos && take < size) return std::nullopt;  // a row over 4 KiB
  const std::string_view row =
      std::string_view(tail).substr(begin == std::string::npos ? 0 : begin + 1);
  TimeNs t = 0;
  const auto [end, ec] = std::from_chars(row.data(), row.data() + row.size(), t);
  if (ec != std::errc() || end == row.data()) return std::nullopt;
  return t;
}

}  // namespace statebench::app
