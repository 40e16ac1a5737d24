// Bullet raycast throughput of the lidar simulation: one Hesai XT32 sweep (64,000 beams) from a
// moving vehicle in an urban grid (a few hundred buildings, kerbs, poles, trees, parked cars and
// moving traffic), on 1 and 2 TBB threads. Reported as rays/s of wall time (all beams cast, hits or
// not) and rays per CPU-second summed over threads (the per-core throughput).
// For reference, the same beams through Bullet's stock btCollisionWorld::rayTest with a
// ClosestRayResultCallback (single thread: that path is not thread-safe in Debian's Bullet).
#include <benchmark/benchmark.h>
#ifdef STATEBENCH_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif
#include <btBulletCollisionCommon.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "bench/dense_town.hpp"
#include "core/stage_profile.hpp"
#include "sensors/lidar_simulator.hpp"
#include "sensors/synthetic_roads.hpp"

namespace statebench::sensors {
namespace {

using bench::DenseTownTerrain;

struct UrbanScene {
  std::unique_ptr<LidarWorld> world;
  std::unique_ptr<LidarSimulator> lidar;
  int buildings = 0;
  std::size_t vehicles = 0;

  UrbanScene() {
    const RoadGeometry roads = bench::DenseTownRoads();
    world = bench::BuildDenseTown(roads);
    for (const WorldBox& b : world->layout().boxes) {
      buildings += b.material == SurfaceMaterial::kBuilding ? 1 : 0;
    }
    // Traffic: 4 vehicles per street lane group driving at 8-14 m/s, SUMO steps of 100 ms.
    std::vector<TrafficFrame> frames;
    for (int k = 0; k <= 30; ++k) {
      TrafficFrame f{TimeNs{k} * 100'000'000, {}};
      for (std::size_t lane = 0; lane < roads.lanes.size(); lane += 3) {
        const auto& c = roads.lanes[lane].centre;
        const Vec3 dir = (c.back() - c.front()).normalized();
        const double speed = 8.0 + static_cast<double>(lane % 7);
        TrafficBox box;
        box.id = "veh" + std::to_string(lane);
        box.centre_world = c.front() + (10.0 + 0.1 * k * speed) * dir + Vec3(0.0, 0.0, 0.75);
        box.yaw_rad = std::atan2(dir.y(), dir.x());
        f.boxes.push_back(box);
      }
      frames.push_back(f);
    }
    vehicles = frames.front().boxes.size();
    world->SetTraffic(TrafficTimeline(frames));
    LidarModelValues v;
    v.model = "hesai_xt32";
    v.sensor_id = "roof";
    lidar = std::make_unique<LidarSimulator>(*world, MakeLidarModelParams(v, "bench"), 1);
  }
};

const UrbanScene& Scene() {
  static const UrbanScene scene;
  return scene;
}

// Driving east along the street y = -5.25 at 10 m/s with a gentle yaw rate.
SE3 Pose(TimeNs t_ns) {
  const double t = ToSeconds(t_ns);
  const double x = 200.0 + 10.0 * t;
  return SE3(Quat(Eigen::AngleAxisd(0.02 * std::sin(t), Vec3::UnitZ())),
             Vec3(x, 120.0 - 5.25, DenseTownTerrain(x, 114.75) + 1.9));
}

void BM_Xt32UrbanScan(benchmark::State& state) {
  const UrbanScene& scene = Scene();
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(state.range(0)));
  std::uint64_t scan_index = 0;
  std::size_t points = 0;
  const double cpu_start = ProcessCpuSeconds();
  for (auto _ : state) {
    const LidarScan scan = scene.lidar->SimulateScan(
        Pose, static_cast<TimeNs>(scan_index % 20) * 100'000'000, scan_index);
    points = scan.points->size();
    benchmark::DoNotOptimize(scan.points->data());
    ++scan_index;
  }
  const double cpu_seconds = ProcessCpuSeconds() - cpu_start;
  const double rays = static_cast<double>(scene.lidar->rays_per_scan());
  // CPU time of all threads: the per-core figure, insensitive to other load on the machine.
  state.counters["rays_per_cpu_s"] = rays * static_cast<double>(state.iterations()) / cpu_seconds;
  state.counters["rays_per_s"] = benchmark::Counter(rays * static_cast<double>(state.iterations()),
                                                    benchmark::Counter::kIsRate);
  state.counters["points_per_scan"] = static_cast<double>(points);
  state.counters["buildings"] = scene.buildings;
  state.counters["vehicles"] = static_cast<double>(scene.vehicles);
  state.counters["triangles"] = static_cast<double>(scene.world->triangle_count());
}
BENCHMARK(BM_Xt32UrbanScan)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// One sweep's rays (origin, unit direction; world frame) from the benchmark's pose.
std::vector<std::pair<Vec3, Vec3>> SweepRays(const UrbanScene& scene) {
  const LidarBeamModel& beams = scene.lidar->params().beams;
  std::vector<std::pair<Vec3, Vec3>> rays;
  for (int c = 0; c < beams.columns; ++c) {
    const SE3 T = Pose(beams.ColumnOffsetNs(c));
    for (int r = 0; r < beams.channels(); ++r) {
      rays.emplace_back(T.translation(), T.rotation() * beams.Direction(c, r));
    }
  }
  return rays;
}

// The static-world kernels alone on the same sweep's rays, one thread: CastStatic (our BVH),
// CastStaticBullet (the reference walk through the tiles' Bullet BVHs) and, when built with it,
// Embree (below); rays per CPU second.
// Casts the sweep's rays through `hit` (true when the ray hits) once per iteration and reports
// rays per CPU second and hits per sweep.
template <typename HitFn>
void TimeKernel(benchmark::State& state, const std::vector<std::pair<Vec3, Vec3>>& rays,
                HitFn hit) {
  std::size_t hits = 0;
  const double cpu_start = ProcessCpuSeconds();
  for (auto _ : state) {
    hits = 0;
    for (const auto& [o, d] : rays) hits += hit(o, d) ? 1 : 0;
    benchmark::DoNotOptimize(hits);
  }
  const double cpu_seconds = ProcessCpuSeconds() - cpu_start;
  const double cast = static_cast<double>(rays.size()) * static_cast<double>(state.iterations());
  state.counters["rays_per_cpu_s"] = cast / cpu_seconds;
  state.counters["hits_per_scan"] = static_cast<double>(hits);
}

template <bool kBullet>
void BM_Xt32UrbanStaticKernel(benchmark::State& state) {
  const UrbanScene& scene = Scene();
  const LidarWorld& world = *scene.world;
  const double max_range = scene.lidar->params().max_range_m;
  TimeKernel(state, SweepRays(scene), [&](const Vec3& o, const Vec3& d) {
    return (kBullet ? world.CastStaticBullet(o, d, max_range) : world.CastStatic(o, d, max_range))
        .has_value();
  });
}
BENCHMARK(BM_Xt32UrbanStaticKernel<false>)->Name("BM_Xt32UrbanStaticKernel/bvh")
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Xt32UrbanStaticKernel<true>)->Name("BM_Xt32UrbanStaticKernel/bullet_walk")
    ->Unit(benchmark::kMillisecond);

