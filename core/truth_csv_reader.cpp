#include "core/truth_csv_reader.hpp"

#include <cmath>

#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/truth_io.hpp"

namespace statebench {

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
