#include "core/module_loader.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <stdexcept>
#include <string>

namespace statebench {

namespace fs = std::filesystem;

std::vector<fs::path> ModuleCandidates(const ModuleSpec& spec) {
  std::vector<fs::path> out;
  if (const char* env = std::getenv(spec.env_variable); env != nullptr && *env != '\0') {
    out.emplace_back(env);
    return out;  // the user's choice only
  }
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) out.push_back(exe.parent_path().parent_path() / "lib" / spec.file_name);
  if (spec.build_path != nullptr && *spec.build_path != '\0') out.emplace_back(spec.build_path);
  return out;
}

void* LoadModuleEntry(const ModuleSpec& spec) {
  std::string tried;
  for (const fs::path& candidate : ModuleCandidates(spec)) {
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
    if (void* entry = dlsym(handle, spec.entry_point); entry != nullptr) return entry;
    tried += "\n  " + candidate.string() + ": no " + spec.entry_point + " entry point";
  }
  throw std::runtime_error(std::string("cannot load ") + spec.what + " " + spec.file_name +
                           " (set " + spec.env_variable + " to its path); tried:" + tried);
}

}  // namespace statebench
