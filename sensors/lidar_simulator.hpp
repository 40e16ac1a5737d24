// Synthesises spinning-lidar sweeps by ray casting into a LidarWorld.
//
// Motion distortion: every column fires from the exact lidar pose at its own firing time, and its
// points are expressed in the lidar frame at that pose, as a real sensor reports them; each
// point carries its time after the scan start (t) and its ring. Deskewing a point with the true
// pose at its time gives back the world surface it hit.
//
// Ranges are exact (double-precision intersections with the world's triangles and the traffic
// boxes at the firing time) before the error model: a return is dropped if the hit is outside
// [min_range, max_range], beyond the reflectivity-limited range, or by the dropout probability;
// the kept range gets Gaussian noise along the beam (the point is BeamReturn of that range, the
// code a lidar packets file rebuilds it with). Intensity = 100 * reflectivity *
// cos(incidence) (a calibrated-reflectivity style value in [0, 100]).
//
// Static hits are cast in packets (LidarWorld::CastStaticPacket: one channel of up to
// kStaticPacketSize adjacent columns, same ranges as single rays, faster); traffic per column
// (TrafficWindow::PoseFor, then one cast per ray).
//
// Determinism: the sweep is cut into fixed blocks of kColumnsPerBlock columns, simulated in
// parallel with TBB; block b draws its errors from MakeRng(seed, "<sensor_id>/scan/<scan_index>/
// block/<b>") in column-major, ring-ascending order, and the blocks' points are concatenated in
// block order. Results do not depend on thread scheduling or the number of threads.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/measurements.hpp"
#include "core/se3.hpp"
#include "core/time.hpp"
#include "sensors/lidar_model_params.hpp"
#include "sensors/lidar_world.hpp"
#include "sensors/ray_fan.hpp"
#include "sensors/traffic_window.hpp"

namespace statebench::sensors {

class LidarSimulator {
 public:
  // Exact pose at any time; called from the calling thread only, once per column.
  using PoseFunction = std::function<SE3(TimeNs)>;

  // The world must outlive the simulator.
  LidarSimulator(const LidarWorld& world, LidarModelParams params, std::uint64_t seed);

  // One sweep whose first column fires at t_start_ns; T_world_lidar(t) is the true lidar pose.
  // header.stamp_ns = t_start_ns, header.arrival_ns = end of the sweep + latency.
  LidarScan SimulateScan(const PoseFunction& T_world_lidar, TimeNs t_start_ns,
                         std::uint64_t scan_index) const;

  // Same, from the true body pose: T_world_lidar(t) = T_world_body(t) * params.T_body_lidar.
  LidarScan SimulateScanFromBody(const PoseFunction& T_world_body, TimeNs t_start_ns,
                                 std::uint64_t scan_index) const;

  const LidarModelParams& params() const { return params_; }
  int rays_per_scan() const { return params_.beams.columns * params_.beams.channels(); }

 private:
  static constexpr int kColumnsPerBlock = 50;

  // Firing times and true poses of one sweep's columns.
  struct Sweep {
    TimeNs t_start_ns = 0;
    std::string stream;  // random stream name of the sweep
    std::vector<TimeNs> t_column;
    std::vector<SE3> T_world_column;
  };
  void SimulateBlock(const Sweep& sweep, const TrafficWindow& traffic, int column_begin,
                     int column_end, int block, std::vector<LidarPoint>* out) const;
  // Static hits of `count` (<= LidarWorld::kStaticPacketSize) columns from column_begin, one
  // packet per channel: d_world and hits [k * channels + ring] for column column_begin + k.
  void CastStaticColumns(const Sweep& sweep, int column_begin, int count, Vec3* d_world,
                         std::optional<RayHit>* hits) const;

  const LidarWorld& world_;
  LidarModelParams params_;
  std::uint64_t seed_;
  std::vector<Vec3> directions_lidar_;  // per (column, ring), column-major
  std::vector<RayFan> column_fans_;     // per column, lidar frame
};

}  // namespace statebench::sensors
