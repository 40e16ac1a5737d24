#include "simulator/truth_simulation.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>

#include "core/content_hash.hpp"
#include "core/csv.hpp"
#include "core/error.hpp"

namespace statebench::sim {
namespace {

constexpr const char* kVehicleStage = "vehicle";
constexpr const char* kTruthFile = "truth.bin";

// Interpolates y(x) on a sorted table, linear, clamped to the ends.
double Interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double x,
                   double* slope) {
  if (x <= xs.front() || xs.size() < 2) {
    *slope = xs.size() < 2 ? 1.0 : (ys[1] - ys[0]) / std::max(xs[1] - xs[0], 1e-12);
    return ys.front() + (x - xs.front()) * *slope;
  }
  if (x >= xs.back()) {
    const std::size_t n = xs.size();
    *slope = (ys[n - 1] - ys[n - 2]) / std::max(xs[n - 1] - xs[n - 2], 1e-12);
    return ys.back() + (x - xs.back()) * *slope;
  }
  const std::size_t i = static_cast<std::size_t>(std::upper_bound(xs.begin(), xs.end(), x) -
                                                 xs.begin()) - 1;
  const double dx = xs[i + 1] - xs[i];
  *slope = dx > 1e-12 ? (ys[i + 1] - ys[i]) / dx : 1.0;
  return ys[i] + (x - xs[i]) * *slope;
}

}  // namespace

EgoVehicleType EgoTypeFor(const VehicleParams& params) {
  // SUMO's ego drives a little inside the model's limits so the tracking controller keeps
  // authority for corrections.
  EgoVehicleType t = EgoVehicleTypeFor(params);
  t.max_accel_mps2 *= 0.8;
  t.max_decel_mps2 *= 0.8;
  return t;
}

TruthSimulation::TruthSimulation(const Scenario& scenario, const std::filesystem::path& work_dir,
                                 const SumoRunOptions& sumo_options, const StageCacheUse& cache)
    : scenario_(scenario), params_(LoadVehicleParamsFile(scenario.vehicle_file)) {
  sumo_ = SimulateSumoCached(scenario_, EgoTypeFor(params_), work_dir, sumo_options, cache);
  if (sumo_.ego.empty() || sumo_.driven_path.empty()) {
    throw InputError(scenario_.file.string() + ": the ego vehicle never entered the network");
  }
  terrain_ = std::make_shared<const Terrain>(Terrain::FitPolylines(sumo_.LaneShapes()));
  path_ = std::make_shared<const Path>(
      Path::Build(sumo_.driven_path.points(), PathOptionsFor(params_)));

  const auto& pts = sumo_.driven_path.points();
  s3d_ = sumo_.driven_path.arc_lengths();
  s2d_.resize(pts.size());
  s2d_[0] = 0.0;
  for (std::size_t i = 1; i < pts.size(); ++i) {
    s2d_[i] = s2d_[i - 1] + (pts[i].head<2>() - pts[i - 1].head<2>()).norm();
  }

  const double last_t = sumo_.ego.back().t_s;
  end_ns_ = FromSeconds(std::min(scenario_.duration_s, last_t));
  vehicle_ = std::make_unique<VehicleSimulation>(params_, path_, terrain_);
  double s0 = 0.0, v0 = 0.0, a0 = 0.0;
  Reference(0, &s0, &v0, &a0);
  vehicle_->Reset(s0, v0, 0);
  if (cache.enabled()) OpenVehicleStage(TruthStageKey(scenario_, sumo_options, cache.code_id), cache);

  summary_.scenario = scenario_.name;
  summary_.seed = scenario_.seed;
  summary_.vehicle = params_.name;
  summary_.ego_arrived = sumo_.ego_arrived;
  for (const TrafficFrame& f : sumo_.traffic) {
    summary_.max_traffic_vehicles =
        std::max(summary_.max_traffic_vehicles, static_cast<int>(f.boxes.size()));
  }
  bool stopped = false;
  for (const EgoSample& e : sumo_.ego) {
    const bool now_stopped = e.v_mps < 0.1;
    if (now_stopped && !stopped && (e.tls_state == 'r' || e.tls_state == 'y') &&
        e.tls_distance_m < 30.0) {
      ++summary_.traffic_lights_stops;
    }
    stopped = now_stopped;
  }
}

