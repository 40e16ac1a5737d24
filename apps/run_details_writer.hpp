// The per-epoch and per-measurement files a run writes beside its estimates, for the run report
// (docs/estimate-format.md, "Run details"): the reference trajectory (reference.csv), every GNSS
// fix of the stream in the run's ENU frame (gnss_fixes.csv), and per estimator its errors at
// every scored epoch (errors.csv) and its verdict on every non-IMU measurement
// (measurements.csv; IMU samples only when rejected). Written as the run goes, buffered.
#pragma once

#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/geodetic.hpp"
#include "core/measurements.hpp"
#include "estimator/estimator_diagnostics.hpp"
#include "reports/epoch_errors.hpp"

namespace statebench::app {

class RunDetailsWriter {
 public:
  // run_dir: where reference.csv and gnss_fixes.csv go; estimator_dirs: one folder per estimator
  // (errors.csv, measurements.csv); frame: the run's ENU frame (nullopt: no gnss_fixes.csv).
  RunDetailsWriter(const std::filesystem::path& run_dir,
                   const std::vector<std::filesystem::path>& estimator_dirs, std::string imu_id,
                   std::optional<LocalEnuFrame> frame);
  ~RunDetailsWriter();

  void Measurement(const statebench::Measurement& m);  // the stream, as fed
  void Verdict(std::size_t estimator, const std::string& sensor_id, TimeNs stamp_ns,
               std::optional<est::RejectReason> rejected);
  void Epoch(const reports::ReferenceState& reference,
             const std::vector<std::optional<reports::EpochErrors>>& errors);
  void Close();  // throws InputError when a file could not be written

 private:
  class File;
  std::string imu_id_;
  std::optional<LocalEnuFrame> frame_;
  std::unique_ptr<File> reference_, fixes_;
  std::vector<std::unique_ptr<File>> errors_, verdicts_;
};

}  // namespace statebench::app