// CastStaticPacket on the same rays: one channel of 25 adjacent columns per packet, as the
// simulation casts them; the walk the CPU allows (AVX2) or the SSE one.
template <TriangleBvh::PacketKernel kKernel>
void BM_Xt32UrbanStaticKernelPacket(benchmark::State& state) {
  const UrbanScene& scene = Scene();
  const LidarWorld& world = *scene.world;
  const double max_range = scene.lidar->params().max_range_m;
  const int channels = scene.lidar->params().beams.channels();
  const std::vector<std::pair<Vec3, Vec3>> rays = SweepRays(scene);
  const int columns = static_cast<int>(rays.size()) / channels;
  constexpr int kPacket = LidarWorld::kStaticPacketSize;
  std::size_t hits = 0;
  const double cpu_start = ProcessCpuSeconds();
  for (auto _ : state) {
    hits = 0;
    for (int c0 = 0; c0 < columns; c0 += kPacket) {
      const int n = std::min(kPacket, columns - c0);
      for (int r = 0; r < channels; ++r) {
        Vec3 origins[kPacket];
        Vec3 directions[kPacket];
        std::optional<RayHit> out[kPacket];
        for (int k = 0; k < n; ++k) {
          const auto& ray = rays[static_cast<std::size_t>((c0 + k) * channels + r)];
          origins[k] = ray.first;
          directions[k] = ray.second;
        }
        world.CastStaticPacket(origins, directions, n, max_range, out, kKernel);
        for (int k = 0; k < n; ++k) hits += out[k] ? 1 : 0;
      }
    }
    benchmark::DoNotOptimize(hits);
  }
  const double cpu_seconds = ProcessCpuSeconds() - cpu_start;
  const double cast = static_cast<double>(rays.size()) * static_cast<double>(state.iterations());
  state.counters["rays_per_cpu_s"] = cast / cpu_seconds;
  state.counters["hits_per_scan"] = static_cast<double>(hits);
}
BENCHMARK(BM_Xt32UrbanStaticKernelPacket<TriangleBvh::PacketKernel::kBest>)
    ->Name("BM_Xt32UrbanStaticKernel/bvh_packet")
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Xt32UrbanStaticKernelPacket<TriangleBvh::PacketKernel::kSse>)
    ->Name("BM_Xt32UrbanStaticKernel/bvh_packet_sse")
    ->Unit(benchmark::kMillisecond);

