#include "sensors/log_reader.hpp"

namespace statebench::sensors {

LogReader::LogReader(const std::filesystem::path& dir)
    : dir_(dir), manifest_(ReadLogManifest(dir / "log.yaml")) {
  for (const LogStreamEntry& entry : manifest_.streams) {
    streams_.push_back(std::make_unique<LogStreamReader>(dir_, entry));
  }
  heads_.resize(streams_.size());
  for (std::size_t i = 0; i < streams_.size() && !error_; ++i) Refill(i);
}

void LogReader::Refill(std::size_t stream) {
  heads_[stream] = streams_[stream]->Next();
  if (!heads_[stream] && streams_[stream]->error()) error_ = streams_[stream]->error();
}

std::optional<Measurement> LogReader::Next() {
  if (error_) return std::nullopt;
  // Linear scan over the heads: a vehicle has a handful of sensors.
  std::optional<std::size_t> best;
  for (std::size_t i = 0; i < heads_.size(); ++i) {
    if (!heads_[i]) continue;
    if (!best || ArrivesBefore(*heads_[i], *heads_[*best])) best = i;
  }
  if (!best) return std::nullopt;
  Measurement m = std::move(*heads_[*best]);
  Refill(*best);
  return m;
}

std::optional<std::filesystem::path> LogReader::setup_file() const {
  if (!manifest_.setup) return std::nullopt;
  return dir_ / *manifest_.setup;
}

}  // namespace statebench::sensors
