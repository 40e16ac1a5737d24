#include "core/truth_csv_reader.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>

#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/truth_io.hpp"

namespace statebench {
namespace {

// The row parsed in one pass over the line, without splitting it into cells: the common case of
// a file TruthWriter wrote (no spaces, every number plain). Returns false as soon as anything
// differs from that (a space, an empty or non-numeric cell, a non-finite value, too few cells, a
// stamp that does not increase, a quaternion off unit norm): the caller then parses the line
// cell by cell, which accepts exactly what this accepts, with the same values (the same
// std::from_chars on the same characters), and words the error otherwise.
class TruthLineScanner {
 public:
  explicit TruthLineScanner(std::string_view line)
      : at_(line.data()), end_(line.data() + line.size()) {}

  // The number at the cursor, which must end at a ','; the cursor moves past the comma.
  template <typename T>
  bool Number(T* value) {
    const auto [ptr, ec] = std::from_chars(at_, end_, *value);
    if (ec != std::errc() || ptr == at_ || ptr == end_ || *ptr != ',') return false;
    at_ = ptr + 1;
    return true;
  }
  bool Finite(double* value) { return Number(value) && std::isfinite(*value); }
  bool Vector(Vec3* v) { return Finite(&v->x()) && Finite(&v->y()) && Finite(&v->z()); }
  // Moves past the next n commas.
  bool Skip(int n) {
    for (int i = 0; i < n; ++i) {
      const void* comma = std::memchr(at_, ',', static_cast<std::size_t>(end_ - at_));
      if (comma == nullptr) return false;
      at_ = static_cast<const char*>(comma) + 1;
    }
    return true;
  }
  // Cells from the cursor to the end of the line.
  std::size_t CellsLeft() const { return static_cast<std::size_t>(std::count(at_, end_, ',')) + 1; }

 private:
  const char* at_;
  const char* end_;
};

// The fields TruthCsvReader::ParseLine reads, in the same column order, with its checks.
bool ScanTruthLine(std::string_view line, std::size_t columns, std::optional<TimeNs> last_ns,
                   TruthSample* s) {
  TruthLineScanner scan(line);
  std::int64_t t_ns = 0;
  Vec3 p;
  double qw = 0.0, qx = 0.0, qy = 0.0, qz = 0.0;
  if (!scan.Number(&t_ns) || (last_ns && t_ns <= *last_ns)) return false;
  if (!scan.Vector(&p) || !scan.Finite(&qw) || !scan.Finite(&qx) || !scan.Finite(&qy) ||
      !scan.Finite(&qz)) {
    return false;
  }
  const Quat q(qw, qx, qy, qz);
  if (std::abs(q.norm() - 1.0) > 1e-6) return false;
  s->t_ns = t_ns;
  s->body.T_world_frame = SE3(q, p);
  if (!scan.Vector(&s->body.v_world) || !scan.Vector(&s->body.a_world) ||
      !scan.Vector(&s->body.omega_frame) || !scan.Vector(&s->body.alpha_frame) ||
      !scan.Skip(6) || !scan.Finite(&s->steering_front_rad) ||
      !scan.Finite(&s->steering_rear_rad)) {
    return false;
  }
  for (double& w : s->wheel_omega_radps) {
    if (!scan.Finite(&w)) return false;
  }
  constexpr std::size_t kColumnsRead = 34;  // t_ns .. distance
  return scan.Finite(&s->sideslip_rad) && scan.Finite(&s->distance_m) &&
         kColumnsRead + scan.CellsLeft() >= columns;
}

}  // namespace

TruthCsvReader::TruthCsvReader(const std::filesystem::path& path)
    : file_(path.string()), lines_(path) {
  done_ = true;
  if (!lines_.is_open()) {
    error_ = file_ + ": cannot open";
    return;
  }
  const std::optional<std::string_view> header_line = lines_.Next();
  if (!header_line) {
    error_ = file_ + ":1: empty file, expected a header";
    return;
  }
  try {
    header_ = ParseCsvHeader(file_, *header_line, TruthCsvColumns());
  } catch (const InputError& e) {
    error_ = e.what();
    return;
  }
  done_ = false;
}

std::optional<TruthSample> TruthCsvReader::Next() {
  if (done_) return std::nullopt;
  while (const std::optional<std::string_view> line = lines_.Next()) {
    if (line->empty() || *line == "\r") continue;
    try {
      TruthSample s = ParseLine(*line);
      last_ns_ = s.t_ns;
      return s;
    } catch (const InputError& e) {
      error_ = e.what();
      done_ = true;
      return std::nullopt;
    }
  }
  if (lines_.bad()) error_ = file_ + ":" + std::to_string(lines_.line_number() + 1) + ": read error";
  done_ = true;
  return std::nullopt;
}

TruthSample TruthCsvReader::ParseLine(std::string_view line) {
  TruthSample fast;
  if (ScanTruthLine(line, header_.size(), last_ns_, &fast)) return fast;
  SplitCsvLine(line, &cells_);
  const CsvRow row(file_, lines_.line_number(), &header_, cells_);
  if (row.size() < header_.size()) row.Fail(row.size(), "missing value (row too short)");
  std::size_t c = 0;
  auto vec = [&row, &c] {
    const Vec3 v(row.Double(c), row.Double(c + 1), row.Double(c + 2));
    c += 3;
    return v;
  };
  TruthSample s;
  s.t_ns = row.Int(c++);
  if (last_ns_ && s.t_ns <= *last_ns_) {
    row.Fail(0, "timestamp does not increase (previous " + std::to_string(*last_ns_) + ")");
  }
  const Vec3 p = vec();
  const Quat q(row.Double(c), row.Double(c + 1), row.Double(c + 2), row.Double(c + 3));
  c += 4;
  if (std::abs(q.norm() - 1.0) > 1e-6) row.Fail(c - 4, "quaternion is not of unit norm");
  s.body.T_world_frame = SE3(q, p);
  s.body.v_world = vec();
  s.body.a_world = vec();
  s.body.omega_frame = vec();
  s.body.alpha_frame = vec();
  c += 6;  // v_body and f_body are derived from the columns above
  s.steering_front_rad = row.Double(c++);
  s.steering_rear_rad = row.Double(c++);
  for (double& w : s.wheel_omega_radps) w = row.Double(c++);
  s.sideslip_rad = row.Double(c++);
  s.distance_m = row.Double(c++);
  return s;
}

TruthReadResult ReadTruthCsv(const std::filesystem::path& path) {
  TruthReadResult result;
  TruthCsvReader reader(path);
  while (std::optional<TruthSample> s = reader.Next()) result.samples.push_back(*s);
  result.error = reader.error();
  return result;
}

}  // namespace statebench
