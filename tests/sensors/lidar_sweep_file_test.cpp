// StateBench sweep files (lidar_sweep_file.hpp): every field of every point comes back bit for
// bit, whatever the values; a damaged file is refused with an InputError naming it and the field.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>

#include "core/error.hpp"
#include "core/random.hpp"
#include "log_test_fixtures.hpp"
#include "lidar_test_fixtures.hpp"
#include "sensors/lidar_file.hpp"
#include "sensors/lidar_sweep_file.hpp"

namespace statebench::sensors {
namespace {

using testing::ExpectSameBits;

constexpr std::size_t kSweepHeaderBytes = 40;

std::vector<LidarPoint> SweepRoundTrip(const testing::TempLogDir& dir,
                                       const std::vector<LidarPoint>& points) {
  const std::filesystem::path file = dir.path() / "a.sweep";
  WriteLidarSweepFile(file, points);
  return ReadLidarSweepFile(file);
}

// A spinning lidar's sweep as the simulator makes it: 32 rings x `columns` columns, points
// range x direction rounded to float, a few rings missing per column, intensity smooth.
std::vector<LidarPoint> SpinningSweep(int columns, std::uint64_t seed) {
  std::mt19937_64 rng = MakeRng(seed, "sweep_file_test");
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<LidarPoint> points;
  for (int c = 0; c < columns; ++c) {
    const double azimuth = 2.0 * std::numbers::pi * c / columns;
    for (int ring = 0; ring < 32; ++ring) {
      if (unit(rng) < 0.1) continue;
      const double elevation = (-16.0 + ring) * std::numbers::pi / 180.0;
      const double range = 5.0 + 20.0 * (1.0 + std::sin(3.0 * azimuth)) + 0.01 * unit(rng);
      points.push_back(LidarPoint{
          static_cast<float>(range * std::cos(elevation) * std::cos(azimuth)),
          static_cast<float>(range * std::cos(elevation) * std::sin(azimuth)),
          static_cast<float>(range * std::sin(elevation)),
          static_cast<float>(50.0 + 40.0 * std::cos(azimuth + ring)),
          static_cast<float>(0.1 * c / columns), static_cast<std::uint16_t>(ring)});
    }
  }
  return points;
}

std::string FileBytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void WriteBytes(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
}

// The InputError message of reading `file` ("" when it reads).
std::string SweepReadError(const std::filesystem::path& file) {
  try {
    ReadLidarSweepFile(file);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(LidarSweepFile, SpinningSweepRoundTripsAndCompresses) {
  testing::TempLogDir dir("sweep_spinning");
  std::filesystem::create_directories(dir.path());
  const std::vector<LidarPoint> points = SpinningSweep(500, 1);
  ExpectSameBits(SweepRoundTrip(dir, points), points);
  const auto bytes = std::filesystem::file_size(dir.path() / "a.sweep");
  EXPECT_LT(bytes, points.size() * 22 / 3) << "about a fifth of a binary PCD expected";
}

TEST(LidarSweepFile, AnyBitsRoundTrip) {
  testing::TempLogDir dir("sweep_any_bits");
  std::filesystem::create_directories(dir.path());
  std::mt19937_64 rng = MakeRng(7, "sweep_any_bits");
  std::vector<LidarPoint> points(3000);
  for (LidarPoint& p : points) {  // every bit pattern: NaNs with payloads, infinities, subnormals
    p = LidarPoint{std::bit_cast<float>(static_cast<std::uint32_t>(rng())),
                   std::bit_cast<float>(static_cast<std::uint32_t>(rng())),
                   std::bit_cast<float>(static_cast<std::uint32_t>(rng())),
                   std::bit_cast<float>(static_cast<std::uint32_t>(rng())),
                   std::bit_cast<float>(static_cast<std::uint32_t>(rng() % 4)),
                   static_cast<std::uint16_t>(rng())};
  }
  ExpectSameBits(SweepRoundTrip(dir, points), points);
}

TEST(LidarSweepFile, SpecialValuesEmptyAndOnePoint) {
  testing::TempLogDir dir("sweep_special");
  std::filesystem::create_directories(dir.path());
  const float inf = std::numeric_limits<float>::infinity();
  const float nan_payload = std::bit_cast<float>(0x7fc12345u);
  const float signalling = std::bit_cast<float>(0xff800001u);
  const float subnormal = std::numeric_limits<float>::denorm_min() * 3;
  // Special values inside a sweep whose other points make every prediction formula run.
  std::vector<LidarPoint> points = SpinningSweep(40, 2);
  const std::vector<LidarPoint> special = {
      {inf, -inf, nan_payload, signalling, 0.f, 0},
      {subnormal, -subnormal, -0.f, 0.f, 0.f, 1},
      {0.f, 1.f, subnormal, inf, 0.f, 65535},
      {std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(),
       std::numeric_limits<float>::min(), nan_payload, nan_payload, 2},
      {1e-30f, 1e30f, -1e-38f, 1.f, inf, 3}};
  points.insert(points.begin() + 100, special.begin(), special.end());
  points.insert(points.end(), special.begin(), special.end());
  ExpectSameBits(SweepRoundTrip(dir, points), points);
  ExpectSameBits(SweepRoundTrip(dir, special), special);
  EXPECT_TRUE(SweepRoundTrip(dir, {}).empty());
  const std::vector<LidarPoint> one = {{1.5f, -2.25f, 0.125f, 12.f, 0.05f, 17}};
  ExpectSameBits(SweepRoundTrip(dir, one), one);
}

TEST(LidarSweepFile, LidarFileDispatchesOnTheExtension) {
  testing::TempLogDir dir("sweep_dispatch");
  std::filesystem::create_directories(dir.path());
  const std::vector<LidarPoint> points = SpinningSweep(20, 3);
  for (const LidarFileFormat format : {LidarFileFormat::kSweep, LidarFileFormat::kPcd}) {
    const std::string name = WriteLidarFile(dir.path(), "a", points, format);
    EXPECT_EQ(name, "a" + std::string(LidarFileExtension(format)));
    ExpectSameBits(ReadLidarFile(dir.path() / name), points);
    EXPECT_EQ(ParseLidarFileFormat(LidarFileFormatName(format)), format);
  }
  // Packets files need a beam model and the points in its beam order: otherwise a sweep file
  // (lidar_packet_file_test.cpp writes packets files through WriteLidarFile).
  const LidarBeamModel beams = HesaiXt32BeamModel();
  EXPECT_EQ(WriteLidarFile(dir.path(), "c", points, LidarFileFormat::kPackets), "c.sweep");
  std::vector<LidarPoint> reversed(points.rbegin(), points.rend());
  EXPECT_EQ(WriteLidarFile(dir.path(), "d", reversed, LidarFileFormat::kPackets, &beams), "d.sweep");
  ExpectSameBits(ReadLidarFile(dir.path() / "d.sweep"), reversed);
  EXPECT_EQ(ParseLidarFileFormat("packets"), LidarFileFormat::kPackets);
  EXPECT_FALSE(ParseLidarFileFormat("las").has_value());
}

TEST(LidarSweepFile, TruncatedFileNamesTheFileAndTheField) {
  testing::TempLogDir dir("sweep_truncated");
  std::filesystem::create_directories(dir.path());
  const auto file = dir.path() / "a.sweep";
  WriteLidarSweepFile(file, SpinningSweep(100, 4));
  const std::string bytes = FileBytes(file);
  EXPECT_TRUE(SweepReadError(file).empty());
  for (std::size_t size = 0; size < bytes.size(); size += 1 + size / 3) {
    WriteBytes(file, bytes.substr(0, size));
    const std::string error = SweepReadError(file);
    EXPECT_NE(error.find(file.string() + ": "), std::string::npos) << size << ": " << error;
    if (size >= kSweepHeaderBytes) {
      EXPECT_NE(error.find("field '"), std::string::npos) << size << ": " << error;
      EXPECT_NE(error.find("truncated"), std::string::npos) << size << ": " << error;
    } else {
      EXPECT_NE(error.find("truncated"), std::string::npos) << size << ": " << error;
    }
  }
  WriteBytes(file, bytes + "x");
  EXPECT_NE(SweepReadError(file).find("1 bytes after its last field"), std::string::npos);
}

TEST(LidarSweepFile, CorruptFrameNamesTheField) {
  testing::TempLogDir dir("sweep_corrupt");
  std::filesystem::create_directories(dir.path());
  const auto file = dir.path() / "a.sweep";
  WriteLidarSweepFile(file, SpinningSweep(100, 5));
  const std::string bytes = FileBytes(file);
  // Field f's frame starts after the header and the frames before it.
  std::size_t start = kSweepHeaderBytes;
  const char* names[] = {"t", "ring", "x", "y", "z", "intensity"};
  for (int f = 0; f < 6; ++f) {
    std::uint32_t size = 0;
    for (int b = 0; b < 4; ++b) {
      size |= std::uint32_t{static_cast<std::uint8_t>(bytes[16 + 4 * f + b])} << (8 * b);
    }
    for (const std::size_t at : {start + size / 2, start + size - 1, start + 5}) {
      std::string bad = bytes;
      bad[at] = static_cast<char>(bad[at] ^ 0x5a);
      WriteBytes(file, bad);
      const std::string error = SweepReadError(file);
      EXPECT_NE(error.find(file.string() + ": field '" + names[f] + "': "), std::string::npos)
          << "byte " << at << ": " << error;
    }
    start += size;
  }
}

TEST(LidarSweepFile, RefusesOtherFilesAndVersions) {
  testing::TempLogDir dir("sweep_other");
  std::filesystem::create_directories(dir.path());
  const auto file = dir.path() / "a.sweep";
  WriteLidarSweepFile(file, SpinningSweep(10, 6));
  const std::string bytes = FileBytes(file);
  std::string bad = bytes;
  bad[0] = 'X';
  WriteBytes(file, bad);
  EXPECT_NE(SweepReadError(file).find("not a StateBench sweep file"), std::string::npos);
  bad = bytes;
  bad[8] = 2;
  WriteBytes(file, bad);
  EXPECT_NE(SweepReadError(file).find("sweep file version 2"), std::string::npos);
  bad = bytes;
  bad[12] = static_cast<char>(bad[12] + 1);  // one more point than the frames hold
  WriteBytes(file, bad);
  EXPECT_NE(SweepReadError(file).find("field 't': its frame holds"), std::string::npos);
  std::filesystem::remove(file);
  EXPECT_NE(SweepReadError(file).find("cannot open"), std::string::npos);
}

}  // namespace
}  // namespace statebench::sensors
