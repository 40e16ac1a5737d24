#include "sensors/lidar_simulator.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "core/random.hpp"
#include "core/stage_profile.hpp"
#include "sensors/traffic_window.hpp"

namespace statebench::sensors {
namespace {

constexpr double kReferenceReflectivity = 0.1;  // range_at_10pct_m refers to a 10 % target

}  // namespace

LidarSimulator::LidarSimulator(const LidarWorld& world, LidarModelParams params, std::uint64_t seed)
    : world_(world), params_(std::move(params)), seed_(seed) {
  const LidarBeamModel& beams = params_.beams;
  directions_lidar_ = beams.Directions();
  const auto channels = static_cast<std::size_t>(beams.channels());
  for (int c = 0; c < beams.columns; ++c) {
    column_fans_.push_back(FanOf(std::span(directions_lidar_).subspan(c * channels, channels)));
  }
}

LidarScan LidarSimulator::SimulateScanFromBody(const PoseFunction& T_world_body, TimeNs t_start_ns,
                                               std::uint64_t scan_index) const {
  const SE3 T_body_lidar = params_.T_body_lidar;
  return SimulateScan([&](TimeNs t) { return T_world_body(t) * T_body_lidar; }, t_start_ns,
                      scan_index);
}

LidarScan LidarSimulator::SimulateScan(const PoseFunction& T_world_lidar, TimeNs t_start_ns,
                                       std::uint64_t scan_index) const {
  const StageScope stage(Stage::kLidarRaycast);
  const LidarBeamModel& beams = params_.beams;
  const int columns = beams.columns;

  // 1. Firing times and exact poses, on this thread (the pose callback need not be thread-safe).
  Sweep sweep;
  sweep.t_start_ns = t_start_ns;
  sweep.stream = params_.sensor_id + "/scan/" + std::to_string(scan_index);
  sweep.t_column.resize(static_cast<std::size_t>(columns));
  sweep.T_world_column.resize(static_cast<std::size_t>(columns));
  Eigen::AlignedBox3d reach;  // where the beams can go during the sweep
  for (int c = 0; c < columns; ++c) {
    sweep.t_column[c] = t_start_ns + beams.ColumnOffsetNs(c);
    sweep.T_world_column[c] = T_world_lidar(sweep.t_column[c]);
    reach.extend(sweep.T_world_column[c].translation());
  }
  reach.min() -= Vec3::Constant(params_.max_range_m);
  reach.max() += Vec3::Constant(params_.max_range_m);
  const TrafficWindow traffic(world_.traffic(), t_start_ns, sweep.t_column.back(), reach);

  // 2. Fixed blocks of columns in parallel, each with its own random stream; 3. concatenated in
  // block order.
  const int blocks = (columns + kColumnsPerBlock - 1) / kColumnsPerBlock;
  std::vector<std::vector<LidarPoint>> block_points(static_cast<std::size_t>(blocks));
  tbb::parallel_for(0, blocks, [&](int b) {
    SimulateBlock(sweep, traffic, b * kColumnsPerBlock,
                  std::min(columns, (b + 1) * kColumnsPerBlock), b, &block_points[b]);
  });
  auto points = std::make_shared<std::vector<LidarPoint>>();
  std::size_t total = 0;
  for (const auto& bp : block_points) total += bp.size();
  points->reserve(total);
  for (const auto& bp : block_points) points->insert(points->end(), bp.begin(), bp.end());

  LidarScan scan;
  scan.header.sensor_id = params_.sensor_id;
  scan.header.stamp_ns = t_start_ns;
  scan.header.arrival_ns = t_start_ns + beams.PeriodNs() + params_.latency_ns;
  scan.points = std::move(points);
  return scan;
}

void LidarSimulator::SimulateBlock(const Sweep& sweep, const TrafficWindow& traffic,
                                   int column_begin, int column_end, int block,
                                   std::vector<LidarPoint>* out) const {
  const int channels = params_.beams.channels();
  const double max_range = params_.max_range_m;
  std::mt19937_64 rng = MakeRng(seed_, sweep.stream + "/block/" + std::to_string(block));
  NormalSampler normal;
  out->reserve(static_cast<std::size_t>(column_end - column_begin) * channels);
  constexpr int kGroup = LidarWorld::kStaticPacketSize;
  const auto group_rays = static_cast<std::size_t>(kGroup * channels);
  std::vector<Vec3> d_world_group(group_rays);                  // [k * channels + ring]
  std::vector<std::optional<RayHit>> static_hits(group_rays);  // the same
  std::vector<PosedTrafficBox> vehicles;  // those the column may see, at its firing time
  for (int c0 = column_begin; c0 < column_end; c0 += kGroup) {
    const int group = std::min(kGroup, column_end - c0);
    CastStaticColumns(sweep, c0, group, d_world_group.data(), static_hits.data());
    for (int c = c0; c < c0 + group; ++c) {
      const SE3& T = sweep.T_world_column[c];
      const Vec3& origin = T.translation();
      const float t_rel = params_.beams.ColumnTimeS(c);  // = t_column[c] - t_start, as float
      traffic.PoseFor(column_fans_[static_cast<std::size_t>(c)].Rotated(T.rotation()), origin,
                      max_range, sweep.t_column[c], &vehicles);
      for (int ring = 0; ring < channels; ++ring) {
        // Exact hit: static world, then traffic at this column's firing time in front of it.
        const Vec3& d_lidar = directions_lidar_[static_cast<std::size_t>(c) * channels + ring];
        const auto at = static_cast<std::size_t>((c - c0) * channels + ring);
        const Vec3& d_world = d_world_group[at];
        std::optional<RayHit> hit = static_hits[at];
        if (!vehicles.empty()) {
          if (auto car =
                  TrafficWindow::Cast(vehicles, origin, d_world, hit ? hit->range_m : max_range)) {
            hit = car;
          }
        }
        if (!hit || hit->range_m < params_.min_range_m) continue;

        // Error model: detection limit, dropout, range noise.
        const double rho = Reflectivity(hit->material);
        const double cos_incidence = std::abs(hit->normal_world.dot(d_world));
        if (params_.range_at_10pct_m > 0.0 &&
            hit->range_m > params_.range_at_10pct_m *
                               std::sqrt(rho * cos_incidence / kReferenceReflectivity)) {
          continue;
        }
        const double u = Uniform01(rng);
        const double noise = params_.range_noise_sigma_m * normal(rng);
        if (u < params_.dropout_probability) continue;
        // Intensity in whole units, as a packet's reflectivity byte carries it.
        const auto intensity = static_cast<float>(std::round(100.0 * rho * cos_incidence));
        out->push_back(BeamReturn(d_lidar, hit->range_m + noise, intensity, t_rel,
                                  static_cast<std::uint16_t>(ring)));
      }
    }
  }
}

void LidarSimulator::CastStaticColumns(const Sweep& sweep, int column_begin, int count,
                                       Vec3* d_world, std::optional<RayHit>* hits) const {
  constexpr int kGroup = LidarWorld::kStaticPacketSize;
  const int channels = params_.beams.channels();
  std::array<Vec3, kGroup> origins;
  for (int k = 0; k < count; ++k) {
    const SE3& T = sweep.T_world_column[column_begin + k];
    origins[k] = T.translation();
    for (int ring = 0; ring < channels; ++ring) {
      const Vec3& d_lidar =
          directions_lidar_[static_cast<std::size_t>(column_begin + k) * channels + ring];
      d_world[k * channels + ring] = T.rotation() * d_lidar;
    }
  }
  std::array<Vec3, kGroup> directions;
  std::array<std::optional<RayHit>, kGroup> packet;
  for (int ring = 0; ring < channels; ++ring) {
    for (int k = 0; k < count; ++k) directions[k] = d_world[k * channels + ring];
    world_.CastStaticPacket(origins.data(), directions.data(), count, params_.max_range_m,
                            packet.data());
    for (int k = 0; k < count; ++k) hits[k * channels + ring] = packet[k];
  }
}

}  // namespace statebench::sensors
