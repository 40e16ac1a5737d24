// Recorded logs: what LogWriter writes, LogReader gives back exactly (every measurement type,
// lidar points included), in arrival order; the manifest and the setup copy are complete.
#include <gtest/gtest.h>

#include <fstream>
#include <algorithm>
#include <map>
#include <set>
#include <sstream>

#include "core/error.hpp"
#include "core/truth_io.hpp"
#include "log_test_fixtures.hpp"
#include "measurement_bytes.hpp"
#include "sensors/lidar_pcd_io.hpp"

namespace statebench::sensors {
namespace {

using statebench::testing::MeasurementBytes;

void WriteLog(const std::filesystem::path& dir, const std::vector<Measurement>& stream,
              LogWriterOptions options = {}) {
  LogWriter writer(dir, std::move(options));
  for (const Measurement& m : stream) writer.Write(m);
  writer.Close();
}

std::vector<Measurement> ReadAll(LogReader& reader) {
  std::vector<Measurement> out;
  while (auto m = reader.Next()) out.push_back(std::move(*m));
  return out;
}

void ExpectReadsBackBitForBit(LidarFileFormat lidar_format) {
  testing::TempLogDir dir("round_trip_" + std::string(LidarFileFormatName(lidar_format)));
  const std::vector<Measurement> written = testing::SyntheticStream(3.0, 11);
  LogWriterOptions options;
  options.lidar_format = lidar_format;
  WriteLog(dir.path(), written, options);

  LogReader reader(dir.path());
  const std::vector<Measurement> read = ReadAll(reader);
  EXPECT_FALSE(reader.error().has_value()) << *reader.error();
  ASSERT_EQ(read.size(), written.size());
  std::map<std::size_t, int> types;
  std::size_t points = 0;
  for (std::size_t i = 0; i < read.size(); ++i) {
    ASSERT_EQ(MeasurementBytes(read[i]), MeasurementBytes(written[i])) << "measurement " << i;
    ++types[read[i].index()];
    if (const auto* scan = std::get_if<LidarScan>(&read[i])) points += scan->points->size();
  }
  EXPECT_EQ(types.size(), std::variant_size_v<Measurement>);  // every type went through
  EXPECT_EQ(points, 30u * 300u);                              // 31 sweeps, one of them empty
}

TEST(LogRoundTrip, ReadsBackTheWrittenStreamBitForBit) {
  ExpectReadsBackBitForBit(LidarFileFormat::kSweep);
}

TEST(LogRoundTrip, ReadsBackTheWrittenStreamBitForBitWithPcdSweeps) {
  ExpectReadsBackBitForBit(LidarFileFormat::kPcd);
}

TEST(LogRoundTrip, ReadsBackTheWrittenStreamBitForBitWithPacketsFiles) {
  // SyntheticStream's sweeps are arbitrary points, not a lidar's returns: sweep files.
  ExpectReadsBackBitForBit(LidarFileFormat::kPackets);
}

// A lidar's returns in beam order go to packets files, with its beam model; other sweeps, or any
// without a model, to sweep files. All read back bit for bit.
TEST(LogRoundTrip, PacketsFilesForReturnsInBeamOrderSweepFilesForTheRest) {
  testing::TempLogDir dir("packets");
  const LidarBeamModel beams = VelodyneVlp16BeamModel();
  const auto scan = [&](const char* id, TimeNs t_ns, bool beam_order) {
    auto points = std::make_shared<std::vector<LidarPoint>>();
    for (int c = 0; c < beams.columns; c += 7) {
      for (int r = 0; r < beams.channels(); r += 3) {
        points->push_back(BeamReturn(beams.Direction(c, r), 2.0 + 0.37 * r + 0.011 * c,
                                     static_cast<float>(r), beams.ColumnTimeS(c),
                                     static_cast<std::uint16_t>(r)));
      }
    }
    if (!beam_order) std::reverse(points->begin(), points->end());
    LidarScan s;
    s.header = MeasurementHeader{id, t_ns, t_ns + 100'000'000};
    s.points = points;
    return Measurement(s);
  };
  const std::vector<Measurement> written = {scan("roof", 0, true), scan("rear", 0, true),
                                            scan("roof", 100'000'000, false)};
  LogWriterOptions options;
  options.lidar_format = LidarFileFormat::kPackets;
  options.lidar_beams["roof"] = beams;  // none for "rear"
  WriteLog(dir.path(), written, options);
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "lidar/roof/0.packets"));
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "lidar/roof/100000000.sweep"));
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "lidar/rear/0.sweep"));
  LogReader reader(dir.path());
  const std::vector<Measurement> read = ReadAll(reader);
  EXPECT_FALSE(reader.error().has_value()) << *reader.error();
  ASSERT_EQ(read.size(), written.size());
  std::multiset<std::string> read_bytes, written_bytes;
  for (std::size_t i = 0; i < read.size(); ++i) {
    read_bytes.insert(MeasurementBytes(read[i]));
    written_bytes.insert(MeasurementBytes(written[i]));
  }
  EXPECT_EQ(read_bytes, written_bytes);
}

