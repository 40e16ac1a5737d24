#include "core/csv.hpp"

#include <charconv>
#include <cmath>

#include "core/error.hpp"

namespace statebench {
namespace {

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) {
    s.remove_suffix(1);
  }
  return s;
}

}  // namespace

void AppendNumber(std::string& out, double value) {
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof(buf), value);
  out.append(buf, static_cast<std::size_t>(res.ptr - buf));  // not the iterator overload: replace()
}

std::string NumberText(double value) {
  std::string out;
  AppendNumber(out, value);
  return out;
}

std::string YamlQuoted(std::string_view s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (c == '\n') {
      out += "\\n";
    } else {
      out += c;
    }
  }
  return out + "\"";
}

void AppendNumber(std::string& out, std::int64_t value) {
  char buf[24];
  const auto res = std::to_chars(buf, buf + sizeof(buf), value);
  out.append(buf, static_cast<std::size_t>(res.ptr - buf));  // not the iterator overload: replace()
}

std::vector<std::string_view> SplitCsvLine(std::string_view line) {
  std::vector<std::string_view> cells;
  SplitCsvLine(line, &cells);
  return cells;
}

void SplitCsvLine(std::string_view line, std::vector<std::string_view>* cells) {
  cells->clear();
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    if (comma == std::string_view::npos) {
      cells->push_back(Trim(line.substr(start)));
      break;
    }
    cells->push_back(Trim(line.substr(start, comma - start)));
    start = comma + 1;
  }
}

std::vector<std::string> ParseCsvHeader(std::string_view file, std::string_view header_line,
                                        const std::vector<std::string>& expected) {
  std::string_view h = Trim(header_line);
  if (!h.empty() && h.front() == '#') h.remove_prefix(1);
  std::vector<std::string> names;
  for (const auto cell : SplitCsvLine(h)) names.emplace_back(Trim(cell));
  for (std::size_t i = 0; i < expected.size(); ++i) {
    if (i >= names.size() || names[i] != expected[i]) {
      throw InputError(std::string(file) + ":1: missing column '" + expected[i] +
                       "' (expected at position " + std::to_string(i + 1) + ")");
    }
  }
  return names;
}

std::string CsvRow::Where() const { return std::string(file_) + ":" + std::to_string(line_); }

void CsvRow::Fail(std::size_t column, const std::string& what) const {
  const std::string name = header_ && column < header_->size() ? (*header_)[column]
                                                               : std::to_string(column + 1);
  throw InputError(Where() + ": column '" + name + "': " + what);
}

std::string_view CsvRow::Text(std::size_t column) const {
  if (column >= cells_.size()) Fail(column, "missing value");
  return cells_[column];
}

double CsvRow::Double(std::size_t column) const {
  if (column >= cells_.size()) Fail(column, "missing value");
  const std::string_view s = cells_[column];
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || ptr != s.data() + s.size() || s.empty()) {
    Fail(column, "expected a number, got '" + std::string(s) + "'");
  }
  if (!std::isfinite(v)) Fail(column, "value is not finite ('" + std::string(s) + "')");
  return v;
}

std::int64_t CsvRow::Int(std::size_t column) const {
  if (column >= cells_.size()) Fail(column, "missing value");
  const std::string_view s = cells_[column];
  std::int64_t v = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || ptr != s.data() + s.size() || s.empty()) {
    Fail(column, "expected an integer, got '" + std::string(s) + "'");
  }
  return v;
}

}  // namespace statebench
