// Where a run's time goes: the pipeline's thread charges its time to one named stage at a time
// (log reading, SUMO, world, vehicle model, sensor synthesis, lidar raycast, estimators, lidar odometry,
// writing, scoring; everything else to `other`). A StageScope switches the stage for its
// lifetime and switches back when it ends, so nested scopes give exclusive times (the lidar
// raycast is not counted again under sensor synthesis) and the stages add up to the whole.
//
// Clocks: a scope reads the monotonic clock (about 60 ns); reading a CPU-time clock is a system
// call (2-3 us on the machines we run on), too dear at every IMU sample. The two stages that run
// on worker threads (lidar raycast, lidar odometry: TBB, a few times a second) also read the
// process's CPU time. CpuSplit then gives every stage CPU seconds: the parallel stages their
// measured process CPU time, the others the rest of the process's CPU time in proportion to their
// monotonic time (exact for a serial pipeline that is not preempted). The stages add up to the
// process's CPU time over the span.
//
// Per thread (the pipeline's); library code may open scopes freely: nothing is printed or stored
// beyond the thread's per-stage totals.
#pragma once

#include <array>
#include <cstddef>
#include <string_view>

namespace statebench {

enum class Stage : int {
  kOther = 0,
  kReading,        // a recorded log read
  kSumo,           // SUMO's output read and the road network built (its processes: children)
  kWorld,          // the lidar world built (terrain, layout, BVHs)
  kVehicle,        // truth: the vehicle model
  kSensors,        // sensor synthesis except the lidar raycast
  kLidarRaycast,   // the lidar simulation's ray casting
  kEstimators,     // estimators except their lidar odometry
  kLidarOdometry,  // the factor graph's scan registration
  kWriting,        // estimates, diagnostics and logs written
  kScoring,        // metrics against the truth
  kCount
};

inline constexpr std::size_t kStageCount = static_cast<std::size_t>(Stage::kCount);

std::string_view StageName(Stage stage);

// Whether the stage runs work on other threads (its process CPU time is measured).
bool StageIsParallel(Stage stage);

// Per stage, seconds charged on this thread: monotonic time, and for the parallel stages the
// process's CPU time while they ran.
struct StageTimes {
  std::array<double, kStageCount> monotonic_s{};
  std::array<double, kStageCount> process_cpu_s{};  // parallel stages only

  StageTimes operator-(const StageTimes& earlier) const;
  StageTimes& operator+=(const StageTimes& more);
};

// This thread's totals up to now (the open stage included).
StageTimes CurrentStageTimes();

// CPU seconds (user + system) of the whole process, of its threads so far.
double ProcessCpuSeconds();

// How monotonic time on the pipeline's thread converts to CPU time over a span whose process CPU
// time was process_cpu_s: the parallel stages keep their measured CPU time, the rest of the
// process's CPU time is spread over the serial stages' monotonic time (see above).
class CpuAttribution {
 public:
  CpuAttribution(const StageTimes& span, double process_cpu_s);

  // CPU seconds per stage of `part` (the span itself, or a part of it such as one estimator's
  // calls); for the span they add up to process_cpu_s.
  std::array<double, kStageCount> Split(const StageTimes& part) const;
  double Total(const StageTimes& part) const;

 private:
  double cpu_per_serial_s_ = 0.0;
  double unattributed_cpu_s_ = 0.0;  // CPU time of a span without any serial monotonic time
};

class StageScope {
 public:
  explicit StageScope(Stage stage);
  ~StageScope();
  StageScope(const StageScope&) = delete;
  StageScope& operator=(const StageScope&) = delete;

 private:
  Stage previous_;
};

}  // namespace statebench
