#include "apps/estimator_feed.hpp"

#include <cstdio>
#include <fstream>

#include "apps/diagnostics_json.hpp"
#include "core/stage_profile.hpp"
#include "reports/metrics_json.hpp"

namespace statebench::app {
namespace {

// RMSE and APE of the estimates inside each outage window (the paper's setup-3 figures).
nlohmann::json DuringOutages(const std::vector<StateEstimate>& estimates,
                             const std::vector<reports::ReferenceState>& reference,
                             const std::vector<reports::OutageWindow>& windows,
                             TimeNs skip_before_ns) {
  nlohmann::json out = nlohmann::json::array();
  for (const reports::OutageWindow& w : windows) {
    std::vector<StateEstimate> inside;
    for (const StateEstimate& e : estimates) {
      if (e.state.t_ns >= w.begin_ns && e.state.t_ns <= w.end_ns) inside.push_back(e);
    }
    reports::MetricsOptions options;
    options.skip_before_ns = skip_before_ns;
    const nlohmann::json m =
        reports::ToJson(reports::ComputeTrajectoryMetrics(inside, reference, options));
    out.push_back({{"begin_s", ToSeconds(w.begin_ns)},
                   {"end_s", ToSeconds(w.end_ns)},
                   {"compared", m["compared"]},
                   {"rmse", m["rmse"]},
                   {"ape", m["ape"]}});
  }
  return out;
}

}  // namespace

void EstimatorFeed::Add(std::string label, std::string type, const std::filesystem::path& dir,
                        std::unique_ptr<est::Estimator> estimator, bool full_covariance) {
  std::filesystem::create_directories(dir);
  FedEstimator e;
  e.label = std::move(label);
  e.type = std::move(type);
  e.dir = dir;
  e.estimator = std::move(estimator);
  e.writer = std::make_unique<reports::EstimateWriter>(dir, full_covariance);
  estimators_.push_back(std::move(e));
}

std::optional<TimeNs> EstimatorFeed::Feed(const Measurement& m) {
  const StageScope stage(Stage::kEstimators);
  const auto* imu = std::get_if<ImuSample>(&m);
  const bool output = imu != nullptr && imu->header.sensor_id == imu_id_;
  for (FedEstimator& f : estimators_) {
    const StageTimes before = CurrentStageTimes();
    f.estimator->Add(m);
    std::optional<StateEstimate> e;
    if (output) e = f.estimator->StateAt(imu->header.stamp_ns);
    f.time += CurrentStageTimes() - before;
    if (!e) continue;
    if (frame_) e->state.p_world = frame_->ToEnu({e->latitude_deg, e->longitude_deg, e->altitude_m});
    {
      const StageScope writing(Stage::kWriting);
      f.writer->Write(*e);
    }
    f.estimates.push_back(*e);
  }
  if (!output) return std::nullopt;
  ++imu_stamps_;
  return imu->header.stamp_ns;
}

std::vector<EstimatorScore> EstimatorFeed::Finish(
    const std::vector<reports::ReferenceState>& reference,
    const std::vector<reports::OutageWindow>& outages) {
  const StageScope stage(Stage::kScoring);
  std::vector<EstimatorScore> scores;
  for (FedEstimator& f : estimators_) {
    EstimatorScore s;
    s.diagnostics = f.estimator->diagnostics();
    s.diagnostics_json = DiagnosticsJson(s.diagnostics);
    {
      const StageScope writing(Stage::kWriting);
      f.writer->Close();
      std::ofstream(f.dir / "diagnostics.json") << s.diagnostics_json.dump(2) << "\n";
    }
    if (!reference.empty()) {
      reports::MetricsOptions options;
      options.skip_before_ns = s.diagnostics.initialized_at_ns;
      options.outages = outages;
      s.metrics = reports::ComputeTrajectoryMetrics(f.estimates, reference, options);
      s.metrics_json = reports::ToJson(s.metrics);
      s.metrics_json["during_outages"] =
          DuringOutages(f.estimates, reference, outages, s.diagnostics.initialized_at_ns);
    }
    // What the estimator delivered: an estimate at how many of the IMU stamps it was offered,
    // and how many of those were finite (before initialisation there is none).
    std::size_t finite = 0;
    for (const StateEstimate& e : f.estimates) {
      finite += e.state.p_world.allFinite() && e.state.v_world.allFinite() &&
                e.state.q_world_imu.coeffs().allFinite();
    }
    s.metrics_json["availability"] = {
        {"imu_stamps", imu_stamps_},
        {"estimates", f.estimates.size()},
        {"finite_estimates", finite},
        {"fraction", imu_stamps_ > 0 ? static_cast<double>(finite) / static_cast<double>(imu_stamps_)
                                     : 0.0}};
    scores.push_back(std::move(s));
  }
  return scores;
}

void WriteMetrics(const std::filesystem::path& dir, const EstimatorScore& score) {
  const StageScope writing(Stage::kWriting);
  std::ofstream(dir / "metrics.json") << score.metrics_json.dump(2) << "\n";
}

void FeedProgress::Epoch(TimeNs t_ns) {
  if (quiet_ || ++epochs_ % 500 != 0) return;
  char detail[64];
  std::snprintf(detail, sizeof(detail), "t=%.0f s", ToSeconds(t_ns));
  bar_.Update(end_s_ > 0 ? ToSeconds(t_ns) / end_s_ : 0.0, detail);
}

void FeedProgress::Finish() {
  if (!quiet_) bar_.Finish();
}

}  // namespace statebench::app
