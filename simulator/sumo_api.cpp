#include "simulator/sumo_api.hpp"

#include "core/module_loader.hpp"

namespace statebench::sim {
namespace {

constexpr ModuleSpec kSumoModule{
    .file_name = "libstatebench_sumo.so",
    .env_variable = "STATEBENCH_SUMO_MODULE",
#ifdef STATEBENCH_SUMO_MODULE_PATH
    .build_path = STATEBENCH_SUMO_MODULE_PATH,
#endif
    .entry_point = "statebench_sumo_api",
    .what = "SUMO's bridge"};

}  // namespace

// The module stays loaded for the life of the process (libsumo's state lives in it).
SumoApi& Sumo() { return LoadedModule<SumoApi, kSumoModule>(); }

}  // namespace statebench::sim
