// Recorded logs with bad content: the reader names the file, the line and the column, returns
// everything merged before the bad row and then stops.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "log_test_fixtures.hpp"
#include "measurement_bytes.hpp"

namespace statebench::sensors {
namespace {

using statebench::testing::MeasurementBytes;

struct BadLog {
  testing::TempLogDir dir;
  std::vector<Measurement> written;

  explicit BadLog(const std::string& name, LidarFileFormat lidar = LidarFileFormat::kSweep)
      : dir(name) {
    written = testing::SyntheticStream(2.0, 5, 50);
    LogWriterOptions options;
    options.lidar_format = lidar;
    LogWriter writer(dir.path(), options);
    for (const Measurement& m : written) writer.Write(m);
    writer.Close();
  }

  std::vector<std::string> Lines(const std::string& file) const {
    std::ifstream in(dir.path() / file);
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    return lines;
  }
  void Rewrite(const std::string& file, const std::vector<std::string>& lines) const {
    std::ofstream out(dir.path() / file, std::ios::trunc);
    for (const std::string& l : lines) out << l << "\n";
  }
  // Replaces cell `column` of line `line` (1-based, the header is line 1).
  void SetCell(const std::string& file, std::size_t line, std::size_t column,
               const std::string& value) const {
    std::vector<std::string> lines = Lines(file);
    std::vector<std::string> cells;
    std::stringstream row(lines.at(line - 1));
    for (std::string c; std::getline(row, c, ',');) cells.push_back(c);
    cells.at(column) = value;
    std::string joined;
    for (std::size_t i = 0; i < cells.size(); ++i) joined += (i ? "," : "") + cells[i];
    lines[line - 1] = joined;
    Rewrite(file, lines);
  }

