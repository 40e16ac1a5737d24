#include "core/truth_io.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "tests/removed_at_exit.hpp"

namespace statebench {
namespace {

std::filesystem::path FreshDir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("statebench_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return testing::RemovedAtExit(dir);
}

TruthSample MakeSample(int i) {
  TruthSample s;
  s.t_ns = 1000000LL * i;
  s.body.T_world_frame = SE3(so3::FromRollPitchYaw(0.01 * i, -0.02, 0.1 * i / 3.0),
                             Vec3(0.1 * i, 1.0 / 3.0, -2.5e-7 * i));
  s.body.v_world = Vec3(1.0 / 7.0, 2, 3);
  s.body.a_world = Vec3(0.1, -0.2, 0.3 * i);
  s.body.omega_frame = Vec3(0.01, 0.02, 0.03);
  s.body.alpha_frame = Vec3(-1, 0, 1);
  s.steering_front_rad = 0.05;
  s.wheel_omega_radps = {1, 2, 3, 4.5};
  s.sideslip_rad = 0.001;
  s.distance_m = i * 0.01;
  return s;
}

TEST(TruthIo, RoundTripIsBitExact) {
  const auto dir = FreshDir("truth_rt");
  {
    TruthWriter w(dir, SE3(Quat::Identity(), Vec3(0.2, 0, 0.5)));
    for (int i = 0; i < 50; ++i) w.Write(MakeSample(i));
    w.Close();
  }
  const TruthReadResult r = ReadTruthCsv(dir / "truth.csv");
  ASSERT_FALSE(r.error) << *r.error;
  ASSERT_EQ(r.samples.size(), 50u);
  for (int i = 0; i < 50; ++i) {
    const TruthSample e = MakeSample(i);
    const TruthSample& g = r.samples[i];
    EXPECT_EQ(g.t_ns, e.t_ns);
    EXPECT_EQ(g.body.T_world_frame.translation(), e.body.T_world_frame.translation());
    EXPECT_EQ(g.body.T_world_frame.rotation().coeffs(), e.body.T_world_frame.rotation().coeffs());
    EXPECT_EQ(g.body.a_world, e.body.a_world);
    EXPECT_EQ(g.wheel_omega_radps, e.wheel_omega_radps);
    EXPECT_EQ(g.distance_m, e.distance_m);
  }
  std::ifstream tum(dir / "truth_body.tum");
  std::string header, first;
  std::getline(tum, header);
  std::getline(tum, first);
  EXPECT_EQ(first.substr(0, 12), "0.000000000 ");
}

// Copies truth.csv with cell `column` of file line `bad_line` replaced by `value`.
std::string WriteBrokenCopy(const std::filesystem::path& dir, int bad_line, int column,
                            const std::string& old_text, const std::string& value) {
  std::ifstream in(dir / "truth.csv");
  std::stringstream out;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (n == bad_line) {
      std::size_t begin = 0;
      for (int c = 0; c < column; ++c) begin = line.find(',', begin) + 1;
      const std::size_t end = line.find(',', begin);
      EXPECT_TRUE(old_text.empty() || line.substr(begin, end - begin) == old_text);
      line.replace(begin, end - begin, value);
    }
    out << line << '\n';
  }
  const auto path = dir / ("broken_" + std::to_string(bad_line) + ".csv");
  std::ofstream(path) << out.str();
  return path.string();
}

TEST(TruthIo, BadRowsAreReportedAndEarlierRowsKept) {
  const auto dir = FreshDir("truth_bad");
  {
    TruthWriter w(dir, SE3());
    for (int i = 0; i < 10; ++i) w.Write(MakeSample(i));
  }
  // NaN on data line 5 (file line 6).
  TruthReadResult r = ReadTruthCsv(WriteBrokenCopy(dir, 6, 1, "", "nan"));
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error->find(":6: column 'p_world_body_x'"), std::string::npos) << *r.error;
  EXPECT_EQ(r.samples.size(), 4u);

  // Timestamp going backwards on file line 8.
  r = ReadTruthCsv(WriteBrokenCopy(dir, 8, 0, "", "0"));
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error->find(":8: column 't_ns': timestamp does not increase"), std::string::npos)
      << *r.error;
  EXPECT_EQ(r.samples.size(), 6u);

  // A misspelt column in the header.
  r = ReadTruthCsv(WriteBrokenCopy(dir, 1, 12, "a_world_y", "a_world_q"));
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error->find("missing column 'a_world_y'"), std::string::npos) << *r.error;
  EXPECT_TRUE(r.samples.empty());

  // A row cut short.
  std::ofstream(dir / "short.csv") << [&] {
    std::ifstream in(dir / "truth.csv");
    std::string header, row;
    std::getline(in, header);
    std::getline(in, row);
    return header + "\n" + row + "\n" + row.substr(0, row.size() / 2) + "\n";
  }();
  r = ReadTruthCsv(dir / "short.csv");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error->find("short.csv:3:"), std::string::npos) << *r.error;
  EXPECT_EQ(r.samples.size(), 1u);
}

