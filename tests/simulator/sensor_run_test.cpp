// The wired pipeline on the paper's setup 2 (quadricycle, front GNSS CEP 2 m, Hesai XT32, IMU,
// encoders) over a short drive: one stream in arrival order, every sensor at its rate, lidar
// sweeps whose points are where the world's surfaces are, and the same seed giving the same bits.
#include "simulator/sensor_run.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>

#include "sensors/lidar_beam_model.hpp"
#include "sensors/log_reader.hpp"
#include "sensors/log_writer.hpp"
#include "tests/sensors/measurement_bytes.hpp"
#include "tests/simulator/sumo_test_support.hpp"

namespace statebench::sim {
namespace {

using testing::SourceDir;

std::filesystem::path WorkDir(const std::string& name) {
  return testing::FreshWorkDir("sensor_run", name);
}

Scenario Setup2(double duration_s) {
  Scenario s = LoadScenario(SourceDir() / "scenarios/paper/setup2_quadricycle.yaml");
  s.mismatch.reset();  // the stream's structure, with the setup's own stamps and mounts
  s.duration_s = duration_s;
  return s;
}

// T_world_body at any time of the recorded 1 kHz truth (geodesic between samples, as the lidar
// model does; the lidar tests check that against exact trajectories).
class TruthPoses {
 public:
  void Add(const TruthSample& s) { poses_.emplace_back(s.t_ns, s.body.T_world_frame); }
  SE3 At(TimeNs t_ns) const {
    const auto after = std::lower_bound(poses_.begin(), poses_.end(), t_ns,
                                        [](const auto& p, TimeNs t) { return p.first < t; });
    if (after->first == t_ns) return after->second;
    const auto before = std::prev(after);
    const double a = static_cast<double>(t_ns - before->first) /
                     static_cast<double>(after->first - before->first);
    return SE3::Interpolate(before->second, after->second, a);
  }
  std::size_t size() const { return poses_.size(); }