double TruthSimulation::HorizontalArcLength(double s3d_m, double* ds2d_ds3d) const {
  return Interpolate(s3d_, s2d_, s3d_m, ds2d_ds3d);
}

void TruthSimulation::Reference(TimeNs t_ns, double* s_raw_m, double* v_mps,
                                double* a_mps2) const {
  // SUMO runs with ballistic updates: over the step (t_k, t_k+1] the ego moves with the constant
  // acceleration reported at t_k+1, starting from (s_k, v_k). SUMO's speed is in lane-length
  // units, which differ from shape length on junction lanes by a few per cent, so the shape is
  // scaled to reach the next sample's arc length exactly.
  const auto& ego = sumo_.ego;
  const double t = ToSeconds(t_ns);
  std::size_t k = 0;
  const double step = sumo_.step_s;
  if (t > ego.front().t_s) {
    k = std::min(static_cast<std::size_t>((t - ego.front().t_s) / step), ego.size() - 1);
    while (k + 1 < ego.size() && ego[k + 1].t_s <= t) ++k;
    while (k > 0 && ego[k].t_s > t) --k;
  }
  const EgoSample& e0 = ego[k];
  double a = 0.0;
  double c = 1.0;  // makes the ballistic shape end exactly on SUMO's next arc length
  if (k + 1 < ego.size()) {
    a = ego[k + 1].a_mps2;
    const double dt = ego[k + 1].t_s - e0.t_s;
    double t_move = dt;
    if (a < 0.0 && e0.v_mps + a * dt < 0.0) t_move = -e0.v_mps / a;
    const double ballistic = e0.v_mps * t_move + 0.5 * a * t_move * t_move;
    if (ballistic > 1e-6) c = (ego[k + 1].s_m - e0.s_m) / ballistic;
  }
  const double tau = std::max(0.0, t - e0.t_s);
  double s_offset = 0.0, v = 0.0;
  if (a < 0.0 && e0.v_mps + a * tau < 0.0) {  // SUMO stops a braking vehicle within the step
    const double t_stop = -e0.v_mps / a;
    s_offset = 0.5 * e0.v_mps * t_stop;
    a = 0.0;
  } else {
    s_offset = e0.v_mps * tau + 0.5 * a * tau * tau;
    v = e0.v_mps + a * tau;
  }
  const double s = e0.s_m + c * s_offset;
  v *= c;
  a *= c;
  double ds2d_ds3d = 1.0;
  const double s_front_2d = HorizontalArcLength(s, &ds2d_ds3d);
  *s_raw_m = s_front_2d - params_.front_bumper_to_origin_m();
  *v_mps = v * ds2d_ds3d;
  *a_mps2 = a * ds2d_ds3d;
}

void TruthSimulation::OpenVehicleStage(const std::optional<std::string>& truth_key,
                                       const StageCacheUse& cache) {
  if (!truth_key) return;  // a scenario built in memory
  Sha256 hash;
  hash.Field("vehicle truth v1").Field(*truth_key);
  const std::string key = hash.Hex();
  if (const auto entry = cache.cache->Find(kVehicleStage, key)) {
    replay_ = std::make_unique<BinaryReader>(*entry / kTruthFile);
    return;
  }
  StageCache::PendingEntry entry = cache.cache->Begin(kVehicleStage, key);
  auto writer = std::make_unique<BinaryWriter>(entry.folder() / kTruthFile);
  record_.emplace(Recording{std::move(entry), std::move(writer)});
}

void TruthSimulation::PublishRecording() {
  WriteTruthEnd(*record_->writer);
  record_->writer->Close();
  record_->entry.Publish();
  record_.reset();
}

