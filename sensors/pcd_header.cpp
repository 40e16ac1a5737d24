#include "sensors/pcd_header.hpp"

#include <array>
#include <charconv>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string_view>

#include "core/error.hpp"

namespace statebench::sensors {
namespace {

namespace fs = std::filesystem;

// The header's entries in the order the PCD specification gives them.
constexpr std::array<std::string_view, 10> kKeys = {"VERSION", "FIELDS", "SIZE",      "TYPE",
                                                    "COUNT",   "WIDTH",  "HEIGHT", "VIEWPOINT",
                                                    "POINTS",  "DATA"};
constexpr std::uint64_t kMaxHeaderBytes = 1 << 20;  // a header is a few hundred bytes
constexpr std::size_t kMaxLineBytes = 1 << 16;
constexpr std::size_t kMaxFields = 1024;
constexpr int kMaxCount = 1 << 20;  // elements of one field per point
constexpr std::size_t kMaxPointStep = 1 << 24;
constexpr std::uint64_t kMaxDimension = std::numeric_limits<std::uint32_t>::max();  // PCL's type

class HeaderError {
 public:
  HeaderError(const fs::path& file, int line) : file_(file), line_(line) {}
  [[noreturn]] void operator()(const std::string& what) const {
    throw InputError(file_.string() + ":" + std::to_string(line_) + ": " + what);
  }

