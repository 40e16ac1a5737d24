// Estimate files: estimate.csv (state, WGS84 position, covariance diagonal and optionally the
// full covariance) and estimate.tum (t tx ty tz qx qy qz qw of T_world_imu). Columns:
// docs/estimate-format.md.
#pragma once

#include <array>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/state.hpp"

namespace statebench::reports {

class EstimateWriter {
 public:
  EstimateWriter(const std::filesystem::path& dir, bool full_covariance);
  ~EstimateWriter();
  void Write(const StateEstimate& estimate);
  void Close();  // throws InputError when writing failed

 private:
  // The TUM line of s; pose_text holds where p and q's text starts in csv_buf_ (and one past).
  void AppendTum(const NavState& s, const std::array<std::size_t, 8>& pose_text);
  // ",bg_x,bg_y,bg_z,ba_x,ba_y,ba_z" of s, from the previous row's text where unchanged.
  void AppendBiases(const NavState& s);
  void Flush();
  std::filesystem::path dir_;
  bool full_covariance_;
  std::ofstream csv_, tum_;
  std::string csv_buf_, tum_buf_;
  bool closed_ = false;
  std::array<double, 6> bias_{};  // the last row's biases and their text
  std::string bias_text_;
};

}  // namespace statebench::reports
