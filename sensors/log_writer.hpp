// Writes a recorded log directory (docs/log-format.md) from a measurement stream: per sensor a
// CSV file in the folder of its type (imu/, gnss/, heading/, wheels/, speed/, steering/,
// body_velocity/), per lidar a sweep index lidar/<id>.csv plus one file per sweep in
// lidar/<id>/<stamp_ns>.packets (or .sweep or .pcd: LogWriterOptions::lidar_format, WriteLidarFile),
// the sensor setup as setup.yaml, optionally the truth (truth.csv,
// truth_body.tum, truth_imu.tum via core/truth_io.hpp), and the manifest log.yaml last.
//
// Numbers are written in shortest round-trip form and lidar points as raw floats, so LogReader
// gives back exactly the measurements written.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/geodetic.hpp"
#include "core/measurements.hpp"
#include "core/se3.hpp"
#include "core/truth.hpp"
#include "sensors/lidar_file.hpp"
#include "sensors/log_manifest.hpp"

namespace statebench {
class TruthWriter;
}

namespace statebench::sensors {

struct LogWriterOptions {
  std::string scenario;
  std::optional<std::uint64_t> seed;
  std::optional<GeodeticPoint> origin;
  std::string setup_yaml;               // copied to setup.yaml when not empty
  std::optional<SE3> truth_T_body_imu;  // when set, WriteTruth writes the truth files
  LidarFileFormat lidar_format = LidarFileFormat::kPcd;  // the files of the lidar sweeps
  // Beam models of the lidars, by sensor id: the packets format needs the sweep's (without one,
  // a sweep is written as a sweep file; lidar_file.hpp).
  std::map<std::string, LidarBeamModel> lidar_beams;
  // GNSS sensors whose files get the velocity columns (docs/log-format.md); a stream whose
  // first fix carries a velocity gets them too.
  std::set<std::string> gnss_velocity_ids;
};

struct LogStreamStats {
  std::string id;
  LogStreamType type = LogStreamType::kImu;
  std::size_t count = 0;
  std::size_t lidar_points = 0;
};

class LogWriter {
 public:
  // Creates `dir` (and its parents). Throws InputError if it already holds a log (log.yaml) or
  // cannot be created.
  LogWriter(const std::filesystem::path& dir, LogWriterOptions options);
  ~LogWriter();  // without Close() the files are flushed but no manifest is written
  LogWriter(const LogWriter&) = delete;
  LogWriter& operator=(const LogWriter&) = delete;

  // Measurements of one sensor must come with strictly increasing stamps and non-decreasing
  // arrivals, and keep their type; throws InputError otherwise (the log would not read back),
  // and for a fix with a velocity in a gnss file without the velocity columns.
  void Write(const Measurement& m);
  // Throws InputError if the options gave no truth_T_body_imu.
  void WriteTruth(const TruthSample& sample);

  // Writes setup.yaml (replacing the options' setup_yaml) and lists it in the manifest, for
  // writers that know the setup only after the measurements (a bag import). Before Close().
  void WriteSetup(const std::string& setup_yaml);

  // Flushes and closes every file and writes log.yaml; throws InputError on a failed write.
  const LogManifest& Close();

  // Per stream, in order of first appearance.
  std::vector<LogStreamStats> stats() const;
  const std::filesystem::path& dir() const { return dir_; }

 private:
  struct Stream;
  Stream& StreamFor(const Measurement& m);
  void WriteLidar(Stream& s, const LidarScan& scan);

  std::filesystem::path dir_;
  LogWriterOptions options_;
  std::vector<std::unique_ptr<Stream>> streams_;
  std::map<std::string, Stream*> by_id_;
  std::unique_ptr<TruthWriter> truth_;
  LogManifest manifest_;
  bool closed_ = false;
};

}  // namespace statebench::sensors
