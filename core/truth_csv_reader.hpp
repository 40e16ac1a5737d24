// Reads truth.csv (written by TruthWriter, columns in docs/truth-format.md) sample by sample, so
// that a long truth can be streamed into a consumer instead of held whole: a ten-minute drive at
// 1 kHz is 600 000 samples, over half a gigabyte of text.
//
// Every value is checked: the header's columns, numbers that parse and are finite, a unit
// quaternion, stamps strictly increasing. Errors do not throw: the first bad row ends the
// stream, Next() returns nothing and error() holds "file:line: column 'x': ...". Every sample
// before the bad row has been returned.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/csv_line_reader.hpp"
#include "core/truth.hpp"

namespace statebench {

class TruthCsvReader {
 public:
  // Opens path and checks its header (error() says what is wrong).
  explicit TruthCsvReader(const std::filesystem::path& path);

  std::optional<TruthSample> Next();
  const std::optional<std::string>& error() const { return error_; }

 private:
  TruthSample ParseLine(std::string_view line);

  std::string file_;
  CsvLineReader lines_;
  std::vector<std::string> header_;
  std::vector<std::string_view> cells_;  // of the row being parsed (storage reused)
  std::optional<TimeNs> last_ns_;
  std::optional<std::string> error_;
  bool done_ = false;
};

struct TruthReadResult {
  std::vector<TruthSample> samples;  // everything read before an error, if any
  std::optional<std::string> error;  // "file:line: column 'x': ..."
};

// The whole file (TruthCsvReader's checks).
TruthReadResult ReadTruthCsv(const std::filesystem::path& path);

}  // namespace statebench
