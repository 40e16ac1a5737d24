// Small CSV helpers shared by every text format StateBench writes and reads.
//
// Numbers are written with std::to_chars in shortest round-trip form, so a value read back is
// bit-identical and the same run writes the same bytes. Readers report "file:line: column 'x': ..."
// through InputError.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace statebench {

// Appends a double in shortest round-trip form ("nan"/"inf" are never written by StateBench).
void AppendNumber(std::string& out, double value);
void AppendNumber(std::string& out, std::int64_t value);
// The same, as a string.
std::string NumberText(double value);
// A YAML double-quoted scalar (", \ and newlines escaped).
std::string YamlQuoted(std::string_view s);

// One parsed CSV data line with its origin, for error messages. Views only: the file name,
// header and cells must outlive it.
class CsvRow {
 public:
  CsvRow(std::string_view file, std::size_t line, const std::vector<std::string>* header,
         std::span<const std::string_view> cells)
      : file_(file), line_(line), header_(header), cells_(cells) {}

  std::size_t size() const { return cells_.size(); }
  double Double(std::size_t column) const;  // rejects NaN/inf and garbage
  std::int64_t Int(std::size_t column) const;
  std::string_view Text(std::size_t column) const;
  [[noreturn]] void Fail(std::size_t column, const std::string& what) const;
  std::string Where() const;

 private:
  std::string_view file_;
  std::size_t line_;
  const std::vector<std::string>* header_;
  std::span<const std::string_view> cells_;
};

// Splits a comma-separated line (no quoting: StateBench files never need it). Trailing '\r' and
// surrounding spaces of each cell are dropped.
std::vector<std::string_view> SplitCsvLine(std::string_view line);
// The same into *cells (cleared first), reusing its storage.
void SplitCsvLine(std::string_view line, std::vector<std::string_view>* cells);

// Reads the header of a CSV file (first line, a leading '#' is allowed) and checks that it holds
// the expected column names in order; throws InputError naming the file and the missing column.
std::vector<std::string> ParseCsvHeader(std::string_view file, std::string_view header_line,
                                        const std::vector<std::string>& expected);

}  // namespace statebench
