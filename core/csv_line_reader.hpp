// Reads a text file line by line through one large buffer: no allocation per line, lines handed
// out as views into the buffer (valid until the next call). For the long CSV files of a log (the
// 1 kHz truth of a ten-minute drive is over half a gigabyte), where std::getline into a string
// and a stream's small reads were a visible share of reading.
#pragma once

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>

namespace statebench {

class CsvLineReader {
 public:
  // Opens path; is_open() tells whether that worked.
  explicit CsvLineReader(const std::filesystem::path& path, std::size_t block_bytes = 1 << 20);

  bool is_open() const { return open_; }
  // The next line without its '\n' (a '\r' before it is kept, as std::getline does), or nothing
  // at the end of the file or on a read error (bad()).
  std::optional<std::string_view> Next();
  // 1-based number of the line Next() returned last.
  std::size_t line_number() const { return line_number_; }
  bool bad() const { return bad_; }

 private:
  bool Refill();

  std::ifstream in_;
  std::string buffer_;
  std::size_t begin_ = 0;  // first byte not handed out yet
  std::size_t end_ = 0;    // end of the valid bytes
  std::size_t block_bytes_;
  std::size_t line_number_ = 0;
  bool open_ = false;
  bool eof_ = false;
  bool bad_ = false;
};

}  // namespace statebench