 private:
  const fs::path& file_;
  int line_;
};

std::vector<std::string> Words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

// A decimal integer in [lo, hi] and nothing else.
std::uint64_t Integer(const std::string& word, std::uint64_t lo, std::uint64_t hi,
                      const char* key, const HeaderError& fail) {
  std::uint64_t v = 0;
  const char* end = word.data() + word.size();
  const auto [ptr, ec] = std::from_chars(word.data(), end, v);
  if (ec != std::errc() || ptr != end || v < lo || v > hi) {
    fail(std::string(key) + ": '" + word + "' is not an integer in [" + std::to_string(lo) +
         ", " + std::to_string(hi) + "]");
  }
  return v;
}

// One value per field on SIZE, TYPE and COUNT.
void ExpectOnePerField(const std::vector<std::string>& words, const PcdHeader& header,
                       const char* key, const HeaderError& fail) {
  if (header.fields.empty()) fail(std::string(key) + " before FIELDS");
  if (words.size() - 1 != header.fields.size()) {
    fail(std::string(key) + " has " + std::to_string(words.size() - 1) + " values for " +
         std::to_string(header.fields.size()) + " fields");
  }
}

void ParseEntry(std::size_t key, const std::vector<std::string>& words, PcdHeader& header,
                const HeaderError& fail) {
  const std::size_t values = words.size() - 1;
  switch (key) {
    case 0:  // VERSION
      if (values != 1) fail("VERSION takes one value");
      break;
    case 1:  // FIELDS
      if (values == 0 || values > kMaxFields) {
        fail("FIELDS names 1 to " + std::to_string(kMaxFields) + " fields");
      }
      for (std::size_t i = 1; i < words.size(); ++i) {
        for (std::size_t j = 1; j < i; ++j) {
          if (words[j] == words[i]) fail("FIELDS names '" + words[i] + "' twice");
        }
        header.fields.push_back(PcdField{words[i]});
      }
      break;
    case 2:  // SIZE
      ExpectOnePerField(words, header, "SIZE", fail);
      for (std::size_t i = 0; i < header.fields.size(); ++i) {
        const auto size = static_cast<int>(Integer(words[i + 1], 1, 8, "SIZE", fail));
        if (size != 1 && size != 2 && size != 4 && size != 8) fail("SIZE must be 1, 2, 4 or 8");
        header.fields[i].size = size;
      }
      break;
    case 3:  // TYPE
      ExpectOnePerField(words, header, "TYPE", fail);
      for (std::size_t i = 0; i < header.fields.size(); ++i) {
        const std::string& t = words[i + 1];
        if (t != "I" && t != "U" && t != "F") fail("TYPE '" + t + "' is not I, U or F");
        header.fields[i].type = t[0];
      }
      break;
    case 4:  // COUNT
      ExpectOnePerField(words, header, "COUNT", fail);
      for (std::size_t i = 0; i < header.fields.size(); ++i) {
        header.fields[i].count =
            static_cast<int>(Integer(words[i + 1], 1, kMaxCount, "COUNT", fail));
      }
      break;
    case 5:  // WIDTH
      if (values != 1) fail("WIDTH takes one value");
      header.width = Integer(words[1], 0, kMaxDimension, "WIDTH", fail);
      break;
    case 6:  // HEIGHT
      if (values != 1) fail("HEIGHT takes one value");
      header.height = Integer(words[1], 0, kMaxDimension, "HEIGHT", fail);
      break;
    case 7: {  // VIEWPOINT: tx ty tz qw qx qy qz
      if (values != 7) fail("VIEWPOINT takes 7 values");
      for (std::size_t i = 1; i < words.size(); ++i) {
        double v = 0.0;
        const char* end = words[i].data() + words[i].size();
        const auto [ptr, ec] = std::from_chars(words[i].data(), end, v);
        if (ec != std::errc() || ptr != end) fail("VIEWPOINT: '" + words[i] + "' is not a number");
      }
      break;
    }
    case 8:  // POINTS
      if (values != 1) fail("POINTS takes one value");
      header.points = Integer(words[1], 0, kMaxDimension, "POINTS", fail);
      break;
    case 9:  // DATA
      if (values != 1) fail("DATA takes one value");
      if (words[1] == "ascii") {
        header.data = PcdData::kAscii;
      } else if (words[1] == "binary") {
        header.data = PcdData::kBinary;
      } else if (words[1] == "binary_compressed") {
        header.data = PcdData::kBinaryCompressed;
      } else {
        fail("DATA '" + words[1] + "' is not ascii, binary or binary_compressed");
      }
      break;
  }
}

// Every required entry present, the sizes agreeing, offsets and point step filled in.
void Complete(const std::vector<bool>& seen, PcdHeader& header, const HeaderError& fail) {
  for (std::size_t k : {1, 2, 3, 5, 6, 8}) {
    if (!seen[k]) fail("DATA before " + std::string(kKeys[k]));
  }
  if (header.width * header.height != header.points) {
    fail("WIDTH x HEIGHT (" + std::to_string(header.width) + " x " +
         std::to_string(header.height) + ") is not POINTS (" + std::to_string(header.points) +
         ")");
  }
  for (PcdField& f : header.fields) {
    f.offset = header.point_step;
    header.point_step += static_cast<std::size_t>(f.size) * static_cast<std::size_t>(f.count);
    if (header.point_step > kMaxPointStep) fail("a point of over 16 MiB");
  }
}

}  // namespace

const PcdField* PcdHeader::Find(const std::string& name) const {
  for (const PcdField& f : fields) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

PcdHeader ReadPcdHeader(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": cannot open");
  PcdHeader header;
  std::vector<bool> seen(kKeys.size(), false);
  std::optional<std::size_t> last_key;
  std::uint64_t offset = 0;  // bytes read so far
  std::vector<char> buffer(kMaxLineBytes);
  for (int line_number = 1; offset < kMaxHeaderBytes; ++line_number) {
    const HeaderError fail(file, line_number);
    in.getline(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    const auto read = static_cast<std::uint64_t>(in.gcount());  // with the '\n'
    if (in.fail()) {
      if (read + 1 >= buffer.size()) fail("a line of over 64 KiB (not a PCD file?)");
      break;  // end of file
    }
    offset += read;
    std::string line(buffer.data(), in.eof() ? read : read - 1);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::vector<std::string> words = Words(line);
    if (words.empty() || words[0][0] == '#') continue;
    std::size_t key = kKeys.size();
    for (std::size_t k = 0; k < kKeys.size(); ++k) {
      if (words[0] == kKeys[k]) key = k;
    }
    if (key == kKeys.size()) fail("'" + words[0] + "' is not a PCD header entry");
    if (last_key && key <= *last_key) {
      fail(std::string(kKeys[key]) + " after " + std::string(kKeys[*last_key]) +
           " (the PCD header's entries come once each, in the order VERSION FIELDS SIZE TYPE "
           "COUNT WIDTH HEIGHT VIEWPOINT POINTS DATA)");
    }
    last_key = key;
    seen[key] = true;
    ParseEntry(key, words, header, fail);
    if (key == 9) {
      Complete(seen, header, fail);
      header.data_offset = offset;
      return header;
    }
  }
  throw InputError(file.string() + ": no DATA line in its first " +
                   std::to_string(kMaxHeaderBytes / 1024) + " KiB (not a PCD file?)");
}

}  // namespace statebench::sensors
