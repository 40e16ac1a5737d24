#include "sensors/log_stream_reader.hpp"

#include <memory>

#include "core/csv.hpp"
#include "core/error.hpp"
#include "sensors/lidar_file.hpp"
#include "sensors/log_csv.hpp"

namespace statebench::sensors {
namespace {

bool IsBlank(const std::string& line) {
  return line.find_first_not_of(" \t\r") == std::string::npos;
}

}  // namespace

LogStreamReader::LogStreamReader(const std::filesystem::path& log_dir, const LogStreamEntry& entry)
    : entry_(entry), path_(log_dir / entry.file), path_text_(path_.string()) {
  sweep_dir_ = path_.parent_path() / path_.stem();
  in_.open(path_, std::ios::binary);
  if (!in_) {
    error_ = path_text_ + ": cannot open (listed in log.yaml for sensor '" + entry_.id + "')";
    done_ = true;
    return;
  }
  std::string header_line;
  line_ = 1;
  if (!std::getline(in_, header_line)) {
    error_ = path_text_ + ":1: empty file (expected the header line)";
    done_ = true;
    return;
  }
  try {
    header_ = ParseCsvHeader(path_text_, header_line, LogCsvColumns(entry_.type));
    layout_ = LogCsvLayoutOf(entry_.type, header_, path_text_);
  } catch (const InputError& e) {
    error_ = e.what();
    done_ = true;
  }
}

std::optional<Measurement> LogStreamReader::Next() {
  if (done_) return std::nullopt;
  std::string line;
  while (std::getline(in_, line)) {
    ++line_;
    if (IsBlank(line)) continue;
    try {
      return ParseLine(line);
    } catch (const InputError& e) {
      error_ = e.what();
      done_ = true;
      return std::nullopt;
    }
  }
  if (in_.bad()) error_ = path_text_ + ":" + std::to_string(line_ + 1) + ": read error";
  done_ = true;
  return std::nullopt;
}

Measurement LogStreamReader::ParseLine(const std::string& line) {
  SplitCsvLine(line, &cells_);
  const CsvRow row(path_text_, line_, &header_, cells_);
  const StampColumns c = StampColumnsOf(entry_.type);
  CheckColumnCount(layout_, row);
  const TimeNs stamp_ns = row.Int(c.stamp);
  const TimeNs arrival_ns = row.Int(c.arrival);
  if (last_stamp_ns_ && stamp_ns <= *last_stamp_ns_) {
    row.Fail(c.stamp, "timestamp " + std::to_string(stamp_ns) + " is not after the previous " +
                          std::to_string(*last_stamp_ns_));
  }
  if (last_stamp_ns_ && arrival_ns < last_arrival_ns_) {
    row.Fail(c.arrival, "arrival " + std::to_string(arrival_ns) + " is before the previous " +
                            std::to_string(last_arrival_ns_) + " (rows must be in arrival order)");
  }
  last_stamp_ns_ = stamp_ns;
  last_arrival_ns_ = arrival_ns;
  if (entry_.type != LogStreamType::kLidar) return ParseLogCsvRow(layout_, entry_.id, row);

  // Lidar index row: stamp, arrival, points, file.
  const std::int64_t count = row.Int(2);
  if (count < 0) row.Fail(2, "must be >= 0");
  const std::string name(row.Text(3));
  if (name.empty() || name.find_first_of("/\\") != std::string::npos || name == "..") {
    row.Fail(3, "expected a sweep or PCD file name in " + sweep_dir_.string());
  }
  LidarScan scan;
  scan.header = MeasurementHeader{entry_.id, stamp_ns, arrival_ns};
  try {
    auto points = std::make_shared<std::vector<LidarPoint>>(ReadLidarFile(sweep_dir_ / name));
    if (points->size() != static_cast<std::size_t>(count)) {
      throw InputError((sweep_dir_ / name).string() + ": holds " + std::to_string(points->size()) +
                       " points, the index says " + std::to_string(count));
    }
    scan.points = std::move(points);
  } catch (const InputError& e) {
    throw InputError(std::string(e.what()) + " (sweep listed at " + row.Where() + ")");
  }
  return scan;
}

}  // namespace statebench::sensors
