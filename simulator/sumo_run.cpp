#include "simulator/sumo_run.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <iostream>
#include <map>
#include <mutex>
#include <unordered_map>

#include "core/so3.hpp"
#include "simulator/density_traffic.hpp"
#include "simulator/routes_file.hpp"
#include "simulator/sumo_api.hpp"
#include "simulator/sumo_tools.hpp"

namespace statebench::sim {
namespace {

namespace fs = std::filesystem;
constexpr double kDegToRad = M_PI / 180.0;

std::mutex& SumoMutex() {
  static std::mutex mutex;
  return mutex;
}

// libsumo sets std::cout and std::cerr to fixed notation with 2 digits when it loads (the
// first Sumo() call, sumo_api.hpp); the caller's streams get their formatting back when the run
// ends.
class StreamFormatGuard {
 public:
  explicit StreamFormatGuard(std::ostream& stream)
      : stream_(stream), flags_(stream.flags()), precision_(stream.precision()) {}
  ~StreamFormatGuard() {
    stream_.flags(flags_);
    stream_.precision(precision_);
  }
  StreamFormatGuard(const StreamFormatGuard&) = delete;
  StreamFormatGuard& operator=(const StreamFormatGuard&) = delete;

 private:
  std::ostream& stream_;
  std::ios_base::fmtflags flags_;
  std::streamsize precision_;
};

// Closes the libsumo simulation however the run ends.
struct SessionCloser {
  ~SessionCloser() {
    try {
      Sumo().Close();
    } catch (...) {
    }
  }
};

Vec3 ToPoint(const SumoPosition& p) { return Vec3(p[0], p[1], p[2]); }

std::vector<Vec3> ToPoints(const std::vector<SumoPosition>& shape) {
  std::vector<Vec3> points;
  points.reserve(shape.size());
  for (const SumoPosition& p : shape) points.push_back(ToPoint(p));
  return points;
}

// SUMO angle (degrees clockwise from north) -> ENU yaw (radians counter-clockwise from east).
double YawFromSumoAngle(double angle_deg) {
  return so3::WrapAngle(M_PI / 2.0 - angle_deg * kDegToRad);
}

bool Contains(const std::vector<std::string>& ids, const std::string& id) {
  return std::find(ids.begin(), ids.end(), id) != ids.end();
}

std::vector<std::string> SumoArguments(const Scenario& scenario, const BuiltNetwork& built,
                                       const SumoRunOptions& options) {
  std::vector<std::string> args;
  const auto add = [&](const std::string& key, const std::string& value) {
    args.push_back(key);
    args.push_back(value);
  };
  add("--net-file", built.net_file.string());
  add("--route-files", built.routes_file.string());
  add("--step-length", FormatNumber(scenario.sumo.step_s));
  add("--step-method.ballistic", "true");
  add("--seed", std::to_string(SumoSeed(scenario.seed, "sumo")));
  add("--no-step-log", "true");
  add("--no-warnings", options.sumo_warnings ? "false" : "true");
  add("--xml-validation", "never");
  add("--log", (built.work_dir / "sumo.log").string());
  add("--collision.action", "warn");
  return args;
}

void ReadNetworkGeometry(SumoResult* result) {
  for (const std::string& id : Sumo().LaneIds()) {
    LaneGeometry lane;
    lane.id = id;
    lane.edge_id = Sumo().LaneEdge(id);
    lane.internal = !id.empty() && id.front() == ':';
    lane.width_m = Sumo().LaneWidth(id);
    lane.length_m = Sumo().LaneLength(id);
    lane.shape = ToPoints(Sumo().LaneShape(id));
    result->lanes.push_back(std::move(lane));
  }
  for (const std::string& id : Sumo().JunctionIds()) {
    if (!id.empty() && id.front() == ':') continue;  // internal waiting points, no outline
    result->junctions.push_back({id, ToPoints(Sumo().JunctionShape(id))});
  }
}

// Records one SUMO run; owns the lookups that make recording cheap.
class Recorder {
 public:
  Recorder(const Scenario& scenario, SumoResult* result) : scenario_(scenario), result_(result) {
    for (std::size_t i = 0; i < result->lanes.size(); ++i) lane_index_[result->lanes[i].id] = i;
  }

