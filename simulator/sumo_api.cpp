#include "simulator/sumo_api.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace statebench::sim {
namespace {

namespace fs = std::filesystem;

constexpr const char* kModuleName = "libstatebench_sumo.so";

// Where the module may be, in the order tried.
std::vector<fs::path> ModuleCandidates() {
  std::vector<fs::path> out;
  if (const char* env = std::getenv("STATEBENCH_SUMO_MODULE"); env != nullptr && *env != '\0') {
    out.emplace_back(env);
    return out;  // the user's choice only
  }
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) out.push_back(exe.parent_path().parent_path() / "lib" / kModuleName);
#ifdef STATEBENCH_SUMO_MODULE_PATH
  out.emplace_back(STATEBENCH_SUMO_MODULE_PATH);
#endif
  return out;
}

SumoApi* LoadModule() {
  std::string tried;
  for (const fs::path& candidate : ModuleCandidates()) {
    std::error_code ec;
    if (!fs::exists(candidate, ec)) {
      tried += "\n  " + candidate.string() + ": no such file";
      continue;
    }
    void* handle = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      const char* why = dlerror();
      tried += "\n  " + candidate.string() + ": " + (why != nullptr ? why : "dlopen failed");
      continue;
    }
    // The module stays loaded for the life of the process (libsumo's state lives in it).
    using Entry = SumoApi* (*)();
    auto* entry = reinterpret_cast<Entry>(dlsym(handle, "statebench_sumo_api"));
    if (entry == nullptr) {
      tried += "\n  " + candidate.string() + ": no statebench_sumo_api entry point";
      continue;
    }
    return entry();
  }
  throw std::runtime_error(std::string("cannot load SUMO's bridge ") + kModuleName +
                           " (set STATEBENCH_SUMO_MODULE to its path); tried:" + tried);
}

}  // namespace

SumoApi& Sumo() {
  // Loaded once (a function-local static: thread-safe, and no lock on the calls after it); a
  // failed load throws, leaves the static uninitialised, and the next call tries again.
  static SumoApi& api = *LoadModule();
  return api;
}

}  // namespace statebench::sim