  // The written stream up to and including the `n`-th (1-based) measurement of `id`: what a
  // reader must return when the row after it is bad.
  std::vector<Measurement> PrefixThrough(const std::string& id, std::size_t n) const {
    std::vector<Measurement> out;
    std::size_t seen = 0;
    for (const Measurement& m : written) {
      if (n == 0) break;
      out.push_back(m);
      if (HeaderOf(m).sensor_id == id && ++seen == n) break;
    }
    return out;
  }
};

// Reads to the end; returns the measurements and the error message ("" when none).
std::pair<std::vector<Measurement>, std::string> ReadAll(const std::filesystem::path& dir) {
  LogReader reader(dir);
  std::vector<Measurement> out;
  while (auto m = reader.Next()) out.push_back(std::move(*m));
  EXPECT_FALSE(reader.Next().has_value());  // stays ended
  return {out, reader.error().value_or("")};
}

void ExpectSameStream(const std::vector<Measurement>& a, const std::vector<Measurement>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(MeasurementBytes(a[i]), MeasurementBytes(b[i])) << i;
  }
}

TEST(LogBadInput, NanNamesFileLineColumnAndKeepsWhatCameBefore) {
  BadLog log("nan");
  log.SetCell("imu/imu.csv", 31, 2, "nan");  // the 30th sample's gyro y
  const auto [read, error] = ReadAll(log.dir.path());
  EXPECT_NE(error.find("imu/imu.csv:31: column 'w_RS_S_y [rad s^-1]'"), std::string::npos) << error;
  EXPECT_NE(error.find("not finite"), std::string::npos) << error;
  ExpectSameStream(read, log.PrefixThrough("imu", 29));
}

TEST(LogBadInput, MissingColumnInTheHeader) {
  BadLog log("missing_header_column");
  std::vector<std::string> lines = log.Lines("gnss/gnss_rear.csv");
  lines[0] = "#timestamp [ns],arrival [ns],latitude [deg],longitude [deg],cov_ee [m^2]";
  log.Rewrite("gnss/gnss_rear.csv", lines);
  const auto [read, error] = ReadAll(log.dir.path());
  EXPECT_NE(error.find("gnss/gnss_rear.csv:1: missing column 'altitude [m]'"), std::string::npos)
      << error;
  EXPECT_TRUE(read.empty());  // the file is unusable from its first line
}

TEST(LogBadInput, MissingValueInARow) {
  BadLog log("missing_value");
  std::vector<std::string> lines = log.Lines("speed/speed.csv");
  lines[20] = lines[20].substr(0, lines[20].rfind(','));  // line 21 loses its speed
  log.Rewrite("speed/speed.csv", lines);
  const auto [read, error] = ReadAll(log.dir.path());
  EXPECT_NE(error.find("speed/speed.csv:21: column 'speed [m s^-1]': missing value"),
            std::string::npos)
      << error;
  ExpectSameStream(read, log.PrefixThrough("speed", 19));
}

TEST(LogBadInput, TimestampGoingBackwards) {
  BadLog log("backwards");
  const std::vector<std::string> lines = log.Lines("gnss/gnss_front.csv");
  const std::string earlier = lines[4].substr(0, lines[4].find(','));  // 4th fix's stamp
  log.SetCell("gnss/gnss_front.csv", 8, 0, earlier);                   // on the 7th fix
  const auto [read, error] = ReadAll(log.dir.path());
  EXPECT_NE(error.find("gnss/gnss_front.csv:8: column 'timestamp [ns]': timestamp " + earlier +
                       " is not after the previous"),
            std::string::npos)
      << error;
  ExpectSameStream(read, log.PrefixThrough("gnss_front", 6));
}

// gnss_front's file has the velocity columns (every other fix has a velocity: lines 2, 4, ...).
TEST(LogBadInput, GnssVelocityCellsAreAllNumbersOrAllEmpty) {
  BadLog log("velocity_half_empty");
  log.SetCell("gnss/gnss_front.csv", 6, 16, "");  // the 5th fix loses vn but keeps the rest
  const auto [read, error] = ReadAll(log.dir.path());
  EXPECT_NE(error.find("gnss/gnss_front.csv:6: column 'vn [m s^-1]': missing value"),
            std::string::npos)
      << error;
  ExpectSameStream(read, log.PrefixThrough("gnss_front", 4));
}

TEST(LogBadInput, GnssVelocitySigmaMustBePositive) {
  BadLog log("velocity_sigma");
  log.SetCell("gnss/gnss_front.csv", 4, 20, "0");
  const auto [read, error] = ReadAll(log.dir.path());
  EXPECT_NE(error.find("gnss/gnss_front.csv:4: column 'sigma_vu [m s^-1]': must be > 0"),
            std::string::npos)
      << error;
}

TEST(LogBadInput, UnknownExtraGnssColumn) {
  BadLog log("gnss_extra_column");
  std::vector<std::string> lines = log.Lines("gnss/gnss_rear.csv");
  lines[0] += ",speed [m s^-1]";
  log.Rewrite("gnss/gnss_rear.csv", lines);
  const auto [read, error] = ReadAll(log.dir.path());
  EXPECT_NE(error.find("gnss/gnss_rear.csv:1: unexpected column 'speed [m s^-1]' at position 16"),
            std::string::npos)
      << error;
  EXPECT_TRUE(read.empty());
}

TEST(LogBadInput, TruncatedPcdNamesThePcdAndItsIndexLine) {
  BadLog log("truncated_pcd", LidarFileFormat::kPcd);
  const std::filesystem::path pcd = log.dir.path() / "lidar/lidar/400000000.pcd";  // 5th sweep
  // Cut inside the point data: the header and 10 of the 50 points stay. (PCL's writer leaves
  // zero padding after the data, so cutting the file's last bytes would lose nothing.)
  std::ifstream in(pcd, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t data_start = bytes.find("DATA binary\n") + 12;
  std::filesystem::resize_file(pcd, data_start + 10 * 22);
  const auto [read, error] = ReadAll(log.dir.path());
  EXPECT_NE(error.find("lidar/lidar/400000000.pcd: truncated"), std::string::npos) << error;
  EXPECT_NE(error.find("lidar/lidar.csv:6"), std::string::npos) << error;
  ExpectSameStream(read, log.PrefixThrough("lidar", 4));
}

TEST(LogBadInput, TruncatedSweepFileNamesTheFileTheFieldAndItsIndexLine) {
  BadLog log("truncated_sweep");
  const std::filesystem::path sweep = log.dir.path() / "lidar/lidar/400000000.sweep";  // 5th
  std::filesystem::resize_file(sweep, std::filesystem::file_size(sweep) - 7);
  const auto [read, error] = ReadAll(log.dir.path());
  EXPECT_NE(error.find("lidar/lidar/400000000.sweep: field 'intensity': truncated"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("lidar/lidar.csv:6"), std::string::npos) << error;
  ExpectSameStream(read, log.PrefixThrough("lidar", 4));
}

TEST(LogBadInput, MissingPcdAndPointCountMismatch) {
  {
    BadLog log("missing_pcd", LidarFileFormat::kPcd);
    std::filesystem::remove(log.dir.path() / "lidar/lidar/0.pcd");
    const auto [read, error] = ReadAll(log.dir.path());
    EXPECT_NE(error.find("lidar/lidar/0.pcd: no such file"), std::string::npos) << error;
    EXPECT_TRUE(read.empty());
  }
  {
    BadLog log("count_mismatch");
    log.SetCell("lidar/lidar.csv", 3, 2, "49");
    const auto [read, error] = ReadAll(log.dir.path());
    EXPECT_NE(error.find("holds 0 points, the index says 49"), std::string::npos) << error;
  }
}

TEST(LogBadInput, BadManifestThrows) {
  BadLog log("manifest");
  std::vector<std::string> lines = log.Lines("log.yaml");
  for (std::string& l : lines) {
    if (l.find("type: imu") != std::string::npos) l.replace(l.find("imu,"), 4, "imuu,");
  }
  log.Rewrite("log.yaml", lines);
  try {
    LogReader reader(log.dir.path());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("log.yaml:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("unknown type 'imuu'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(LogReader(log.dir.path() / "nowhere"), InputError);
}

}  // namespace
}  // namespace statebench::sensors
