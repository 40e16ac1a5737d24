#include "simulator/sumo_result_io.hpp"

#include <stdexcept>

#include "core/binary_io.hpp"
#include "core/error.hpp"

namespace statebench::sim {
namespace {

constexpr std::uint32_t kMagic = 0x53554d31;  // "SUM1"

void PutVec3(BinaryWriter& w, const Vec3& v) {
  w.Put(v.x());
  w.Put(v.y());
  w.Put(v.z());
}

Vec3 GetVec3(BinaryReader& r) {
  const double x = r.Get<double>(), y = r.Get<double>(), z = r.Get<double>();
  return Vec3(x, y, z);
}

void PutPoints(BinaryWriter& w, const std::vector<Vec3>& points) {
  w.Put<std::uint64_t>(points.size());
  for (const Vec3& p : points) PutVec3(w, p);
}

std::vector<Vec3> GetPoints(BinaryReader& r) {
  std::vector<Vec3> points(r.Get<std::uint64_t>());
  for (Vec3& p : points) p = GetVec3(r);
  return points;
}

template <typename T, typename PutOne>
void PutList(BinaryWriter& w, const std::vector<T>& items, PutOne put) {
  w.Put<std::uint64_t>(items.size());
  for (const T& item : items) put(item);
}

template <typename T, typename GetOne>
std::vector<T> GetList(BinaryReader& r, GetOne get) {
  const auto n = r.Get<std::uint64_t>();
  std::vector<T> items;
  for (std::uint64_t i = 0; i < n; ++i) items.push_back(get());
  return items;
}

}  // namespace

void WriteSumoResult(const SumoResult& result, const std::filesystem::path& file) {
  BinaryWriter w(file);
  w.Put(kMagic);
  w.Put(result.step_s);
  w.Put<std::uint8_t>(result.ego_arrived ? 1 : 0);
  PutList(w, result.ego, [&w](const EgoSample& e) {
    w.Put(e.t_s);
    w.PutString(e.lane_id);
    w.Put<std::uint64_t>(e.driven_lane);
    for (const double v : {e.lane_pos_m, e.s_m, e.v_mps, e.a_mps2, e.ds_dt_mps}) w.Put(v);
    PutVec3(w, e.p_world_front);
    for (const double v : {e.yaw_rad, e.slope_rad}) w.Put(v);
    w.Put(e.tls_state);
    for (const double v : {e.tls_distance_m, e.leader_gap_m}) w.Put(v);
  });
  PutPoints(w, result.driven_path.points());
  w.PutVector(result.driven_path.arc_lengths());
  PutList(w, result.driven_path.lanes(), [&w](const DrivenLane& l) {
    w.PutString(l.lane_id);
    for (const double v : {l.s_begin_m, l.s_end_m, l.lane_length_m}) w.Put(v);
  });
  PutList(w, result.lanes, [&w](const LaneGeometry& l) {
    w.PutString(l.id);
    w.PutString(l.edge_id);
    w.Put<std::uint8_t>(l.internal ? 1 : 0);
    w.Put(l.width_m);
    w.Put(l.length_m);
    PutPoints(w, l.shape);
  });
  PutList(w, result.junctions, [&w](const JunctionGeometry& j) {
    w.PutString(j.id);
    PutPoints(w, j.shape);
  });
  PutList(w, result.traffic, [&w](const TrafficFrame& f) {
    w.Put(f.t_s);
    PutList(w, f.boxes, [&w](const TrafficBox& b) {
      w.PutString(b.id);
      PutVec3(w, b.p_world_center);
      for (const double v :
           {b.yaw_rad, b.pitch_rad, b.length_m, b.width_m, b.height_m, b.v_mps}) {
        w.Put(v);
      }
    });
  });
  w.Close();
}

SumoResult ReadSumoResult(const std::filesystem::path& file) {
  BinaryReader r(file);
  if (r.Get<std::uint32_t>() != kMagic) {
    throw InputError(file.string() + ": not a cached SUMO result");
  }
  SumoResult result;
  result.step_s = r.Get<double>();
  result.ego_arrived = r.Get<std::uint8_t>() != 0;
  result.ego = GetList<EgoSample>(r, [&r] {
    EgoSample e;
    e.t_s = r.Get<double>();
    e.lane_id = r.GetString();
    e.driven_lane = r.Get<std::uint64_t>();
    for (double* v : {&e.lane_pos_m, &e.s_m, &e.v_mps, &e.a_mps2, &e.ds_dt_mps}) {
      *v = r.Get<double>();
    }
    e.p_world_front = GetVec3(r);
    e.yaw_rad = r.Get<double>();
    e.slope_rad = r.Get<double>();
    e.tls_state = r.Get<char>();
    e.tls_distance_m = r.Get<double>();
    e.leader_gap_m = r.Get<double>();
    return e;
  });
  std::vector<Vec3> points = GetPoints(r);
  std::vector<double> arc_lengths = r.GetVector<double>();
  std::vector<DrivenLane> driven_lanes = GetList<DrivenLane>(r, [&r] {
    DrivenLane l;
    l.lane_id = r.GetString();
    l.s_begin_m = r.Get<double>();
    l.s_end_m = r.Get<double>();
    l.lane_length_m = r.Get<double>();
    return l;
  });
  try {
    result.driven_path =
        DrivenPath::Restore(std::move(points), std::move(arc_lengths), std::move(driven_lanes));
  } catch (const std::invalid_argument& e) {
    throw InputError(file.string() + ": " + e.what());
  }
  result.lanes = GetList<LaneGeometry>(r, [&r] {
    LaneGeometry l;
    l.id = r.GetString();
    l.edge_id = r.GetString();
    l.internal = r.Get<std::uint8_t>() != 0;
    l.width_m = r.Get<double>();
    l.length_m = r.Get<double>();
    l.shape = GetPoints(r);
    return l;
  });
  result.junctions = GetList<JunctionGeometry>(r, [&r] {
    JunctionGeometry j;
    j.id = r.GetString();
    j.shape = GetPoints(r);
    return j;
  });
  result.traffic = GetList<TrafficFrame>(r, [&r] {
    TrafficFrame f;
    f.t_s = r.Get<double>();
    f.boxes = GetList<TrafficBox>(r, [&r] {
      TrafficBox b;
      b.id = r.GetString();
      b.p_world_center = GetVec3(r);
      for (double* v : {&b.yaw_rad, &b.pitch_rad, &b.length_m, &b.width_m, &b.height_m, &b.v_mps}) {
        *v = r.Get<double>();
      }
      return b;
    });
    return f;
  });
  if (!r.AtEnd()) throw InputError(file.string() + ": trailing bytes after the SUMO result");
  return result;
}

}  // namespace statebench::sim
