// The part of PCL's I/O that lidar_pcd_io.cpp calls, behind an interface that a small module
// (sensors/pcd/pcl_pcd_module.cpp, built as libstatebench_pcd.so) implements and that is loaded
// with dlopen the first time a process writes a PCD file or reads one that is not plain binary
// (core/module_loader.hpp).
//
// Why not link PCL's I/O directly: libpcl_io pulls in 67 shared libraries (VTK, OpenNI, libusb,
// Boost, ...) whose loading and static initialisation cost every `statebench` process about
// 0.04 CPU s at start-up, PCD files or not (`statebench estimate` of an IMU + GNSS log, `results`,
// `report`). Logs are recorded as packets files by default (--lidar-format packets or sweep need
// no PCL), and binary PCD files are read without PCL: only a process that writes PCD or reads
// ascii or binary_compressed PCD pays for PCL, once.
//
// Errors come back as messages (no exception crosses the module's boundary).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/measurements.hpp"

namespace statebench::sensors {

// A cloud as PCL reads it: width x height points of point_step bytes each, in data.
struct PclCloud {
  std::uint64_t points = 0;
  std::uint32_t point_step = 0;
  std::vector<std::uint8_t> data;
};

class PclPcdApi {
 public:
  virtual ~PclPcdApi() = default;
  // Writes `points` as a binary PCD (lidar_pcd_io.hpp's fields); an empty sweep is its header
  // alone (PCL refuses to write a cloud without data). Empty on success, else what failed.
  virtual std::string WriteBinary(const std::string& file,
                                  const std::vector<LidarPoint>& points) = 0;
  // PCL's reading of the whole file (ascii, binary or binary_compressed). Empty on success,
  // else what failed.
  virtual std::string Read(const std::string& file, PclCloud* cloud) = 0;
};

// The module's PCL, loaded on the first call (thread-safe). The module is looked up as
// $STATEBENCH_PCD_MODULE when set, else libstatebench_pcd.so in ../lib beside the running
// program, else where the build put it. std::runtime_error naming every place tried and the
// loader's message when it cannot be loaded.
PclPcdApi& PclPcd();

}  // namespace statebench::sensors

// The module's entry point: its one PclPcdApi instance.
extern "C" statebench::sensors::PclPcdApi* statebench_pcd_api();
