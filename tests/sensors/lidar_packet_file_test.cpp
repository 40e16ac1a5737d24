// Lidar packets files (sensors/lidar_packet_file.hpp): a simulated sweep, motion distortion and
// range noise included, reads back bit for bit (the reader rebuilds x y z t with the simulator's
// own BeamReturn), points a fault moved or made NaN too; sweeps that are not a lidar's returns in
// beam order are refused; damaged files throw an error naming the file and the field.
#include "sensors/lidar_packet_file.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "core/error.hpp"
#include "core/so3.hpp"
#include "lidar_test_fixtures.hpp"
#include "sensors/file_bytes.hpp"
#include "sensors/lidar_file.hpp"
#include "sensors/lidar_simulator.hpp"

namespace statebench::sensors {
namespace {

using testing::ExpectSameBits;

// A noisy XT32 driving at 10 m/s and turning at 0.5 rad/s through a street with walls: every
// column fires from its own pose.
struct SimulatedSweep {
  LidarModelParams params;
  std::vector<LidarPoint> points;
};

SimulatedSweep SimulateMovingXt32() {
  const std::vector<WorldBox> walls = {{Vec3(0.0, 12.0, 3.0), 0.0, Vec3(60.0, 1.0, 6.0)},
                                       {Vec3(20.0, -9.0, 2.0), 0.3, Vec3(8.0, 4.0, 4.0)}};
  const auto world = testing::FlatWorld(0.0, walls);
  LidarModelValues v;
  v.model = "hesai_xt32";
  v.sensor_id = "lidar_roof";
  SimulatedSweep sweep{MakeLidarModelParams(v, "test"), {}};
  const LidarSimulator sim(*world, sweep.params, 5);
  const auto pose = [](TimeNs t_ns) {
    const double t = ToSeconds(t_ns);
    return SE3(so3::Exp(Vec3(0.0, 0.0, 0.5 * t)), Vec3(10.0 * t - 5.0, 0.3 * t, 1.8));
  };
  sweep.points = *sim.SimulateScan(pose, 0, 0).points;
  return sweep;
}

class LidarPacketFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("statebench_packets_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  std::filesystem::path dir_;
};

TEST_F(LidarPacketFile, SimulatedSweepWithMotionReadsBackBitForBit) {
  const SimulatedSweep sweep = SimulateMovingXt32();
  ASSERT_GT(sweep.points.size(), 20000u);
  ASSERT_EQ(WriteLidarFile(dir_, "0", sweep.points, LidarFileFormat::kPackets, &sweep.params.beams),
            "0.packets");
  const auto file = dir_ / "0.packets";
  ExpectSameBits(ReadLidarFile(file), sweep.points);
  ExpectSameBits(ReadLidarPacketFile(file), sweep.points);
  // A range word and an intensity byte per return, a mask bit per beam, a few raw points: under
  // 5.5 bytes a point where a binary PCD takes 22.
  const double bytes_per_point =
      static_cast<double>(std::filesystem::file_size(file)) / sweep.points.size();
  EXPECT_LT(bytes_per_point, 5.5);
  RecordProperty("bytes_per_point", std::to_string(bytes_per_point));
}

TEST_F(LidarPacketFile, FaultedPointsAndFractionalIntensitiesReadBackBitForBit) {
  SimulatedSweep sweep = SimulateMovingXt32();
  std::vector<LidarPoint>& points = sweep.points;
  points[3].x = std::numeric_limits<float>::quiet_NaN();
  points[10].y = -std::numeric_limits<float>::infinity();
  points[11].z = 1e30f;
  points[12] = LidarPoint{0.f, 0.f, 0.f, points[12].intensity, points[12].t, points[12].ring};
  points[20].x = std::nextafter(points[20].x, 1e9f);  // one float step off its beam
  points[30].intensity = 0.25f;                       // not a whole number: float32 intensities
  points[31].intensity = -0.f;
  const auto bytes = EncodeLidarPackets(points, sweep.params.beams);
  ASSERT_TRUE(bytes.has_value());
  ExpectSameBits(DecodeLidarPackets(*bytes, "faulted.packets"), points);
}

TEST_F(LidarPacketFile, EmptySweepReadsBackEmpty) {
  const auto bytes = EncodeLidarPackets({}, HesaiXt32BeamModel());
  ASSERT_TRUE(bytes.has_value());
  EXPECT_TRUE(DecodeLidarPackets(*bytes, "empty.packets").empty());
}

TEST_F(LidarPacketFile, PointsNotInBeamOrderAreRefused) {
  const SimulatedSweep sweep = SimulateMovingXt32();
  const LidarBeamModel& beams = sweep.params.beams;
  auto swapped = sweep.points;  // two returns of one column, rings descending
  ASSERT_EQ(swapped[0].t, swapped[1].t);
  std::swap(swapped[0], swapped[1]);
  EXPECT_FALSE(EncodeLidarPackets(swapped, beams).has_value());
  auto twice = sweep.points;  // one beam's return twice
  twice.insert(twice.begin() + 1, twice[0]);
  EXPECT_FALSE(EncodeLidarPackets(twice, beams).has_value());
  auto retimed = sweep.points;  // a t between two columns
  retimed[5].t = std::nextafter(retimed[5].t, 1.f);
  EXPECT_FALSE(EncodeLidarPackets(retimed, beams).has_value());
  auto other_ring = sweep.points;
  other_ring.back().ring = 32;
  EXPECT_FALSE(EncodeLidarPackets(other_ring, beams).has_value());
  EXPECT_FALSE(EncodeLidarPackets(sweep.points, VelodyneVlp16BeamModel()).has_value());
  EXPECT_FALSE(WriteLidarPacketFile(dir_ / "no.packets", swapped, beams));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "no.packets"));
}