  // Extends the driven path to the ego's current lane; returns its sample fields.
  EgoSample EgoState(double t_s) {
    const std::string& ego = kEgoId;
    EgoSample s;
    s.t_s = t_s;
    s.lane_id = Sumo().VehicleLane(ego);
    AdvancePath(s.lane_id, t_s);
    s.driven_lane = result_->driven_path.lanes().size() - 1;
    s.lane_pos_m = Sumo().VehicleLanePosition(ego);
    const DrivenLane& lane = result_->driven_path.lanes().back();
    s.s_m = lane.ArcLength(s.lane_pos_m);
    s.v_mps = Sumo().VehicleSpeed(ego);
    s.ds_dt_mps = s.v_mps * (lane.s_end_m - lane.s_begin_m) / lane.lane_length_m;
    s.a_mps2 = Sumo().VehicleAcceleration(ego);
    s.p_world_front = ToPoint(Sumo().VehiclePosition3D(ego));
    s.yaw_rad = YawFromSumoAngle(Sumo().VehicleAngle(ego));
    s.slope_rad = Sumo().VehicleSlope(ego) * kDegToRad;
    const auto tls = Sumo().VehicleNextTls(ego);
    if (!tls.empty()) {
      s.tls_state = tls.front().state;
      s.tls_distance_m = tls.front().distance_m;
    }
    const auto leader = Sumo().VehicleLeader(ego, 100.0);
    if (!leader.first.empty()) s.leader_gap_m = leader.second;
    return s;
  }

  TrafficFrame Traffic(double t_s) {
    TrafficFrame frame;
    frame.t_s = t_s;
    for (const std::string& id : Sumo().VehicleIds()) {
      if (id == kEgoId) continue;
      frame.boxes.push_back(Box(id));
    }
    return frame;
  }

 private:
  // A traffic vehicle's box: SUMO gives the front bumper centre on the road surface; the box
  // centre is L/2 back along the body x axis and H/2 up along the body z axis, with
  // R = Rz(yaw) Ry(pitch), pitch = -slope.
  TrafficBox Box(const std::string& id) {
    const Vec3& dims = TypeDimensions(Sumo().VehicleType(id));
    TrafficBox box;
    box.id = id;
    box.length_m = dims.x();
    box.width_m = dims.y();
    box.height_m = dims.z();
    box.yaw_rad = YawFromSumoAngle(Sumo().VehicleAngle(id));
    const double slope = Sumo().VehicleSlope(id) * kDegToRad;
    box.pitch_rad = -slope;
    const Vec3 p = ToPoint(Sumo().VehiclePosition3D(id));
    const double cy = std::cos(box.yaw_rad), sy = std::sin(box.yaw_rad);
    const double cs = std::cos(slope), ss = std::sin(slope);
    const Vec3 forward(cy * cs, sy * cs, ss);
    const Vec3 up(-cy * ss, -sy * ss, cs);
    box.p_world_center =
        p - 0.5 * box.length_m * forward + 0.5 * box.height_m * up;
    box.v_mps = Sumo().VehicleSpeed(id);
    return box;
  }

  const Vec3& TypeDimensions(const std::string& type_id) {
    auto it = type_dims_.find(type_id);
    if (it == type_dims_.end()) {
      const Vec3 dims(Sumo().TypeLength(type_id),
                      Sumo().TypeWidth(type_id),
                      Sumo().TypeHeight(type_id));
      it = type_dims_.emplace(type_id, dims).first;
    }
    return it->second;
  }

  const std::vector<std::string>& Successors(const std::string& lane) {
    auto it = successors_.find(lane);
    if (it == successors_.end()) {
      std::vector<std::string> next;
      for (const SumoLaneLink& link : Sumo().LaneLinks(lane)) {
        next.push_back(link.approached_internal.empty() ? link.approached_lane
                                                        : link.approached_internal);
      }
      it = successors_.emplace(lane, std::move(next)).first;
    }
    return it->second;
  }

  void Append(const std::string& lane_id) {
    const LaneGeometry& lane = result_->lanes.at(lane_index_.at(lane_id));
    result_->driven_path.AppendLane(lane.id, lane.shape, lane.length_m);
  }

  // Appends the lanes from the last driven lane to `lane_id`, including short junction lanes
  // the ego crossed within one step (breadth-first search over lane links, at most 4 deep).
  void AdvancePath(const std::string& lane_id, double t_s) {
    DrivenPath& path = result_->driven_path;
    if (path.empty()) return Append(lane_id);
    const std::string& last = path.lanes().back().lane_id;
    if (last == lane_id) return;
    std::map<std::string, std::string> parent;
    std::deque<std::pair<std::string, int>> queue = {{last, 0}};
    while (!queue.empty() && parent.count(lane_id) == 0) {
      const auto [lane, depth] = queue.front();
      queue.pop_front();
      if (depth >= 4) continue;
      for (const std::string& next : Successors(lane)) {
        if (parent.emplace(next, lane).second) queue.emplace_back(next, depth + 1);
      }
    }
    if (parent.count(lane_id) == 0) {
      scenario_.ego.source.Fail("at t = " + FormatNumber(t_s) + " s the ego jumped from lane '" +
                                last + "' to lane '" + lane_id + "' without a connection");
    }
    std::vector<std::string> chain;
    for (std::string lane = lane_id; lane != last; lane = parent.at(lane)) chain.push_back(lane);
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) Append(*it);
  }

