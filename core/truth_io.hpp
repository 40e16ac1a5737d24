// Truth files: truth.csv (every field of TruthSample plus the IMU frame through its mount) and
// TUM trajectories (t tx ty tz qx qy qz qw). Column definitions: docs/truth-format.md.
#pragma once

#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "core/truth.hpp"
#include "core/truth_csv_reader.hpp"  // ReadTruthCsv, for the readers of truth.csv

namespace statebench {

// Column names of truth.csv, in order.
const std::vector<std::string>& TruthCsvColumns();

// Streams truth samples to <dir>/truth.csv, <dir>/truth_body.tum and <dir>/truth_imu.tum.
class TruthWriter {
 public:
  // T_body_imu: the IMU mount whose frame is written alongside the body frame.
  TruthWriter(const std::filesystem::path& dir, const SE3& T_body_imu);
  ~TruthWriter();
  void Write(const TruthSample& sample);
  // Flushes and closes; throws InputError if a write failed (disk full, ...).
  void Close();

 private:
  void FlushBuffers();
  std::filesystem::path dir_;
  SE3 T_body_imu_;
  std::ofstream csv_, tum_body_, tum_imu_;
  std::string csv_buf_, tum_body_buf_, tum_imu_buf_;
  bool closed_ = false;
};

// Appends one TUM line: seconds with 9 decimals, then position and quaternion (x y z w).
void AppendTumLine(std::string& out, TimeNs t_ns, const SE3& T_world_frame);
// The line's first field alone: "[-]sec.nnnnnnnnn".
void AppendTumStamp(std::string& out, TimeNs t_ns);

}  // namespace statebench