// The message of the InputError that decoding `bytes` throws ("" when it throws none).
std::string DecodeError(const std::vector<std::uint8_t>& bytes) {
  try {
    DecodeLidarPackets(bytes, "LOG/lidar/roof/7.packets");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST_F(LidarPacketFile, DamagedFilesNameTheFileAndTheField) {
  const SimulatedSweep sweep = SimulateMovingXt32();
  const std::vector<std::uint8_t> good = *EncodeLidarPackets(sweep.points, sweep.params.beams);
  const auto with = [&](std::size_t at, std::vector<std::uint8_t> value) {
    std::vector<std::uint8_t> b = good;
    std::copy(value.begin(), value.end(), b.begin() + static_cast<std::ptrdiff_t>(at));
    return b;
  };
  const std::size_t masks = 52 + 8 * 32;
  const struct {
    std::vector<std::uint8_t> bytes;
    std::string message;
  } cases[] = {
      {{good.begin(), good.begin() + 30}, "truncated: 30 bytes, the header alone takes 52"},
      {{good.begin(), good.end() - 1}, "truncated: " + std::to_string(good.size() - 1) + " bytes"},
      {with(good.size(), {}), ""},
      {with(0, {'P', 'C', 'D'}), "not a StateBench lidar packets file"},
      {with(8, {2, 0, 0, 0}), "field 'version': 2, this reader knows 1"},
      {with(28, {7}), "field 'intensity encoding': 7"},
      {with(29, {3}), "field 'clockwise': 3"},
      {with(30, {0, 0}), "field 'channels': 0"},
      {with(32, {0, 0, 0, 0x10}), "field 'columns'"},
      {with(36, {0, 0, 0, 0, 0, 0, 0xF8, 0x7F}), "field 'rotation rate'"},
      {with(52, {0, 0, 0, 0, 0, 0, 0xF0, 0x7F}), "field 'elevations': ring 0 is not finite"},
      {with(20, {static_cast<std::uint8_t>(good[20] ^ 0x10)}), "field 'direction checksum'"},
      {with(12, {0, 0, 0, 0}), "too long"},
      {with(masks, {static_cast<std::uint8_t>(good[masks] ^ 0x01)}), "field 'hit masks'"},
  };
  for (const auto& c : cases) {
    const std::string error = DecodeError(c.bytes);
    if (c.message.empty()) {
      EXPECT_EQ(error, "");
      continue;
    }
    EXPECT_NE(error.find("LOG/lidar/roof/7.packets: "), std::string::npos) << error;
    EXPECT_NE(error.find(c.message), std::string::npos) << error << "\n expected: " << c.message;
  }
  // Four more bytes than announced.
  std::vector<std::uint8_t> longer = good;
  longer.insert(longer.end(), {0, 0, 0, 0});
  EXPECT_NE(DecodeError(longer).find("too long"), std::string::npos);
}

TEST_F(LidarPacketFile, RawPointIndicesMustIncreaseBelowTheCount) {
  SimulatedSweep sweep = SimulateMovingXt32();
  sweep.points[4].x = std::numeric_limits<float>::quiet_NaN();
  sweep.points[9].x = std::numeric_limits<float>::quiet_NaN();
  std::vector<std::uint8_t> bytes = *EncodeLidarPackets(sweep.points, sweep.params.beams);
  const std::uint32_t raw = GetLittleEndian<std::uint32_t>(&bytes[16]);
  ASSERT_GE(raw, 2u);
  const std::size_t last = bytes.size() - 16;  // the last raw point's index
  PutLittleEndian(&bytes[last], std::uint32_t{0});
  EXPECT_NE(DecodeError(bytes).find("field 'raw points': raw point " + std::to_string(raw - 1)),
            std::string::npos)
      << DecodeError(bytes);
  PutLittleEndian(&bytes[last], static_cast<std::uint32_t>(sweep.points.size()));
  EXPECT_NE(DecodeError(bytes).find("field 'raw points'"), std::string::npos);
}

TEST_F(LidarPacketFile, RingBitsBeyondTheChannelsAreRefused) {
  std::vector<LidarPoint> points;
  const LidarBeamModel beams = VelodyneVlp16BeamModel();  // 16 channels: 2 mask bytes, all used
  LidarBeamModel odd = beams;
  odd.elevations_rad.pop_back();  // 15 channels: the mask's top bit is spare
  const auto d = odd.Direction(0, 2);
  points.push_back(BeamReturn(d, 10.0, 5.f, odd.ColumnTimeS(0), 2));
  std::vector<std::uint8_t> bytes = *EncodeLidarPackets(points, odd);
  const std::size_t mask = 52 + 8 * 15;
  bytes[mask + 1] |= 0x80;  // ring 15 of column 0
  bytes[mask] &= 0xFB;      // ring 2 gone: still one return
  EXPECT_NE(DecodeError(bytes).find("field 'hit masks': column 0 has a return of a ring beyond"),
            std::string::npos)
      << DecodeError(bytes);
}

TEST_F(LidarPacketFile, AnyDamageThrowsOrDecodesNeverCrashes) {
  LidarBeamModel beams = VelodyneVlp16BeamModel();
  beams.columns = 40;  // a small sweep, so every byte can be hit
  std::vector<LidarPoint> points;
  for (int c = 0; c < beams.columns; c += 3) {
    for (int r = 0; r < beams.channels(); r += 2) {
      points.push_back(BeamReturn(beams.Direction(c, r), 3.0 + 0.1 * r + 0.01 * c,
                                  static_cast<float>(r), beams.ColumnTimeS(c),
                                  static_cast<std::uint16_t>(r)));
    }
  }
  const std::vector<std::uint8_t> good = *EncodeLidarPackets(points, beams);
  ExpectSameBits(DecodeLidarPackets(good, "small.packets"), points);
  std::mt19937 rng(3);
  for (std::size_t at = 0; at < good.size(); ++at) {
    for (int trial = 0; trial < 3; ++trial) {
      std::vector<std::uint8_t> bad = good;
      bad[at] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
      try {
        DecodeLidarPackets(bad, "bad.packets");
      } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("bad.packets: ", 0), 0u) << e.what();
      }
    }
    std::vector<std::uint8_t> cut(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(at));
    EXPECT_THROW(DecodeLidarPackets(cut, "cut.packets"), InputError) << at << " bytes";
  }
}

TEST_F(LidarPacketFile, MissingFileNamesIt) {
  try {
    ReadLidarPacketFile(dir_ / "missing.packets");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.packets: cannot open"), std::string::npos);
  }
}

}  // namespace
}  // namespace statebench::sensors
