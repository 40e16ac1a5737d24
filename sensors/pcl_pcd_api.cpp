#include "sensors/pcl_pcd_api.hpp"

#include "core/module_loader.hpp"

namespace statebench::sensors {
namespace {

constexpr ModuleSpec kPcdModule{
    .file_name = "libstatebench_pcd.so",
    .env_variable = "STATEBENCH_PCD_MODULE",
#ifdef STATEBENCH_PCD_MODULE_PATH
    .build_path = STATEBENCH_PCD_MODULE_PATH,
#endif
    .entry_point = "statebench_pcd_api",
    .what = "PCL's PCD reader and writer"};

}  // namespace

PclPcdApi& PclPcd() { return LoadedModule<PclPcdApi, kPcdModule>(); }

}  // namespace statebench::sensors
