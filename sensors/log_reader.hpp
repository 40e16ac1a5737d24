// Streams a recorded log directory (docs/log-format.md) back as one measurement stream in
// arrival order: the files listed in log.yaml merged by ArrivesBefore (measurement_stream.hpp),
// ties between files broken by their order in the manifest. A log written by LogWriter reads
// back as exactly the stream that was written, bit for bit.
//
// Bad input: a problem with log.yaml itself throws InputError from the constructor (there is
// nothing to stream). A problem inside a stream file (missing column, non-number, NaN, timestamp
// going backwards, truncated or missing PCD, ...) stops the stream: every measurement merged
// before the failing file's bad row has been returned, Next() then returns nothing and error()
// names the file, the line and the column. Precisely: the stream ends right after the failing
// file's last good measurement (measurements of other files arriving after it are not
// returned, since the bad row's own time is unknown).
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sensors/log_manifest.hpp"
#include "sensors/log_stream_reader.hpp"
#include "sensors/measurement_stream.hpp"

namespace statebench::sensors {

class LogReader : public MeasurementSource {
 public:
  explicit LogReader(const std::filesystem::path& dir);

  std::optional<Measurement> Next() override;

  // Set once a stream file was found bad; the stream has then ended.
  const std::optional<std::string>& error() const { return error_; }
  const LogManifest& manifest() const { return manifest_; }
  const std::filesystem::path& dir() const { return dir_; }
  // The log's sensor-setup file (nullopt when the manifest lists none).
  std::optional<std::filesystem::path> setup_file() const;

 private:
  void Refill(std::size_t stream);

  std::filesystem::path dir_;
  LogManifest manifest_;
  std::vector<std::unique_ptr<LogStreamReader>> streams_;
  std::vector<std::optional<Measurement>> heads_;
  std::optional<std::string> error_;
};

}  // namespace statebench::sensors