bool TruthSimulation::Simulate(TrackedTruth* truth) {
  if (started_) {
    if (vehicle_->time_ns() + VehicleSimulation::kStepNs > end_ns_) return false;
    double s = 0.0, v = 0.0, a = 0.0;
    Reference(vehicle_->time_ns(), &s, &v, &a);
    vehicle_->Step(s, v, a);
  }
  started_ = true;
  truth->sample = vehicle_->Truth();
  truth->lateral_error_m = vehicle_->projection().lateral_m;
  truth->longitudinal_error_m = vehicle_->projection().s_m - vehicle_->reference().s_m;
  return true;
}

bool TruthSimulation::Next(TruthSample* sample) {
  TrackedTruth truth;
  if (replay_) {
    if (!ReadTrackedTruth(*replay_, &truth)) return false;
  } else if (!Simulate(&truth)) {
    if (record_) PublishRecording();
    return false;
  } else if (record_) {
    WriteTrackedTruth(*record_->writer, truth);
  }
  *sample = truth.sample;
  Accumulate(truth);
  return true;
}

void TruthSimulation::Accumulate(const TrackedTruth& truth) {
  const TruthSample& s = truth.sample;
  const FrameKinematics& b = s.body;
  summary_.duration_s = ToSeconds(s.t_ns);
  summary_.distance_m = s.distance_m;
  summary_.max_speed_mps = std::max(summary_.max_speed_mps, b.v_world.norm());
  const Vec3 a_body = b.T_world_frame.rotation().conjugate() * b.a_world;
  summary_.max_lateral_accel_mps2 = std::max(summary_.max_lateral_accel_mps2, std::abs(a_body.y()));
  summary_.max_yaw_rate_radps = std::max(summary_.max_yaw_rate_radps, std::abs(b.omega_frame.z()));
  const double lateral = truth.lateral_error_m;
  sum_lateral_sq_ += lateral * lateral;
  ++samples_;
  summary_.rms_lateral_error_m = std::sqrt(sum_lateral_sq_ / static_cast<double>(samples_));
  summary_.max_lateral_error_m = std::max(summary_.max_lateral_error_m, std::abs(lateral));
  summary_.max_longitudinal_error_m =
      std::max(summary_.max_longitudinal_error_m, std::abs(truth.longitudinal_error_m));
  if (s.t_ns == FromSeconds(60.0)) distance_at_60s_ = s.distance_m;
  if (distance_at_60s_ >= 0.0) summary_.distance_after_60s_m = s.distance_m - distance_at_60s_;
}

void WriteTrafficCsv(const SumoResult& sumo, const std::filesystem::path& file) {
  std::ofstream out(file, std::ios::binary);
  if (!out) throw InputError(file.string() + ": cannot create");
  std::string buf = "t_ns,id,x,y,z,yaw,pitch,length,width,height\n";
  for (const TrafficFrame& f : sumo.traffic) {
    const TimeNs t_ns = FromSeconds(f.t_s);
    for (const TrafficBox& b : f.boxes) {
      AppendNumber(buf, t_ns);
      buf += "," + b.id;
      for (const double v : {b.p_world_center.x(), b.p_world_center.y(), b.p_world_center.z(),
                             b.yaw_rad, b.pitch_rad, b.length_m, b.width_m, b.height_m}) {
        buf.push_back(',');
        AppendNumber(buf, v);
      }
      buf.push_back('\n');
    }
    if (buf.size() > (1u << 20)) {
      out << buf;
      buf.clear();
    }
  }
  out << buf;
  if (!out) throw InputError(file.string() + ": write failed");
}

void WritePathCsv(const Path& path, const Terrain& terrain, const std::filesystem::path& file) {
  std::ofstream out(file, std::ios::binary);
  if (!out) throw InputError(file.string() + ": cannot create");
  std::string buf = "s,x,y,z,heading,curvature\n";
  const double length = path.length_m();
  for (double s = 0.0; s <= length; s += 0.5) {
    const PathPoint p = path.At(s);
    for (const double v : {s, p.position.x(), p.position.y(),
                           terrain.Height(p.position.x(), p.position.y()), p.heading_rad}) {
      AppendNumber(buf, v);
      buf.push_back(',');
    }
    AppendNumber(buf, p.curvature_1pm);
    buf.push_back('\n');
  }
  out << buf;
  if (!out) throw InputError(file.string() + ": write failed");
}

}  // namespace statebench::sim
