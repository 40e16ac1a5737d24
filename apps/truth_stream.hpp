// A log's truth.csv handed to the estimator feed's scorer as the log is read: before each
// message, the truth up to its stamps (so every estimate it releases finds its reference, as if
// the whole truth had been read first), in blocks of samples. The scorer then holds the truth of
// the last instants, not the whole file.
#pragma once

#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "apps/estimator_feed.hpp"
#include "core/truth_csv_reader.hpp"

namespace statebench::app {

class TruthStream {
 public:
  // Opens the file (reading stage); empty() when it holds no sample (an error says why).
  explicit TruthStream(const std::filesystem::path& truth_csv);

  bool empty() const { return !first_ns_.has_value(); }
  const std::optional<TimeNs>& first_ns() const { return first_ns_; }

  // Hands the feed the truth until its newest sample is at or after t_ns, or the file ends.
  void FeedUpTo(TimeNs t_ns, EstimatorFeed& feed);
  // Hands the feed the rest of the file.
  void FeedRest(EstimatorFeed& feed) { FeedUpTo(kForever, feed); }

  // The file's problem, if reading stopped at one (the samples before it were handed on).
  const std::optional<std::string>& error() const { return reader_.error(); }

 private:
  static constexpr TimeNs kForever = std::numeric_limits<TimeNs>::max();

  TruthCsvReader reader_;
  std::vector<TruthSample> block_;  // read, not handed on yet
  std::optional<TimeNs> first_ns_;
  std::optional<TimeNs> newest_fed_ns_;
  bool done_ = false;
};

// The stamp of the last row of a CSV file whose rows start with an integer stamp (the last
// 4 KiB are read); nullopt when it has none. For a progress bar's end, not for results.
std::optional<TimeNs> LastRowStamp(const std::filesystem::path& csv);

}  // namespace statebench::app
