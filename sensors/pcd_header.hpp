// The header of a PCD file (PCL's point-cloud format, version 0.7), read and checked without PCL.
// The PCD specification orders the header's entries: VERSION, FIELDS, SIZE, TYPE, COUNT, WIDTH,
// HEIGHT, VIEWPOINT, POINTS, DATA; '#' starts a comment line. This reader takes them in that
// order only, each once (VERSION, COUNT and VIEWPOINT optional), with FIELDS, SIZE, TYPE and COUNT
// naming the same fields, SIZE 1/2/4/8 matching TYPE I/U/F, and WIDTH x HEIGHT = POINTS. Anything
// else (the legacy COLUMNS key, a number with trailing characters, a second FIELDS line) is
// refused with the file and line: PCL's own header parser crashes on some malformed headers
// (found by fuzz_log_reader), so nothing reaches it that this reader has not accepted.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace statebench::sensors {

struct PcdField {
  std::string name;
  int size = 0;      // bytes of one element: 1, 2, 4 or 8
  char type = 'F';   // I signed, U unsigned, F floating point
  int count = 1;     // elements per point
  std::size_t offset = 0;  // bytes from the start of a point (binary layout)
};

enum class PcdData { kAscii, kBinary, kBinaryCompressed };

struct PcdHeader {
  std::vector<PcdField> fields;
  std::uint64_t width = 0;
  std::uint64_t height = 0;
  std::uint64_t points = 0;
  std::size_t point_step = 0;  // bytes of one point in the binary layout
  PcdData data = PcdData::kBinary;
  std::uint64_t data_offset = 0;  // bytes from the start of the file to the data

  // The field of that name, or nullptr.
  const PcdField* Find(const std::string& name) const;
};

// Throws InputError "file:line: what" when the header is not of the form above, or "file: what"
// when the file cannot be read or ends before its DATA line.
PcdHeader ReadPcdHeader(const std::filesystem::path& file);

}  // namespace statebench::sensors
