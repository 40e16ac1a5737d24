// Modules of our own: shared libraries built beside `statebench` that hold the code linking a
// heavy dependency (SUMO's libsumocpp, PCL's I/O), loaded with dlopen the first time a process
// needs it, so that a process that does not need it does not pay for loading and initialising
// that dependency's shared libraries at start-up (simulator/sumo_api.hpp, sensors/pcl_pcd_api.hpp).
//
// A module exports one extern "C" entry point that returns its one instance of an interface
// (a class of pure virtual functions) declared in a header of the library that loads it.
#pragma once

#include <filesystem>
#include <vector>

namespace statebench {

struct ModuleSpec {
  const char* file_name = nullptr;     // e.g. "libstatebench_sumo.so"
  const char* env_variable = nullptr;  // when set and not empty: the only place tried
  const char* build_path = nullptr;    // where the build put it (nullptr when unknown)
  const char* entry_point = nullptr;   // the exported function returning the instance
  const char* what = nullptr;          // for messages, e.g. "SUMO's bridge"
};

// Where the module may be, in the order tried: $env_variable when set (alone); else file_name
// in ../lib beside the running program; else build_path.
std::vector<std::filesystem::path> ModuleCandidates(const ModuleSpec& spec);

// The address of the entry point of the first candidate that loads (the caller casts it to the
// entry point's own type). The module stays loaded for the life of the process.
// std::runtime_error naming every place tried and the loader's message when none loads.
void* LoadModuleEntry(const ModuleSpec& spec);

// The module's instance: its entry point, of type Api* (), called on the first call (a
// function-local static: thread-safe, and no lock on the calls after it). A failed load throws,
// leaves the static uninitialised, and the next call tries again.
template <typename Api, const ModuleSpec& kSpec>
Api& LoadedModule() {
  static Api& api = *reinterpret_cast<Api* (*)()>(LoadModuleEntry(kSpec))();
  return api;
}

}  // namespace statebench