  const Scenario& scenario_;
  SumoResult* result_;
  std::unordered_map<std::string, std::size_t> lane_index_;
  std::unordered_map<std::string, Vec3> type_dims_;
  std::unordered_map<std::string, std::vector<std::string>> successors_;
};

void LoadOrFail(const Scenario& scenario, const BuiltNetwork& built,
                const SumoRunOptions& options) {
  try {
    Sumo().Load(SumoArguments(scenario, built, options));
  } catch (const std::exception& e) {
    throw InputError(scenario.file.string() + ": SUMO could not load " + built.net_file.string() +
                     " with " + built.routes_file.string() + ": " + e.what());
  }
}

}  // namespace

SumoResult RunSumo(const Scenario& scenario, const BuiltNetwork& built,
                   const SumoRunOptions& options) {
  std::lock_guard<std::mutex> lock(SumoMutex());
  const StreamFormatGuard cout_guard(std::cout);
  const StreamFormatGuard cerr_guard(std::cerr);
  LoadOrFail(scenario, built, options);
  SessionCloser closer;

  SumoResult result;
  result.step_s = scenario.sumo.step_s;
  ReadNetworkGeometry(&result);
  Recorder recorder(scenario, &result);
  const std::string ego_start_edge = built.ego_route.front();
  DensityTraffic density(scenario.traffic.density, scenario.seed, built.index.edges,
                         {ego_start_edge});
  density.Start();

  const double dt = scenario.sumo.step_s;
  const long last_recorded = static_cast<long>(std::floor(scenario.duration_s / dt + 1e-9));
  const long last_step = last_recorded + static_cast<long>(std::ceil(options.max_tail_s / dt));
  bool parked = scenario.ego.parked_s > 0.0;  // ego.parked_s: held at 0 m/s until then
  try {
    for (long k = 0; k <= last_step; ++k) {
      Sumo().Step();
      const double t_s = static_cast<double>(k) * dt;
      const std::vector<std::string> arrived = Sumo().ArrivedIds();
      if (Contains(arrived, kEgoId)) {
        result.ego_arrived = k <= last_recorded;
        break;
      }
      if (k == 0) {
        if (!Contains(Sumo().DepartedIds(), kEgoId)) {
          scenario.ego.source.Fail("the ego could not depart at t = 0 on edge '" + ego_start_edge +
                                   "' (departure position blocked?)");
        }
        Sumo().SetLaneChangeMode(kEgoId, 0);  // no lane changes of any kind
        if (parked) Sumo().SetSpeed(kEgoId, 0.0);
      }
      if (parked && t_s >= scenario.ego.parked_s - 1e-9) {
        Sumo().SetSpeed(kEgoId, -1.0);  // the driver model moves it from the next step
        parked = false;
      }
      if (Contains(Sumo().StartingTeleportIds(), kEgoId)) {
        scenario.ego.source.Fail("the ego got stuck at t = " + FormatNumber(t_s) +
                                 " s and SUMO teleported it (lane changes are disabled: can its "
                                 "route be driven in one lane?)");
      }
      if (k <= last_recorded) {
        result.ego.push_back(recorder.EgoState(t_s));
        if (options.record_traffic) result.traffic.push_back(recorder.Traffic(t_s));
        density.AfterStep(arrived);
        continue;
      }
      // Tail: only extend the driven path for the path tracker's look-ahead.
      recorder.EgoState(t_s);
      if (result.driven_path.length_m() - result.ego.back().s_m >= options.lookahead_m) break;
    }
  } catch (const InputError&) {
    throw;
  } catch (const std::runtime_error& e) {  // libsumo::TraCIException
    throw std::runtime_error(std::string("SUMO failed during the run: ") + e.what());
  }
  return result;
}

SumoResult SimulateSumo(const Scenario& scenario, const EgoVehicleType& ego_type,
                        const fs::path& work_dir, const SumoRunOptions& options) {
  const BuiltNetwork built = NetworkBuilder().Build(scenario, ego_type, work_dir);
  return RunSumo(scenario, built, options);
}

}  // namespace statebench::sim
