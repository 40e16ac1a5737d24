#include "apps/estimator_feed.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>

#include "apps/diagnostics_json.hpp"
#include "core/stage_profile.hpp"
#include "reports/metrics_json.hpp"

namespace statebench::app {
void EstimatorFeed::Add(std::string label, std::string type, const std::filesystem::path& dir,
                        std::unique_ptr<est::Estimator> estimator, bool full_covariance,
                        std::vector<std::string> inputs) {
  std::filesystem::create_directories(dir);
  FedEstimator e;
  e.label = std::move(label);
  e.type = std::move(type);
  e.dir = dir;
  e.estimator = std::move(estimator);
  e.inputs = std::move(inputs);
  e.writer = std::make_unique<reports::EstimateWriter>(dir, full_covariance);
  // What the estimator lacks in this setup, before it runs (also in diagnostics.json).
  for (const std::string& w : e.estimator->diagnostics().warnings) {
    std::fprintf(stderr, "warning: %s: %s\n", e.label.c_str(), w.c_str());
  }
  estimators_.push_back(std::move(e));
}

void EstimatorFeed::ScoreAgainstTruth(const SE3& T_body_frame,
                                      std::vector<reports::OutageWindow> outages) {
  reports::RunScoringOptions options;
  options.metrics.outages = outages;
  outages_ = std::move(outages);
  scorer_.emplace(estimators_.size(), T_body_frame, options);
}

void EstimatorFeed::WriteDetails(const std::filesystem::path& run_dir) {
  std::vector<std::filesystem::path> dirs;
  for (const FedEstimator& f : estimators_) dirs.push_back(f.dir);
  details_ = std::make_unique<RunDetailsWriter>(run_dir, dirs, imu_id_, frame_);
  RunDetailsWriter* details = details_.get();
  for (std::size_t k = 0; k < estimators_.size(); ++k) {
    estimators_[k].estimator->SetVerdictObserver(
        [details, k](const std::string& id, TimeNs stamp_ns,
                     std::optional<est::RejectReason> rejected) {
          const StageScope writing(Stage::kWriting);
          details->Verdict(k, id, stamp_ns, rejected);
        });
  }
  if (scorer_) {
    scorer_->SetEpochObserver(
        [details](const reports::ReferenceState& reference,
                  const std::vector<std::optional<reports::EpochErrors>>& errors) {
          const StageScope writing(Stage::kWriting);
          details->Epoch(reference, errors);
        });
  }
}

void EstimatorFeed::AddTruth(const TruthSample& sample) {
  if (!scorer_) return;
  const StageScope stage(Stage::kScoring);
  scorer_->AddTruth(sample);
}

void EstimatorFeed::AddTruth(std::span<const TruthSample> samples) {
  if (!scorer_) return;
  const StageScope stage(Stage::kScoring);
  for (const TruthSample& s : samples) scorer_->AddTruth(s);
}

std::optional<TimeNs> EstimatorFeed::Feed(const Measurement& m) {
  const StageScope stage(Stage::kEstimators);
  const auto* imu = std::get_if<ImuSample>(&m);
  const bool output = imu != nullptr && imu->header.sensor_id == imu_id_;
  if (details_ && imu == nullptr) {
    const StageScope writing(Stage::kWriting);
    details_->Measurement(m);
  }
  epoch_.assign(estimators_.size(), std::nullopt);
  for (std::size_t k = 0; k < estimators_.size(); ++k) {
    FedEstimator& f = estimators_[k];
    const StageTimes before = CurrentStageTimes();
    if (f.inputs.empty() ||
        std::find(f.inputs.begin(), f.inputs.end(), HeaderOf(m).sensor_id) != f.inputs.end()) {
      f.estimator->Add(m);
    }
    const bool now = output && !f.estimator->EstimatesAtEnd();
    std::optional<StateEstimate> e;
    if (now) e = f.estimator->StateAt(imu->header.stamp_ns);
    f.time += CurrentStageTimes() - before;
    if (now) epoch_[k] = Present(f, std::move(e), imu->gyro);
  }
  if (!output) return std::nullopt;
  ++imu_stamps_;
  if (EstimatesAtEnd()) {
    // Until the end of the log: the stamp, the gyro and the other estimators' estimates.
    HeldEpoch held{imu->header.stamp_ns, imu->gyro, {}};
    for (std::size_t k = 0; k < estimators_.size(); ++k) {
      if (!estimators_[k].estimator->EstimatesAtEnd()) {
        held.live.push_back(epoch_[k] ? std::optional(reports::ScoredEstimate::Of(*epoch_[k]))
                                      : std::nullopt);
      }
    }
    held_.push_back(std::move(held));
  } else if (scorer_) {
    const StageScope scoring(Stage::kScoring);
    scorer_->AddEpoch(imu->header.stamp_ns, epoch_);
  }
  return imu->header.stamp_ns;
}

bool EstimatorFeed::EstimatesAtEnd() const {
  return std::any_of(estimators_.begin(), estimators_.end(),
                     [](const FedEstimator& f) { return f.estimator->EstimatesAtEnd(); });
}

std::optional<StateEstimate> EstimatorFeed::Present(FedEstimator& f,
                                                    std::optional<StateEstimate> e,
                                                    const Vec3& gyro) {
  if (!e) {
    f.steps.Break();
    return std::nullopt;
  }
  // A local-frame estimate (no GNSS) has no meaningful WGS84 position: kept as it is.
  const bool local = e->status == EstimateStatus::kLocal;
  if (frame_ && !local)
    e->state.p_world = frame_->ToEnu({e->latitude_deg, e->longitude_deg, e->altitude_m});
  // The step from a local estimate to an ENU one is the change of frame, not a jump.
  if (local != f.last_local) f.steps.Break();
  f.last_local = local;
  f.steps.Add(e->state, gyro);
  {
    const StageScope writing(Stage::kWriting);
    f.writer->Write(*e);
  }
  ++f.estimates;
  f.finite_estimates += e->state.p_world.allFinite() && e->state.v_world.allFinite() &&
                        e->state.q_world_imu.coeffs().allFinite();
  return e;
}

// The estimators that estimate at the end are told the log ended and asked at every held epoch;
// each epoch then goes to the scorer with every estimator's estimate, as Feed would have done.
void EstimatorFeed::ReplayHeldEpochs() {
  for (FedEstimator& f : estimators_) {
    if (!f.estimator->EstimatesAtEnd()) continue;
    const StageScope stage(Stage::kEstimators);
    const StageTimes before = CurrentStageTimes();
    f.estimator->EndOfLog();
    f.time += CurrentStageTimes() - before;
  }
  for (HeldEpoch& held : held_) {
    epoch_.assign(estimators_.size(), std::nullopt);
    std::size_t live = 0;
    for (std::size_t k = 0; k < estimators_.size(); ++k) {
      FedEstimator& f = estimators_[k];
      if (!f.estimator->EstimatesAtEnd()) {
        const std::optional<reports::ScoredEstimate>& h = held.live[live++];
        epoch_[k] = h ? std::optional(h->ToStateEstimate()) : std::nullopt;
        continue;
      }
      const StageScope stage(Stage::kEstimators);
      const StageTimes before = CurrentStageTimes();
      std::optional<StateEstimate> e = f.estimator->StateAt(held.t_ns);
      f.time += CurrentStageTimes() - before;
      epoch_[k] = Present(f, std::move(e), held.gyro);
    }
    if (scorer_) scorer_->AddEpoch(held.t_ns, epoch_);
  }
  held_.clear();
  held_.shrink_to_fit();
}

std::vector<EstimatorScore> EstimatorFeed::Finish() {
  const StageScope stage(Stage::kScoring);
  ReplayHeldEpochs();
  std::vector<reports::RunScore> run_scores;
  if (scorer_) run_scores = scorer_->Finish();
  if (details_) {
    const StageScope writing(Stage::kWriting);
    details_->Close();
  }
  std::vector<EstimatorScore> scores;
  for (std::size_t k = 0; k < estimators_.size(); ++k) {
    FedEstimator& f = estimators_[k];
    EstimatorScore s;
    s.diagnostics = f.estimator->diagnostics();
    s.diagnostics_json = DiagnosticsJson(s.diagnostics);
    s.output_steps = f.steps.Summary();
    s.diagnostics_json["output_step"] = reports::ToJson(s.output_steps);
    {
      const StageScope writing(Stage::kWriting);
      f.writer->Close();
      std::ofstream(f.dir / "diagnostics.json") << s.diagnostics_json.dump(2) << "\n";
    }
    // What the estimator delivered: an estimate at how many of the IMU stamps it was offered,
    // and how many of those were finite (before initialisation there is none); inside the
    // scored span too when there is a truth.
    reports::Availability a;
    if (scorer_) {
      const reports::RunScore& r = run_scores[k];
      s.metrics = r.metrics;
      s.metrics_json = reports::ToJson(r.metrics);
      nlohmann::json windows = nlohmann::json::array();
      for (std::size_t w = 0; w < outages_.size(); ++w) {
        const nlohmann::json m = reports::ToJson(r.during_outages[w]);
        windows.push_back({{"begin_s", ToSeconds(outages_[w].begin_ns)},
                           {"end_s", ToSeconds(outages_[w].end_ns)},
                           {"compared", m["compared"]},
                           {"rmse", m["rmse"]},
                           {"ape", m["ape"]}});
      }
      s.metrics_json["during_outages"] = windows;
      a = r.availability;
    } else {
      a.epochs = imu_stamps_;
      a.estimates = f.estimates;
      a.finite_estimates = f.finite_estimates;
    }
    nlohmann::json availability = {{"imu_stamps", a.epochs},
                                   {"estimates", a.estimates},
                                   {"finite_estimates", a.finite_estimates},
                                   {"fraction", a.Fraction()}};
    if (scorer_) {
      availability["span_begin_s"] = ToSeconds(scorer_->span_begin_ns().value_or(0));
      availability["span_imu_stamps"] = a.span_epochs;
      availability["span_finite_estimates"] = a.span_finite_estimates;
      availability["span_local_estimates"] = a.span_local_estimates;
      availability["span_fraction"] = a.SpanFraction();
    }
    s.metrics_json["availability"] = availability;
    scores.push_back(std::move(s));
  }
  return scores;
}

void WriteMetrics(const std::filesystem::path& dir, const EstimatorScore& score) {
  const StageScope writing(Stage::kWriting);
  std::ofstream(dir / "metrics.json") << score.metrics_json.dump(2) << "\n";
}

std::optional<std::string> NoEstimateMessage(const FedEstimator& fed, const EstimatorScore& score) {
  if (fed.estimates > 0) return std::nullopt;
  const std::string& why = score.diagnostics.waiting_for;
  if (why.empty()) return fed.label + " produced no estimate";
  return fed.label + " never initialised: " + why;
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
