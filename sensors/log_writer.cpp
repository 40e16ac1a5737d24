#include "sensors/log_writer.hpp"

#include <fstream>

#include "core/error.hpp"
#include "core/stage_profile.hpp"
#include "core/truth_io.hpp"
#include "sensors/lidar_file.hpp"
#include "sensors/log_csv.hpp"

namespace statebench::sensors {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kFlushBytes = 1 << 20;

std::string HeaderLine(const LogCsvLayout& layout) {
  std::string line = "#";
  const auto columns = layout.Columns();
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (i > 0) line += ',';
    line += columns[i];
  }
  return line + "\n";
}

}  // namespace

struct LogWriter::Stream {
  LogStreamEntry entry;
  LogCsvLayout layout;
  fs::path path;
  std::ofstream out;
  std::string buffer;
  std::optional<TimeNs> last_stamp_ns;
  TimeNs last_arrival_ns = 0;
  std::size_t lidar_points = 0;

  void Flush() {
    out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    buffer.clear();
    if (!out) throw InputError(path.string() + ": write failed");
  }
};

LogWriter::LogWriter(const fs::path& dir, LogWriterOptions options)
    : dir_(dir), options_(std::move(options)) {
  std::error_code ec;
  if (fs::exists(dir_ / "log.yaml", ec)) {
    throw InputError(dir_.string() +
                     ": already holds a log (log.yaml); remove it or choose another directory");
  }
  fs::create_directories(dir_, ec);
  if (ec) throw InputError(dir_.string() + ": cannot create the log directory: " + ec.message());
  manifest_.scenario = options_.scenario;
  manifest_.seed = options_.seed;
  manifest_.origin = options_.origin;
  if (!options_.setup_yaml.empty()) WriteSetup(options_.setup_yaml);
  if (options_.truth_T_body_imu) {
    truth_ = std::make_unique<TruthWriter>(dir_, *options_.truth_T_body_imu);
    manifest_.truth_csv = "truth.csv";
    manifest_.truth_imu_mount = *options_.truth_T_body_imu;
  }
}

LogWriter::~LogWriter() {
  if (closed_) return;
  try {
    for (auto& s : streams_) s->Flush();
    if (truth_) truth_->Close();
  } catch (const std::exception&) {  // a destructor must not throw; Close() reports errors
  }
}

LogWriter::Stream& LogWriter::StreamFor(const Measurement& m) {
  const MeasurementHeader& h = HeaderOf(m);
  const LogStreamType type = StreamTypeOf(m);
  if (const auto it = by_id_.find(h.sensor_id); it != by_id_.end()) {
    if (it->second->entry.type != type) {
      throw InputError("log: sensor '" + h.sensor_id + "' gave a " +
                       std::string(LogStreamTypeName(type)) + " after " +
                       std::string(LogStreamTypeName(it->second->entry.type)) + " measurements");
    }
    return *it->second;
  }
  if (h.sensor_id.empty() || h.sensor_id.find_first_of("/\\") != std::string::npos ||
      h.sensor_id == "." || h.sensor_id == "..") {
    throw InputError("log: sensor id '" + h.sensor_id + "' cannot name a file");
  }
  auto s = std::make_unique<Stream>();
  s->entry.id = h.sensor_id;
  s->entry.type = type;
  const fs::path folder(LogStreamFolder(type));
  s->entry.file = (folder / (h.sensor_id + ".csv")).generic_string();
  s->path = dir_ / s->entry.file;
  std::error_code ec;
  fs::create_directories(s->path.parent_path(), ec);
  if (type == LogStreamType::kLidar) fs::create_directories(dir_ / folder / h.sensor_id, ec);
  if (ec) throw InputError(s->path.parent_path().string() + ": cannot create: " + ec.message());
  s->out.open(s->path, std::ios::binary | std::ios::trunc);
  if (!s->out) throw InputError(s->path.string() + ": cannot create");
  s->layout.type = type;
  if (const auto* fix = std::get_if<GnssFix>(&m)) {
    s->layout.gnss_velocity =
        fix->velocity.has_value() || options_.gnss_velocity_ids.contains(h.sensor_id);
  }
  s->buffer = HeaderLine(s->layout);
  Stream& ref = *s;
  by_id_[h.sensor_id] = s.get();
  streams_.push_back(std::move(s));
  return ref;
}