TEST(LogRoundTrip, WritesManifestSetupTruthAndEuRocImu) {
  testing::TempLogDir dir("manifest");
  const std::vector<Measurement> written = testing::SyntheticStream(1.0, 3);
  LogWriterOptions options;
  options.scenario = "synthetic \"drive\"";
  options.seed = 42;
  options.origin = GeodeticPoint{48.7846, 2.136, 130.25};
  options.setup_yaml = "name: test_setup\nsensors: []\n";
  // A mount off the identity by a turn that no short decimal writes exactly.
  options.truth_T_body_imu =
      SE3(Quat(Eigen::AngleAxisd(0.0031, Vec3(0.3, -0.2, 0.9).normalized())),
          Vec3(0.011, -0.0037, 0.5));
  {
    LogWriter writer(dir.path(), options);
    for (const Measurement& m : written) writer.Write(m);
    for (TimeNs t = 0; t <= 1000 * kNsPerMillisecond; t += kNsPerMillisecond) {
      TruthSample s;
      s.t_ns = t;
      s.body.T_world_frame = SE3(Quat::Identity(), Vec3(ToSeconds(t), 0.0, 0.0));
      writer.WriteTruth(s);
    }
    const LogManifest& m = writer.Close();
    EXPECT_EQ(m.streams.size(), 9u);
  }
  const LogManifest m = ReadLogManifest(dir.path() / "log.yaml");
  EXPECT_EQ(m.scenario, "synthetic \"drive\"");
  EXPECT_EQ(m.seed, 42u);
  ASSERT_TRUE(m.origin.has_value());
  EXPECT_EQ(m.origin->latitude_deg, 48.7846);
  EXPECT_EQ(m.origin->longitude_deg, 2.136);
  EXPECT_EQ(m.origin->altitude_m, 130.25);
  ASSERT_TRUE(m.setup.has_value());
  std::ifstream setup(dir.path() / *m.setup);
  std::stringstream text;
  text << setup.rdbuf();
  EXPECT_EQ(text.str(), options.setup_yaml);
  std::map<std::string, LogStreamEntry> by_id;
  for (const LogStreamEntry& e : m.streams) by_id[e.id] = e;
  EXPECT_EQ(by_id.at("imu").file, "imu/imu.csv");
  EXPECT_EQ(by_id.at("imu").count, 101u);
  EXPECT_EQ(by_id.at("gnss_rear").file, "gnss/gnss_rear.csv");
  EXPECT_EQ(by_id.at("gnss_heading").type, LogStreamType::kDualAntennaHeading);
  EXPECT_EQ(by_id.at("lidar").file, "lidar/lidar.csv");
  EXPECT_EQ(by_id.at("lidar").count, 11u);
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "lidar/lidar/0.pcd"));
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "lidar/lidar/100000000.pcd"));

  // The IMU file is EuRoC's imu0/data.csv plus the arrival column.
  std::ifstream imu(dir.path() / "imu/imu.csv");
  std::string header;
  std::getline(imu, header);
  EXPECT_EQ(header,
            "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
            "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2],arrival [ns]");

  ASSERT_TRUE(m.truth_csv.has_value());
  // The mount the truth's IMU columns were written through, bit for bit.
  ASSERT_TRUE(m.truth_imu_mount.has_value());
  EXPECT_EQ(m.truth_imu_mount->translation(), options.truth_T_body_imu->translation());
  EXPECT_EQ(m.truth_imu_mount->rotation().coeffs(), options.truth_T_body_imu->rotation().coeffs());
  const TruthReadResult truth = ReadTruthCsv(dir.path() / *m.truth_csv);
  EXPECT_FALSE(truth.error.has_value());
  EXPECT_EQ(truth.samples.size(), 1001u);
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "truth_imu.tum"));
}

