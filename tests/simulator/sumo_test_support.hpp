// Helpers shared by the SUMO-side simulator tests: a fresh temporary folder, file writing, and
// a small grid-town scenario whose parts a test can replace.
#pragma once

#include <stdlib.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <string>

#include "core/error.hpp"
#include "tests/removed_at_exit.hpp"

namespace statebench::sim::testing {

// The source tree (ctest sets STATEBENCH_SOURCE_DIR; tests also run from the repository root).
inline std::filesystem::path SourceDir() {
  const char* dir = std::getenv("STATEBENCH_SOURCE_DIR");
  return dir ? std::filesystem::path(dir) : std::filesystem::current_path();
}

// An emptied folder <tmp>/statebench_<prefix>_<name>_<pid> for one run's outputs, removed when
// the test program ends (the process id keeps two test programs running at once, e.g. two build
// trees' ctest, out of each other's folders).
inline std::filesystem::path FreshWorkDir(const std::string& prefix, const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("statebench_" + prefix + "_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  return statebench::testing::RemovedAtExit(dir);
}

class TempDir {
 public:
  TempDir() {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "statebench_sumo_XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline std::filesystem::path WriteFile(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path) << text;
  return path;
}

// The InputError message of f, or "" when it does not throw one.
inline std::string InputErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A 3 x 3 grid town (100 m blocks, dead-end streets of 50 m, traffic lights with a 40 s cycle,
// junction heights of sigma 1 m) driven around one block. Each argument replaces a section.
struct GridScenarioParts {
  std::string header =
      "name: grid_test\nseed: 11\nduration_s: 40.0\n"
      "origin: {latitude_deg: 48.78, longitude_deg: 2.13, altitude_m: 100.0}\n"
      "vehicle: quadricycle\n";
  std::string network =
      "network:\n"
      "  generate:\n"
      "    grid: {number: 3, length_m: 100.0, attach_length_m: 50.0}\n"
      "    speed_mps: 13.89\n"
      "    traffic_lights: true\n"
      "    tls_cycle_s: 40\n"
      "    elevation: {sigma_m: 1.0, limit_m: 2.0}\n";
  std::string ego =
      "ego:\n"
      "  route: [A0A1, A1B1, B1B0, B0A0]\n"
      "  loops: 3\n"
      "  depart_pos_m: 5.0\n";
  std::string traffic =
      "traffic:\n"
      "  density: 12\n"
      "  flows:\n"
      "    - {from: left1A1, to: C1right1, vehs_per_hour: 400}\n";
  std::string rest = "sumo:\n  step_s: 0.1\n";

  std::string Text() const { return header + network + ego + traffic + rest; }
};

}  // namespace statebench::sim::testing
