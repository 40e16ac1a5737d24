// The feed-and-score loop shared by `statebench run` and `statebench estimate` (and the runs of a
// sweep): every measurement of a stream goes, in arrival order, to each estimator; after every
// sample of the setup's IMU each estimator's real-time estimate is read, re-expressed in the
// stream's ENU frame through its WGS84 position (estimators anchor their own frame where they
// like), written, and scored against the truth as it goes (reports/run_scorer.hpp: one common
// span for every estimator, memory that does not grow with the run); at the end each one's
// diagnostics and metrics are written next to its estimate. The step between consecutive
// estimates beyond their own motion (truth-free, reports/output_step.hpp) goes into
// diagnostics.json as `output_step`; against the truth it is in metrics.json.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "apps/progress_bar.hpp"
#include "apps/run_details_writer.hpp"
#include "core/geodetic.hpp"
#include "core/stage_profile.hpp"
#include "estimator/estimator.hpp"
#include "reports/estimate_writer.hpp"
#include "reports/output_step.hpp"
#include "reports/run_scorer.hpp"
#include "reports/trajectory_metrics.hpp"

namespace statebench::app {

struct FedEstimator {
  std::string label;  // names its folder
  std::string type;
  std::filesystem::path dir;
  std::unique_ptr<est::Estimator> estimator;
  std::unique_ptr<reports::EstimateWriter> writer;
  std::vector<std::string> inputs;  // the sensors it is given; empty: every one
  std::size_t estimates = 0;        // written
  std::size_t finite_estimates = 0;
  StageTimes time;  // spent in its calls (its lidar odometry included; not writing)
  reports::OwnMotionStepMeter steps;  // truth-free output steps (diagnostics.json output_step)
  bool last_local = false;  // the last estimate was in a local frame (status local)
};

// What the scoring of one estimator gives: diagnostics.json and metrics.json (written), and the
// figures for a summary line.
struct EstimatorScore {
  est::EstimatorDiagnostics diagnostics;
  nlohmann::json diagnostics_json;
  reports::TrajectoryMetrics metrics;
  nlohmann::json metrics_json;  // the caller may add fields before WriteMetrics
  reports::OutputSteps output_steps;  // truth-free (reports/output_step.hpp)
};

class EstimatorFeed {
 public:
  // frame: the stream's ENU frame (nullopt: keep each estimator's own).
  EstimatorFeed(std::string imu_id, std::optional<LocalEnuFrame> frame)
      : imu_id_(std::move(imu_id)), frame_(std::move(frame)) {}

  // An estimator writing into dir (created) at IMU rate, given the measurements of `inputs`
  // only (sensor ids; empty: all).
  void Add(std::string label, std::string type, const std::filesystem::path& dir,
           std::unique_ptr<est::Estimator> estimator, bool full_covariance,
           std::vector<std::string> inputs = {});

  // Scores the estimators against the truth of the frame at T_body_frame (the IMU's mount), with
  // the RMSE and APE inside each outage window besides. Call after the last Add and before the
  // first Feed; without it there are no metrics but availability.
  void ScoreAgainstTruth(const SE3& T_body_frame, std::vector<reports::OutageWindow> outages);
  // Writes the run's details beside the estimates (apps/run_details_writer.hpp): reference and
  // GNSS fixes into run_dir, each estimator's errors and verdicts into its folder. Call after
  // the last Add (and after ScoreAgainstTruth, without which there are no errors).
  void WriteDetails(const std::filesystem::path& run_dir);
  // A truth sample (stamps increasing; ahead of the measurements or behind them).
  void AddTruth(const TruthSample& sample);
  // The same for several samples in one stage switch (a long truth read in blocks: the two
  // clock reads of a switch per 1 kHz sample were a visible share of estimate's CPU).
  void AddTruth(std::span<const TruthSample> samples);

  // Hands m to every estimator; returns the stamp when m is a sample of the setup's IMU (an
  // output epoch).
  std::optional<TimeNs> Feed(const Measurement& m);

  // Ends the log for the estimators that estimate at the end (Estimator::EstimatesAtEnd: their
  // estimates are written and scored now, at the epochs Feed held), then closes each writer and
  // finishes each estimator's score.
  std::vector<EstimatorScore> Finish();

  // Whether an estimator estimates at the end: then every output epoch is held until Finish
  // (stamp, gyro, what the scorer needs of the other estimators' estimates: about 0.5 KB per
  // epoch and estimator) and
  // scored there, so that all are scored over one span.
  bool EstimatesAtEnd() const;

  std::vector<FedEstimator>& estimators() { return estimators_; }

 private:
  struct HeldEpoch {
    TimeNs t_ns = 0;
    Vec3 gyro;
    std::vector<std::optional<reports::ScoredEstimate>> live;  // of the others, in their order
  };
  // Re-expresses, meters, writes and counts an estimate; returns it (nullopt when none).
  std::optional<StateEstimate> Present(FedEstimator& f, std::optional<StateEstimate> e,
                                       const Vec3& gyro);
  void ReplayHeldEpochs();

  std::string imu_id_;
  std::optional<LocalEnuFrame> frame_;
  std::vector<FedEstimator> estimators_;
  std::optional<reports::RunScorer> scorer_;
  std::unique_ptr<RunDetailsWriter> details_;
  std::vector<reports::OutageWindow> outages_;
  std::vector<std::optional<StateEstimate>> epoch_;  // this epoch's estimates, reused
  std::size_t imu_stamps_ = 0;                       // output stamps offered to every estimator
  std::vector<HeldEpoch> held_;  // while an estimator estimates at the end
};

// Writes score.metrics_json to dir/metrics.json.
void WriteMetrics(const std::filesystem::path& dir, const EstimatorScore& score);

// "LABEL never initialised: WAITING_FOR" (or "LABEL produced no estimate") for an estimator
// that wrote no estimate; nullopt when it wrote some.
std::optional<std::string> NoEstimateMessage(const FedEstimator& fed, const EstimatorScore& score);

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
