// The feed-and-score loop shared by `statebench run` and `statebench estimate` (and the runs of a
// sweep): every measurement of a stream goes, in arrival order, to each estimator; after every
// sample of the setup's IMU each estimator's real-time estimate is read, re-expressed in the
// stream's ENU frame through its WGS84 position (estimators anchor their own frame where they
// like), written and kept; at the end each one's diagnostics and metrics against the reference
// are computed and written next to its estimate.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "apps/progress_bar.hpp"
#include "core/geodetic.hpp"
#include "core/stage_profile.hpp"
#include "estimator/estimator.hpp"
#include "reports/estimate_writer.hpp"
#include "reports/trajectory_metrics.hpp"

namespace statebench::app {

struct FedEstimator {
  std::string label;  // names its folder
  std::string type;
  std::filesystem::path dir;
  std::unique_ptr<est::Estimator> estimator;
  std::unique_ptr<reports::EstimateWriter> writer;
  std::vector<StateEstimate> estimates;
  StageTimes time;  // spent in its calls (its lidar odometry included; not writing)
};

// What the scoring of one estimator gives: diagnostics.json and metrics.json (written), and the
// figures for a summary line.
struct EstimatorScore {
  est::EstimatorDiagnostics diagnostics;
  nlohmann::json diagnostics_json;
  reports::TrajectoryMetrics metrics;
  nlohmann::json metrics_json;  // the caller may add fields before WriteMetrics
};

class EstimatorFeed {
 public:
  // frame: the stream's ENU frame (nullopt: keep each estimator's own).
  EstimatorFeed(std::string imu_id, std::optional<LocalEnuFrame> frame)
      : imu_id_(std::move(imu_id)), frame_(std::move(frame)) {}

  // An estimator writing into dir (created) at IMU rate.
  void Add(std::string label, std::string type, const std::filesystem::path& dir,
           std::unique_ptr<est::Estimator> estimator, bool full_covariance);

  // Hands m to every estimator; returns the stamp when m is a sample of the setup's IMU (an
  // output epoch).
  std::optional<TimeNs> Feed(const Measurement& m);

  // Closes each writer and scores each estimator from its initialisation on against `reference`
  // (metrics empty when there is none), with the RMSE and APE inside each outage window.
  std::vector<EstimatorScore> Finish(const std::vector<reports::ReferenceState>& reference,
                                     const std::vector<reports::OutageWindow>& outages);

  std::vector<FedEstimator>& estimators() { return estimators_; }

 private:
  std::string imu_id_;
  std::optional<LocalEnuFrame> frame_;
  std::vector<FedEstimator> estimators_;
  std::size_t imu_stamps_ = 0;  // output stamps offered to every estimator
};

// Writes score.metrics_json to dir/metrics.json.
void WriteMetrics(const std::filesystem::path& dir, const EstimatorScore& score);

// Updates the bar every 500 output epochs with the simulated time (fraction of end_s).
class FeedProgress {
 public:
  FeedProgress(std::string label, double end_s, bool quiet)
      : bar_(std::move(label)), end_s_(end_s), quiet_(quiet) {}
  void Epoch(TimeNs t_ns);
  void Finish();

 private:
  ProgressBar bar_;
  double end_s_;
  bool quiet_;
  std::size_t epochs_ = 0;
};

}  // namespace statebench::app