TEST(LogRoundTrip, PcdFilesAreReadableAsPlainPcd) {
  testing::TempLogDir dir("pcd");
  std::filesystem::create_directories(dir.path());
  const std::vector<LidarPoint> points = {{1.f, -2.f, 3.5f, 40.f, 0.05f, 7},
                                          {-0.f, 1e-40f, -3e38f, 0.f, 0.0999f, 31}};
  WriteLidarPcd(dir.path() / "a.pcd", points);
  std::ifstream in(dir.path() / "a.pcd", std::ios::binary);
  std::string line;
  std::vector<std::string> header;
  while (std::getline(in, line) && line.rfind("DATA", 0) != 0) header.push_back(line);
  EXPECT_EQ(line, "DATA binary");
  EXPECT_NE(std::find(header.begin(), header.end(), "FIELDS x y z intensity t ring"), header.end());
  EXPECT_NE(std::find(header.begin(), header.end(), "TYPE F F F F F U"), header.end());
  EXPECT_NE(std::find(header.begin(), header.end(), "SIZE 4 4 4 4 4 2"), header.end());
  EXPECT_NE(std::find(header.begin(), header.end(), "POINTS 2"), header.end());
  const std::vector<LidarPoint> back = ReadLidarPcd(dir.path() / "a.pcd");
  ASSERT_EQ(back.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(std::bit_cast<std::uint32_t>(back[i].x), std::bit_cast<std::uint32_t>(points[i].x));
    EXPECT_EQ(std::bit_cast<std::uint32_t>(back[i].y), std::bit_cast<std::uint32_t>(points[i].y));
    EXPECT_EQ(std::bit_cast<std::uint32_t>(back[i].z), std::bit_cast<std::uint32_t>(points[i].z));
    EXPECT_EQ(back[i].ring, points[i].ring);
  }
  WriteLidarPcd(dir.path() / "empty.pcd", {});
  EXPECT_TRUE(ReadLidarPcd(dir.path() / "empty.pcd").empty());
}

GnssFix SingleFix(const char* id, TimeNs t_ns) {
  GnssFix fix;
  fix.header = {id, t_ns, t_ns + 10};
  fix.latitude_deg = 48.0;
  fix.longitude_deg = 2.0;
  fix.altitude_m = 100.0;
  fix.covariance_enu = Mat3::Identity();
  fix.status = GnssFixStatus::kSingle;
  return fix;
}

TEST(LogWriter, RejectsWhatCouldNotBeReadBack) {
  testing::TempLogDir dir("writer_checks");
  LogWriter writer(dir.path(), {});
  writer.Write(VehicleSpeed{{"speed", 20, 30}, 1.0});
  EXPECT_THROW(writer.Write(VehicleSpeed{{"speed", 20, 40}, 1.0}), InputError);   // same stamp
  EXPECT_THROW(writer.Write(VehicleSpeed{{"speed", 30, 25}, 1.0}), InputError);   // arrival back
  EXPECT_THROW(writer.Write(SteeringAngle{{"speed", 40, 50}, 0.1}), InputError);  // other type
  EXPECT_THROW(writer.Write(SteeringAngle{{"a/b", 40, 50}, 0.1}), InputError);    // not a name
  EXPECT_THROW(writer.WriteTruth(TruthSample{}), InputError);  // no truth mount given
  // A gnss file takes its columns from its first fix: a velocity after fixes without one needs
  // the sensor in gnss_velocity_ids.
  GnssFix fix = SingleFix("gnss", 10);
  writer.Write(fix);
  fix.header = {"gnss", 20, 30};
  fix.velocity = GnssVelocity{Vec3(1.0, 2.0, 0.0), Vec3(0.1, 0.1, 0.2)};
  EXPECT_THROW(writer.Write(fix), InputError);
  writer.Close();
  EXPECT_THROW(LogWriter(dir.path(), {}), InputError);  // a log is already there
}

// A gnss file without the velocity columns (every log written before them) reads as before;
// gnss_velocity_ids gives a file the columns from its first fix on.
TEST(LogWriter, GnssVelocityColumnsOnlyWhereAsked) {
  testing::TempLogDir dir("gnss_velocity_ids");
  LogWriterOptions options;
  options.gnss_velocity_ids = {"late"};
  LogWriter writer(dir.path(), options);
  GnssFix fix = SingleFix("plain", 10);
  writer.Write(fix);
  fix.header = {"late", 10, 20};
  writer.Write(fix);
  fix.header = {"late", 20, 30};
  fix.velocity = GnssVelocity{Vec3(1.0, 2.0, 0.0), Vec3(0.1, 0.1, 0.2)};
  writer.Write(fix);
  writer.Close();
  std::ifstream plain(dir.path() / "gnss/plain.csv");
  std::string header;
  std::getline(plain, header);
  EXPECT_EQ(header.find("ve [m s^-1]"), std::string::npos) << header;
  LogReader reader(dir.path());
  const std::vector<Measurement> read = ReadAll(reader);
  EXPECT_FALSE(reader.error().has_value()) << *reader.error();
  ASSERT_EQ(read.size(), 3u);
  int with_velocity = 0;
  for (const Measurement& m : read) {
    const auto& f = std::get<GnssFix>(m);
    if (f.velocity) {
      ++with_velocity;
      EXPECT_EQ(f.header.sensor_id, "late");
      EXPECT_EQ(f.velocity->v_enu, Vec3(1.0, 2.0, 0.0));
      EXPECT_EQ(f.velocity->sigma_enu, Vec3(0.1, 0.1, 0.2));
    }
  }
  EXPECT_EQ(with_velocity, 1);
}

}  // namespace
}  // namespace statebench::sensors