// Rows as TruthWriter writes them are read in one pass over the line; rows with spaces around
// the cells and '\r\n' line ends cell by cell. Both give the same samples, bit for bit, and
// the same error for a quaternion off unit norm.
TEST(TruthIo, PlainAndSpacedRowsReadTheSame) {
  const auto dir = FreshDir("truth_spaced");
  {
    TruthWriter w(dir, SE3());
    for (int i = 0; i < 10; ++i) w.Write(MakeSample(i));
  }
  {
    std::ifstream in(dir / "truth.csv");
    std::ofstream out(dir / "spaced.csv");
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
      if (n > 1 && n % 2 == 0) {
        std::string spaced;
        for (const char c : line) spaced += c == ',' ? std::string(" , ") : std::string(1, c);
        line = spaced;
      }
      out << line << "\r\n";
    }
  }
  const TruthReadResult plain = ReadTruthCsv(dir / "truth.csv");
  const TruthReadResult spaced = ReadTruthCsv(dir / "spaced.csv");
  ASSERT_FALSE(plain.error) << *plain.error;
  ASSERT_FALSE(spaced.error) << *spaced.error;
  ASSERT_EQ(plain.samples.size(), 10u);
  ASSERT_EQ(spaced.samples.size(), 10u);
  for (std::size_t i = 0; i < 10; ++i) {
    const TruthSample& a = plain.samples[i];
    const TruthSample& b = spaced.samples[i];
    EXPECT_EQ(a.t_ns, b.t_ns);
    EXPECT_EQ(a.body.T_world_frame.translation(), b.body.T_world_frame.translation());
    EXPECT_EQ(a.body.T_world_frame.rotation().coeffs(), b.body.T_world_frame.rotation().coeffs());
    EXPECT_EQ(a.body.v_world, b.body.v_world);
    EXPECT_EQ(a.body.a_world, b.body.a_world);
    EXPECT_EQ(a.body.omega_frame, b.body.omega_frame);
    EXPECT_EQ(a.body.alpha_frame, b.body.alpha_frame);
    EXPECT_EQ(a.steering_front_rad, b.steering_front_rad);
    EXPECT_EQ(a.steering_rear_rad, b.steering_rear_rad);
    EXPECT_EQ(a.wheel_omega_radps, b.wheel_omega_radps);
    EXPECT_EQ(a.sideslip_rad, b.sideslip_rad);
    EXPECT_EQ(a.distance_m, b.distance_m);
  }
  const TruthReadResult off_norm = ReadTruthCsv(WriteBrokenCopy(dir, 5, 4, "", "1.5"));
  ASSERT_TRUE(off_norm.error);
  EXPECT_NE(off_norm.error->find(":5: column 'q_world_body_w': quaternion is not of unit norm"),
            std::string::npos)
      << *off_norm.error;
  EXPECT_EQ(off_norm.samples.size(), 3u);
}

// The streaming reader gives the samples one by one, the same as the whole-file read, and stops
// at a bad row with the samples before it given.
TEST(TruthIo, StreamingReaderGivesTheSamplesUpToTheFirstBadRow) {
  const auto dir = FreshDir("truth_stream");
  {
    TruthWriter w(dir, SE3());
    for (int i = 0; i < 10; ++i) w.Write(MakeSample(i));
  }
  TruthCsvReader reader(WriteBrokenCopy(dir, 7, 3, "", "x"));
  std::vector<TimeNs> stamps;
  while (const auto s = reader.Next()) stamps.push_back(s->t_ns);
  ASSERT_TRUE(reader.error());
  EXPECT_NE(reader.error()->find(":7: column 'p_world_body_z': expected a number, got 'x'"),
            std::string::npos)
      << *reader.error();
  ASSERT_EQ(stamps.size(), 5u);
  EXPECT_EQ(stamps.back(), MakeSample(4).t_ns);
  EXPECT_FALSE(reader.Next());

  TruthCsvReader missing(dir / "no_such_truth.csv");
  EXPECT_FALSE(missing.Next());
  ASSERT_TRUE(missing.error());
  EXPECT_NE(missing.error()->find("cannot open"), std::string::npos);
}

// The stamp is "[-]sec.nnnnnnnnn", as printf's "%lld.%09lld" wrote it (a minus also before a
// zero second count).
TEST(TruthIo, TumStampsAreSecondsWithNineDigits) {
  for (const TimeNs t : {TimeNs{0}, TimeNs{1}, TimeNs{10160000000}, TimeNs{999999999},
                         TimeNs{-1}, TimeNs{-500000000}, TimeNs{-1500000000},
                         TimeNs{123456789012345678}}) {
    std::string line;
    AppendTumLine(line, t, SE3());
    const TimeNs sec = t / kNsPerSecond;
    const TimeNs frac = t % kNsPerSecond;
    char expected[48];
    std::snprintf(expected, sizeof(expected), "%s%lld.%09lld ", (t < 0 && sec == 0) ? "-" : "",
                  static_cast<long long>(sec), static_cast<long long>(frac < 0 ? -frac : frac));
    EXPECT_EQ(line.substr(0, line.find(' ') + 1), expected) << t;
  }
}

}  // namespace
}  // namespace statebench
