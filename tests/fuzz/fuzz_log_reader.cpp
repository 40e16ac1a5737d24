// Fuzz target: a recorded log folder (docs/log-format.md) read by LogReader, every stream to its
// end, and its truth file. The input is a list of files, each introduced by a line
// "== relative/path" (letters, digits, '_', '-', '.', '/'; no ".."), the first usually log.yaml.
// Lidar sweeps may be PCDs, sweep files (lidar_sweep_file.hpp) or packets files
// (lidar_packet_file.hpp); make_seeds.py writes small ones of each. Bad input must end in an
// InputError or a reader error naming file and line (for a sweep or packets file: the field),
// never a crash.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "core/error.hpp"
#include "core/truth_io.hpp"
#include "fuzz_support.hpp"
#include "sensors/log_reader.hpp"

namespace {

bool SafePath(std::string_view p) {
  if (p.empty() || p.size() > 64 || p.front() == '/' || p.find("..") != std::string_view::npos) {
    return false;
  }
  for (char c : p) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-' || c == '.' || c == '/';
    if (!ok) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fs = std::filesystem;
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const fs::path dir = statebench::fuzz::ScratchDir() / "log";
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir);
  // Split into files at lines starting with "== ".
  std::size_t pos = input.rfind("== ", 0) == 0 ? 0 : input.find("\n== ");
  if (pos == std::string_view::npos) return 0;
  if (pos != 0) ++pos;
  int files = 0;
  while (pos != std::string_view::npos && files < 16) {
    const std::size_t name_end = input.find('\n', pos);
    if (name_end == std::string_view::npos) break;
    const std::string_view name = input.substr(pos + 3, name_end - pos - 3);
    std::size_t next = input.find("\n== ", name_end);
    const std::string_view content =
        input.substr(name_end + 1, (next == std::string_view::npos ? input.size() : next + 1) -
                                       (name_end + 1));
    if (SafePath(name) && statebench::fuzz::WriteFile(dir / std::string(name), content)) {
      ++files;
    }
    pos = next == std::string_view::npos ? next : next + 1;
  }
  try {
    statebench::sensors::LogReader reader(dir);
    for (int n = 0; n < 100000 && reader.Next(); ++n) {
    }
    if (reader.manifest().truth_csv) statebench::ReadTruthCsv(dir / *reader.manifest().truth_csv);
  } catch (const statebench::InputError&) {
  } catch (const std::exception& e) {
    statebench::fuzz::Unexpected("fuzz_log_reader", e);
  }
  return 0;
}