#ifdef STATEBENCH_HAVE_EMBREE
// Embree 3 (Debian's build, default scene and build quality, single rays through rtcIntersect1)
// on the same triangles, in float relative to the world's Bullet origin: the per-core limit our
// kernel is measured against. Embree's float ranges are not exact; only the hit count is compared.
void BM_Xt32UrbanStaticKernelEmbree(benchmark::State& state) {
  const UrbanScene& scene = Scene();
  const Vec3 shift = scene.world->bullet_origin_world();
  const double max_range = scene.lidar->params().max_range_m;
  RTCDevice device = rtcNewDevice("threads=1");
  RTCScene rtc_scene = rtcNewScene(device);
  for (const TriangleMesh* mesh : scene.world->tile_meshes()) {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
        mesh->vertices.size()));
    for (std::size_t k = 0; k < mesh->vertices.size(); ++k) {
      const Vec3 v = mesh->vertices[k] - shift;
      vertices[3 * k] = static_cast<float>(v.x());
      vertices[3 * k + 1] = static_cast<float>(v.y());
      vertices[3 * k + 2] = static_cast<float>(v.z());
    }
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
        mesh->triangles.size()));
    for (std::size_t k = 0; k < mesh->triangles.size(); ++k) {
      for (int j = 0; j < 3; ++j) indices[3 * k + j] = static_cast<unsigned>(mesh->triangles[k][j]);
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(rtc_scene, geometry);
    rtcReleaseGeometry(geometry);
  }
  rtcCommitScene(rtc_scene);
  TimeKernel(state, SweepRays(scene), [&](const Vec3& o, const Vec3& d) {
    const Vec3 from = o - shift;
    RTCRayHit rh{};
    rh.ray.org_x = static_cast<float>(from.x());
    rh.ray.org_y = static_cast<float>(from.y());
    rh.ray.org_z = static_cast<float>(from.z());
    rh.ray.dir_x = static_cast<float>(d.x());
    rh.ray.dir_y = static_cast<float>(d.y());
    rh.ray.dir_z = static_cast<float>(d.z());
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = static_cast<float>(max_range);
    rh.ray.mask = ~0u;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect1(rtc_scene, &context, &rh);
    return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  });
  rtcReleaseScene(rtc_scene);
  rtcReleaseDevice(device);
}
BENCHMARK(BM_Xt32UrbanStaticKernelEmbree)->Name("BM_Xt32UrbanStaticKernel/embree")
    ->Unit(benchmark::kMillisecond);
#endif

// Stock Bullet path, static world only, one thread.
void BM_Xt32UrbanScanStockRayTest(benchmark::State& state) {
  const UrbanScene& scene = Scene();
  auto& world = const_cast<LidarWorld&>(*scene.world).collision_world();
  const Vec3 shift = scene.world->bullet_origin_world();
  const LidarBeamModel& beams = scene.lidar->params().beams;
  const double max_range = scene.lidar->params().max_range_m;
  std::size_t hits = 0;
  for (auto _ : state) {
    hits = 0;
    for (int c = 0; c < beams.columns; ++c) {
      const SE3 T = Pose(beams.ColumnOffsetNs(c));
      const Vec3 from = T.translation() - shift;
      for (int r = 0; r < beams.channels(); ++r) {
        const Vec3 to = from + max_range * (T.rotation() * beams.Direction(c, r));
        const btVector3 a(static_cast<btScalar>(from.x()), static_cast<btScalar>(from.y()),
                          static_cast<btScalar>(from.z()));
        const btVector3 b(static_cast<btScalar>(to.x()), static_cast<btScalar>(to.y()),
                          static_cast<btScalar>(to.z()));
        btCollisionWorld::ClosestRayResultCallback callback(a, b);
        world.rayTest(a, b, callback);
        hits += callback.hasHit() ? 1 : 0;
      }
    }
    benchmark::DoNotOptimize(hits);
  }
  const double rays = static_cast<double>(beams.columns * beams.channels());
  state.counters["rays_per_s"] = benchmark::Counter(rays * static_cast<double>(state.iterations()),
                                                    benchmark::Counter::kIsRate);
  state.counters["hits_per_scan"] = static_cast<double>(hits);
}
BENCHMARK(BM_Xt32UrbanScanStockRayTest)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace statebench::sensors
