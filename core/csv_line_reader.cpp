#include "core/csv_line_reader.hpp"

#include <cstring>

namespace statebench {

CsvLineReader::CsvLineReader(const std::filesystem::path& path, std::size_t block_bytes)
    : in_(path, std::ios::binary), block_bytes_(block_bytes < 16 ? 16 : block_bytes) {
  open_ = static_cast<bool>(in_);
  eof_ = !open_;
}

// Moves the unread tail to the front and appends the next block; false when nothing was added.
bool CsvLineReader::Refill() {
  if (eof_) return false;
  const std::size_t tail = end_ - begin_;
  if (begin_ > 0 && tail > 0) std::memmove(buffer_.data(), buffer_.data() + begin_, tail);
  begin_ = 0;
  end_ = tail;
  if (buffer_.size() < tail + block_bytes_) buffer_.resize(tail + block_bytes_);
  in_.read(buffer_.data() + end_, static_cast<std::streamsize>(block_bytes_));
  const auto got = static_cast<std::size_t>(in_.gcount());
  end_ += got;
  if (!in_) {
    eof_ = true;
    bad_ = in_.bad();
  }
  return got > 0;
}

std::optional<std::string_view> CsvLineReader::Next() {
  std::size_t scanned = begin_;  // bytes before it hold no '\n'
  while (true) {
    const char* base = buffer_.data();
    const void* nl = scanned < end_ ? std::memchr(base + scanned, '\n', end_ - scanned) : nullptr;
    if (nl != nullptr) {
      const std::size_t at = static_cast<const char*>(nl) - base;
      const std::string_view line(base + begin_, at - begin_);
      begin_ = at + 1;
      ++line_number_;
      return line;
    }
    const std::size_t offset = end_ - begin_;  // the tail moves to the front
    if (!Refill()) break;
    scanned = offset;
  }
  if (begin_ == end_ || bad_) return std::nullopt;
  const std::string_view last(buffer_.data() + begin_, end_ - begin_);  // no final '\n'
  begin_ = end_;
  ++line_number_;
  return last;
}

}  // namespace statebench
