#include "sensors/file_bytes.hpp"

#include <fstream>
#include <string>

#include "core/error.hpp"

namespace statebench::sensors {

void ReadFileBytes(const std::filesystem::path& file, std::vector<std::uint8_t>& bytes) {
  std::ifstream in(file, std::ios::binary | std::ios::ate);
  if (!in) throw InputError(file.string() + ": cannot open");
  const std::streamoff size = in.tellg();
  if (size < 0) throw InputError(file.string() + ": cannot read its size");
  bytes.resize(static_cast<std::size_t>(size));
  in.seekg(0);
  in.read(reinterpret_cast<char*>(bytes.data()), size);
  if (in.gcount() != size) {
    throw InputError(file.string() + ": cannot read its " + std::to_string(size) + " bytes");
  }
}

void WriteFileBytes(const std::filesystem::path& file, const std::uint8_t* bytes,
                    std::size_t size) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes), static_cast<std::streamsize>(size));
  if (!out) throw InputError(file.string() + ": cannot write");
}

}  // namespace statebench::sensors