void LogWriter::Write(const Measurement& m) {
  const StageScope stage(Stage::kWriting);
  Stream& s = StreamFor(m);
  const MeasurementHeader& h = HeaderOf(m);
  if (s.last_stamp_ns && (h.stamp_ns <= *s.last_stamp_ns || h.arrival_ns < s.last_arrival_ns)) {
    throw InputError("log: sensor '" + h.sensor_id + "': stamp " + std::to_string(h.stamp_ns) +
                     " / arrival " + std::to_string(h.arrival_ns) +
                     " not after the previous stamp " + std::to_string(*s.last_stamp_ns) +
                     " / arrival " + std::to_string(s.last_arrival_ns));
  }
  s.last_stamp_ns = h.stamp_ns;
  s.last_arrival_ns = h.arrival_ns;
  if (const auto* scan = std::get_if<LidarScan>(&m)) {
    WriteLidar(s, *scan);
  } else {
    const auto* fix = std::get_if<GnssFix>(&m);
    if (fix && fix->velocity && !s.layout.gnss_velocity) {
      throw InputError("log: gnss sensor '" + h.sensor_id +
                       "': a fix with a velocity after fixes without (list the sensor in "
                       "LogWriterOptions::gnss_velocity_ids)");
    }
    AppendLogCsvRow(s.buffer, m, s.layout);
  }
  ++s.entry.count;
  if (s.buffer.size() >= kFlushBytes) s.Flush();
}

void LogWriter::WriteLidar(Stream& s, const LidarScan& scan) {
  static const std::vector<LidarPoint> kNone;
  const std::vector<LidarPoint>& points = scan.points ? *scan.points : kNone;
  const auto beams = options_.lidar_beams.find(s.entry.id);
  const std::string name =
      WriteLidarFile(dir_ / LogStreamFolder(LogStreamType::kLidar) / s.entry.id,
                     std::to_string(scan.header.stamp_ns), points, options_.lidar_format,
                     beams == options_.lidar_beams.end() ? nullptr : &beams->second);
  AppendLidarIndexRow(s.buffer, scan, name);
  s.lidar_points += points.size();
}

void LogWriter::WriteSetup(const std::string& setup_yaml) {
  std::ofstream setup(dir_ / "setup.yaml", std::ios::binary | std::ios::trunc);
  setup << setup_yaml;
  if (!setup) throw InputError((dir_ / "setup.yaml").string() + ": cannot write");
  manifest_.setup = "setup.yaml";
}

void LogWriter::WriteTruth(const TruthSample& sample) {
  if (!truth_) throw InputError("log: no truth mount given (LogWriterOptions::truth_T_body_imu)");
  const StageScope stage(Stage::kWriting);
  truth_->Write(sample);
}

const LogManifest& LogWriter::Close() {
  if (closed_) return manifest_;
  manifest_.streams.clear();
  for (auto& s : streams_) {
    s->Flush();
    s->out.close();
    if (!s->out) throw InputError(s->path.string() + ": write failed");
    manifest_.streams.push_back(s->entry);
  }
  if (truth_) truth_->Close();
  WriteLogManifest(dir_ / "log.yaml", manifest_);
  closed_ = true;
  return manifest_;
}

std::vector<LogStreamStats> LogWriter::stats() const {
  std::vector<LogStreamStats> out;
  for (const auto& s : streams_) {
    out.push_back({s->entry.id, s->entry.type, s->entry.count, s->lidar_points});
  }
  return out;
}

}  // namespace statebench::sensors
