#include "core/csv_line_reader.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/removed_at_exit.hpp"

namespace statebench {
namespace {

std::filesystem::path WriteLineReaderFile(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("statebench_csv_line_reader_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  testing::RemovedAtExit(dir);
  const auto path = dir / name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// The lines std::getline gives for the same text, the reference.
std::vector<std::string> GetlineLines(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::vector<std::string> ReaderLines(const std::filesystem::path& path, std::size_t block) {
  CsvLineReader reader(path, block);
  EXPECT_TRUE(reader.is_open());
  std::vector<std::string> lines;
  while (const auto line = reader.Next()) {
    lines.emplace_back(*line);
    EXPECT_EQ(reader.line_number(), lines.size());
  }
  EXPECT_FALSE(reader.bad());
  return lines;
}

TEST(CsvLineReader, GivesTheLinesGetlineGivesWhateverTheBlockSize) {
  std::string long_line(100, 'x');
  const std::vector<std::string> texts = {
      "a,b\n1,2\n3,4\n",
      "a,b\r\n1,2\r\n\r\n3,4",  // CR kept, blank line, no final newline
      "",
      "\n\n",
      "header\n" + long_line + "\n" + long_line + "," + long_line + "\nlast",
  };
  for (std::size_t t = 0; t < texts.size(); ++t) {
    const auto path = WriteLineReaderFile("t" + std::to_string(t) + ".csv", texts[t]);
    for (const std::size_t block : {16u, 17u, 64u, 1u << 20}) {
      EXPECT_EQ(ReaderLines(path, block), GetlineLines(texts[t])) << "text " << t << " block "
                                                                 << block;
    }
  }
}

TEST(CsvLineReader, MissingFileIsNotOpen) {
  CsvLineReader reader(std::filesystem::temp_directory_path() / "statebench_no_such_file.csv");
  EXPECT_FALSE(reader.is_open());
  EXPECT_FALSE(reader.Next());
}

}  // namespace
}  // namespace statebench
