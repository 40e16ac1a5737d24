// Shared pieces of the fuzz targets (libFuzzer; built with -DSTATEBENCH_FUZZ=ON and clang,
// docs/fuzzing.md): a private scratch folder per process, and the one failure a target reports
// besides the sanitizers' (an exception other than the documented InputError).
#pragma once

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace statebench::fuzz {

// A folder of this process under the temporary folder, removed at exit.
inline const std::filesystem::path& ScratchDir() {
  static const std::filesystem::path dir = [] {
    std::filesystem::path d = std::filesystem::temp_directory_path() /
                              ("statebench_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(std::filesystem::temp_directory_path() /
                                      ("statebench_fuzz_" + std::to_string(::getpid())),
                                  ec);
    });
    return d;
  }();
  return dir;
}

// Writes the file, creating its folders; false when the input's paths clash (a file where a
// folder must go, "a/" as a file name): the harness skips such a file, it is not a finding.
inline bool WriteFile(const std::filesystem::path& path, std::string_view content) {
  std::error_code ec;
  std::filesystem::create_directories(path.parent_path(), ec);
  if (ec || std::filesystem::is_directory(path, ec)) return false;
  std::ofstream out(path, std::ios::binary);
  out.write(content.data(), static_cast<std::streamsize>(content.size()));
  return static_cast<bool>(out);
}

// An exception that is not the documented InputError is a finding: print it and abort, so
// libFuzzer keeps the input.
[[noreturn]] inline void Unexpected(const char* target, const std::exception& e) {
  std::fprintf(stderr, "%s: unexpected exception: %s\n", target, e.what());
  std::abort();
}

}  // namespace statebench::fuzz
