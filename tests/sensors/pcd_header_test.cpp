#include "sensors/pcd_header.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "core/error.hpp"
#include "log_test_fixtures.hpp"
#include "sensors/lidar_pcd_io.hpp"

namespace statebench::sensors {
namespace {

const char* const kGoodHeader =
    "# .PCD v0.7 - Point Cloud Data file format\n"
    "VERSION 0.7\n"
    "FIELDS x y z intensity t ring\n"
    "SIZE 4 4 4 4 4 2\n"
    "TYPE F F F F F U\n"
    "COUNT 1 1 1 1 1 1\n"
    "WIDTH 2\n"
    "HEIGHT 1\n"
    "VIEWPOINT 0 0 0 1 0 0 0\n"
    "POINTS 2\n";

class PcdFile {
 public:
  explicit PcdFile(const std::string& name) : dir_("pcd_header_" + name) {
    std::filesystem::create_directories(dir_.path());
  }
  std::filesystem::path Write(const std::string& text) const {
    const std::filesystem::path file = dir_.path() / "cloud.pcd";
    std::ofstream(file, std::ios::binary) << text;
    return file;
  }

 private:
  testing::TempLogDir dir_;
};

// The message of the InputError that reading `text` as a PCD header throws ("" if none).
std::string HeaderError(const std::string& text) {
  const PcdFile pcd("error");
  try {
    ReadPcdHeader(pcd.Write(text));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(PcdHeader, ReadsWhatPclWritesWithOffsetsAndDataStart) {
  const PcdFile pcd("pcl");
  const std::filesystem::path file = pcd.Write("");
  WriteLidarPcd(file, {{1.f, 2.f, 3.f, 4.f, 0.05f, 7}, {5.f, 6.f, 7.f, 8.f, 0.06f, 9}});
  const PcdHeader header = ReadPcdHeader(file);
  ASSERT_EQ(header.fields.size(), 6u);
  EXPECT_EQ(header.points, 2u);
  EXPECT_EQ(header.width * header.height, 2u);
  EXPECT_EQ(header.point_step, 22u);
  EXPECT_EQ(header.data, PcdData::kBinary);
  ASSERT_NE(header.Find("ring"), nullptr);
  EXPECT_EQ(header.Find("ring")->offset, 20u);
  EXPECT_EQ(header.Find("ring")->type, 'U');
  EXPECT_EQ(header.Find("t")->offset, 16u);
  EXPECT_EQ(header.Find("nope"), nullptr);
  // The data starts at data_offset (PCL's writer pads the file after it to a page).
  EXPECT_GE(std::filesystem::file_size(file), header.data_offset + 2 * 22);
  std::ifstream in(file, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(header.data_offset + 22));
  float x = 0.f;
  in.read(reinterpret_cast<char*>(&x), sizeof(x));
  EXPECT_EQ(x, 5.f);
}

TEST(PcdHeader, MalformedHeadersAreRefusedWithTheirLine) {
  const std::string good(kGoodHeader);
  EXPECT_EQ(HeaderError(good + "DATA binary\n"), "");
  const auto expect = [](const std::string& text, const std::string& what) {
    const std::string error = HeaderError(text);
    EXPECT_NE(error.find(what), std::string::npos) << "expected '" << what << "' in '" << error
                                                   << "' for\n" << text;
  };
  // The legacy key PCL takes for FIELDS (a fuzzed header with it crashed PCL's parser).
  expect("COLUMNS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n",
         "cloud.pcd:1: 'COLUMNS' is not a PCD header entry");
  expect("FIELDS x y z\nFIELDS x y z\n", "cloud.pcd:2: FIELDS after FIELDS");
  expect("SIZE 4 4 4\nFIELDS x y z\n", "cloud.pcd:1: SIZE before FIELDS");
  expect("FIELDS x y z\nTYPE F F F\nSIZE 4 4 4\n", "cloud.pcd:3: SIZE after TYPE");
  expect("FIELDS x y z\nSIZE 4 4\n", "cloud.pcd:2: SIZE has 2 values for 3 fields");
  expect("FIELDS x y x\n", "cloud.pcd:1: FIELDS names 'x' twice");
  expect("FIELDS x\nSIZE 3\n", "cloud.pcd:2: SIZE must be 1, 2, 4 or 8");
  expect("FIELDS x\nSIZE 4\nTYPE D\n", "cloud.pcd:3: TYPE 'D' is not I, U or F");
  expect("FIELDS x\nSIZE 4\nTYPE F\nCOUNT 0\n", "COUNT: '0' is not an integer in [1,");
  expect("FIELDS x\nSIZE 4\nTYPE F\nWIDTH 2x\n", "cloud.pcd:4: WIDTH: '2x' is not an integer");
  expect("FIELDS x\nSIZE 4\nTYPE F\nWIDTH 99999999999\n", "WIDTH: '99999999999' is not");
  expect("FIELDS x\nSIZE 4\nTYPE F\nWIDTH 2\nHEIGHT 2\nPOINTS 3\nDATA binary\n",
         "cloud.pcd:7: WIDTH x HEIGHT (2 x 2) is not POINTS (3)");
  expect("FIELDS x\nSIZE 4\nTYPE F\nWIDTH 1\nPOINTS 1\nDATA binary\n",
         "cloud.pcd:6: DATA before HEIGHT");
  expect("FIELDS x\nSIZE 4\nTYPE F\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA binary_lzf\n",
         "is not ascii, binary or binary_compressed");
  expect(good + "VIEWPOINT 0 0 0 1 0 0 0\n", "cloud.pcd:11: VIEWPOINT after POINTS");
  expect(good, "cloud.pcd: no DATA line in its first 1024 KiB");
  expect(std::string(70000, 'A'), "cloud.pcd:1: a line of over 64 KiB");
  expect("", "no DATA line");
}

TEST(PcdHeader, AsciiPcdIsReadThroughPclAndCrlfIsTolerated) {
  const PcdFile pcd("ascii");
  const std::filesystem::path file = pcd.Write(
      "VERSION 0.7\r\nFIELDS x y z ring\r\nSIZE 4 4 4 2\r\nTYPE F F F U\r\nCOUNT 1 1 1 1\r\n"
      "WIDTH 2\r\nHEIGHT 1\r\nPOINTS 2\r\nDATA ascii\r\n1.5 -2 3 7\r\n4 5 6 9\r\n");
  const std::vector<LidarPoint> points = ReadLidarPcd(file);
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[0].x, 1.5f);
  EXPECT_EQ(points[0].y, -2.f);
  EXPECT_EQ(points[1].z, 6.f);
  EXPECT_EQ(points[1].ring, 9);
  EXPECT_EQ(points[1].intensity, 0.f);  // not in the file
}

TEST(PcdHeader, AsciiDataTooShortForItsPointsIsRefusedBeforeAllocating) {
  const PcdFile pcd("ascii_short");
  // Four billion points announced in a file of a few bytes: refused from the file's size.
  const std::filesystem::path file = pcd.Write(
      "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 4000000000\nHEIGHT 1\nPOINTS 4000000000\n"
      "DATA ascii\n1 2 3\n");
  try {
    ReadLidarPcd(file);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot hold the header's 4000000000 points"),
              std::string::npos)
        << e.what();
  }
  // Exactly long enough (the last value without its newline) is read.
  EXPECT_EQ(ReadLidarPcd(pcd.Write("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\n"
                                   "POINTS 1\nDATA ascii\n1 2 3"))
                .size(),
            1u);
}

TEST(PcdHeader, FieldOfTheWrongTypeAndMissingXyzAreNamed) {
  const PcdFile pcd("types");
  const auto error = [&pcd](const std::string& text) {
    try {
      ReadLidarPcd(pcd.Write(text));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error("FIELDS x y z\nSIZE 4 4 8\nTYPE F F F\nWIDTH 0\nHEIGHT 1\nPOINTS 0\nDATA "
                  "binary\n")
                .find("field 'z' is F 8 x 1, expected F 4 x 1"),
            std::string::npos);
  EXPECT_NE(error("FIELDS x y\nSIZE 4 4\nTYPE F F\nWIDTH 0\nHEIGHT 1\nPOINTS 0\nDATA binary\n")
                .find("needs the fields x, y and z"),
            std::string::npos);
  EXPECT_NE(error("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA "
                  "binary_compressed\n")
                .find("truncated: no compressed data"),
            std::string::npos);
}

}  // namespace
}  // namespace statebench::sensors