 private:
  std::vector<std::pair<TimeNs, SE3>> poses_;
};

struct LidarCheck {
  int points = 0;
  int on_static_surface = 0;  // within 5 sigma of the static world along the beam
  int in_front = 0;           // closer than the static world: traffic
  int behind = 0;             // beyond the static surface: impossible
  double max_ring_error_rad = 0.0;
  double max_azimuth_error_rad = 0.0;
};

// Deskews every 53rd point of a sweep with the truth and casts its beam into the static world.
void CheckSweep(const LidarScan& scan, const TruthPoses& truth, const SE3& T_body_lidar,
                const sensors::LidarWorld& world, LidarCheck* check) {
  const sensors::LidarBeamModel beams = sensors::HesaiXt32BeamModel();
  const double column_s = 0.1 / beams.columns;
  for (std::size_t i = 0; i < scan.points->size(); i += 53) {
    const LidarPoint& p = (*scan.points)[i];
    const Vec3 p_lidar(p.x, p.y, p.z);
    const double range = p_lidar.norm();
    const double elevation = std::asin(p_lidar.z() / range);
    check->max_ring_error_rad =
        std::max(check->max_ring_error_rad, std::abs(elevation - beams.elevations_rad.at(p.ring)));
    const int column = static_cast<int>(std::lround(p.t / column_s));
    const double azimuth_error = std::remainder(
        std::atan2(p_lidar.y(), p_lidar.x()) - beams.ColumnAzimuthRad(column), 2.0 * M_PI);
    check->max_azimuth_error_rad = std::max(check->max_azimuth_error_rad, std::abs(azimuth_error));

    const SE3 T_world_lidar = truth.At(scan.header.stamp_ns + FromSeconds(p.t)) * T_body_lidar;
    const Vec3 direction = T_world_lidar.rotation() * (p_lidar / range);
    const auto hit = world.CastStatic(T_world_lidar.translation(), direction, 130.0);
    ++check->points;
    if (hit && std::abs(hit->range_m - range) < 0.05) {
      ++check->on_static_surface;
    } else if (!hit || range < hit->range_m) {
      ++check->in_front;
    } else {
      ++check->behind;
    }
  }
}

TEST(SensorRun, Setup2StreamInArrivalOrderWithLidarOnTheWorld) {
  constexpr double kSeconds = 10.0;
  SensorRun run(Setup2(kSeconds), WorkDir("setup2"));
  ASSERT_NE(run.world(), nullptr);
  TruthPoses truth;
  run.SetTruthObserver([&](const TruthSample& s) { truth.Add(s); });
  const SE3 T_body_lidar = run.sensors().setup.Find("lidar_roof")->spec.T_body_sensor;

  std::map<std::string, int> count;
  std::optional<Measurement> previous;
  LidarCheck check;
  std::size_t min_points = 1u << 30, max_points = 0;
  int sweeps_with_traffic = 0;
  while (std::optional<Measurement> m = run.Next()) {
    const MeasurementHeader& h = HeaderOf(*m);
    ++count[h.sensor_id];
    if (previous) {
      ASSERT_FALSE(sensors::ArrivesBefore(*m, *previous)) << h.sensor_id << " " << h.stamp_ns;
    }
    if (const auto* scan = std::get_if<LidarScan>(&*m)) {
      EXPECT_EQ(h.stamp_ns % (100 * kNsPerMillisecond), 0);
      EXPECT_EQ(h.arrival_ns, h.stamp_ns + 120 * kNsPerMillisecond);  // sweep + 20 ms latency
      min_points = std::min(min_points, scan->points->size());
      max_points = std::max(max_points, scan->points->size());
      for (const LidarPoint& p : *scan->points) {
        ASSERT_LT(p.ring, 32);
        ASSERT_GE(p.t, 0.f);
        ASSERT_LT(p.t, 0.1f);
      }
      if (count[h.sensor_id] % 10 == 5) {  // the truth up to this sweep's end is recorded
        const int before = check.in_front;
        CheckSweep(*scan, truth, T_body_lidar, *run.world(), &check);
        sweeps_with_traffic += check.in_front > before ? 1 : 0;
      }
      previous = Measurement(VehicleSpeed{h, 0.0});  // keep the header, drop the points
    } else {
      previous = std::move(m);
    }
  }
  EXPECT_EQ(truth.size(), 10001u);
  // From t = 0 to 10 s inclusive; encoders start counting at their first sample.
  EXPECT_EQ(count["imu"], 1001);
  EXPECT_EQ(count["steering"], 501);
  EXPECT_EQ(count["speed"], 500);
  EXPECT_EQ(count["gnss_front"], 101);  // no urban canyon in the paper scenario
  EXPECT_EQ(count["lidar_roof"], 100);  // sweeps from 0 to 9.9 s, each complete at +0.1 s
  // XT32: 64,000 beams a sweep, 2 % dropout; the 16 upward beams mostly see sky, buildings and
  // trees; the downward ones the road.
  std::printf(
      "points per sweep: %zu .. %zu; checked %d points: %d on static surfaces, %d in "
      "front (traffic, %d sweeps), %d behind; ring error %.2g rad, azimuth error %.2g rad\n",
      min_points, max_points, check.points, check.on_static_surface, check.in_front,
      sweeps_with_traffic, check.behind, check.max_ring_error_rad, check.max_azimuth_error_rad);
  EXPECT_GT(min_points, 32000u);
  EXPECT_LE(max_points, 64000u * 99 / 100);
  EXPECT_GT(check.points, 5000);
  EXPECT_EQ(check.behind, 0);
  EXPECT_GT(check.on_static_surface, check.points * 95 / 100);
  EXPECT_LT(check.max_ring_error_rad, 1e-5);
  EXPECT_LT(check.max_azimuth_error_rad, 1e-5);
}

// FNV-1a over every bit of the stream.
std::uint64_t StreamDigest(sensors::MeasurementSource& source, std::size_t* count) {
  std::uint64_t h = 1469598103934665603ull;
  *count = 0;
  while (std::optional<Measurement> m = source.Next()) {
    ++*count;
    for (const char c : statebench::testing::MeasurementBytes(*m)) {
      h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
    }
  }
  return h;
}

TEST(SensorRun, SameSeedSameBitsOtherSensorSeedOtherBits) {
  std::size_t n1 = 0, n2 = 0, n3 = 0;
  std::uint64_t d1 = 0, d2 = 0, d3 = 0;
  {
    SensorRun run(Setup2(2.0), WorkDir("seed_a"));
    d1 = StreamDigest(run, &n1);
  }
  {
    SensorRun run(Setup2(2.0), WorkDir("seed_b"));
    d2 = StreamDigest(run, &n2);
  }
  {
    SensorRunOptions options;
    options.sensor_seed = 7;
    SensorRun run(Setup2(2.0), WorkDir("seed_c"), options);
    d3 = StreamDigest(run, &n3);
  }
  EXPECT_GT(n1, 300u);
  EXPECT_EQ(n1, n2);
  EXPECT_EQ(d1, d2);
  EXPECT_EQ(n1, n3);  // same schedule
  EXPECT_NE(d1, d3);  // other errors
}

// What `statebench record` does, then the reader: the same stream, bit for bit. Setup 1 has every
// simulated type but generic body velocity (two antennas and their heading, wheels, steering,
// speed, XT32, IMU).
TEST(SensorRun, RecordedSetup1LogReadsBackBitForBit) {
  Scenario scenario = LoadScenario(SourceDir() / "scenarios/paper/setup1_quadricycle.yaml");
  scenario.duration_s = 2.0;
  const auto dir = WorkDir("record");
  SensorRun run(scenario, dir / "sim");
  sensors::LogWriterOptions options;
  options.scenario = scenario.name;
  options.seed = scenario.seed;
  options.origin = scenario.origin;
  options.setup_yaml = run.sensors().setup_yaml;
  options.truth_T_body_imu = run.T_body_imu();
  sensors::LogWriter writer(dir / "log", options);
  run.SetTruthObserver([&](const TruthSample& s) { writer.WriteTruth(s); });
  std::vector<std::string> written;
  std::map<std::size_t, int> types;
  while (std::optional<Measurement> m = run.Next()) {
    writer.Write(*m);
    written.push_back(statebench::testing::MeasurementBytes(*m));
    ++types[m->index()];
  }
  writer.Close();
  EXPECT_EQ(types.size(), 7u);

  sensors::LogReader reader(dir / "log");
  std::size_t i = 0;
  while (std::optional<Measurement> m = reader.Next()) {
    ASSERT_LT(i, written.size());
    ASSERT_EQ(statebench::testing::MeasurementBytes(*m), written[i]) << i;
    ++i;
  }
  EXPECT_FALSE(reader.error().has_value()) << *reader.error();
  EXPECT_EQ(i, written.size());
  ASSERT_TRUE(reader.setup_file().has_value());
  EXPECT_EQ(sensors::LoadSensorSetup(*reader.setup_file()).name, "setup1_quadricycle");
  std::filesystem::remove_all(dir);
}

TEST(SensorRun, UrbanCanyonOnRequestDegradesTheFixes) {
  SensorRunOptions options;
  options.urban_canyon = true;
  SensorRun run(Setup2(4.0), WorkDir("canyon"), options);
  std::map<GnssFixStatus, int> status;
  while (std::optional<Measurement> m = run.Next()) {
    if (const auto* fix = std::get_if<GnssFix>(&*m)) ++status[fix->status];
  }
  int fixes = 0;
  for (const auto& [s, n] : status) fixes += n;
  std::printf("setup 2 in the canyon: %d of 41 fixes\n", fixes);
  // Single point needs 4 satellites; between the town's buildings some epochs have fewer.
  EXPECT_LT(fixes, 41);
  EXPECT_GT(fixes, 0);
}

}  // namespace
}  // namespace statebench::sim
