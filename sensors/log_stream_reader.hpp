// Reads one stream file of a recorded log (a sensor's CSV, or a lidar's sweep index with its PCD
// files) row by row, checking every value: the header's columns, numbers that parse and are
// finite, stamps strictly increasing and arrivals non-decreasing, each lidar sweep's PCD complete
// and holding the number of points its index row announces.
//
// Errors do not throw: the first bad row ends the stream, Next() returns nothing and error()
// holds "file:line: column 'x': ..." (for a PCD: the PCD file and the index line listing it).
// Everything before the bad row has been returned.
#pragma once

#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/measurements.hpp"
#include "sensors/log_format.hpp"
#include "sensors/log_manifest.hpp"

namespace statebench::sensors {

class LogStreamReader {
 public:
  LogStreamReader(const std::filesystem::path& log_dir, const LogStreamEntry& entry);

  // The next measurement of the file, or nothing at its end or at the first error.
  std::optional<Measurement> Next();

  const std::optional<std::string>& error() const { return error_; }
  const LogStreamEntry& entry() const { return entry_; }

 private:
  Measurement ParseLine(const std::string& line);

  LogStreamEntry entry_;
  std::filesystem::path path_;
  std::string path_text_;
  std::filesystem::path sweep_dir_;  // lidar: the index path without ".csv", holding the sweeps
  std::ifstream in_;
  std::vector<std::string> header_;
  LogCsvLayout layout_;
  std::vector<std::string_view> cells_;  // of the row being parsed (storage reused)
  std::size_t line_ = 0;
  bool done_ = false;
  std::optional<std::string> error_;
  std::optional<TimeNs> last_stamp_ns_;
  TimeNs last_arrival_ns_ = 0;
};

}  // namespace statebench::sensors
