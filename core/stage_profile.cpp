#include "core/stage_profile.hpp"

#include <time.h>

#include <algorithm>
#include <chrono>

namespace statebench {
namespace {

struct ThreadStages {
  Stage current = Stage::kOther;
  std::chrono::steady_clock::time_point since = std::chrono::steady_clock::now();
  double since_cpu_s = 0.0;  // process CPU time when the current (parallel) stage began
  StageTimes times;

  // Charges the time since the last switch to the current stage and makes `next` current.
  void SwitchTo(Stage next) {
    const auto now = std::chrono::steady_clock::now();
    const auto i = static_cast<std::size_t>(current);
    times.monotonic_s[i] += std::chrono::duration<double>(now - since).count();
    since = now;
    if (StageIsParallel(current) || StageIsParallel(next)) {
      const double cpu = ProcessCpuSeconds();
      if (StageIsParallel(current)) times.process_cpu_s[i] += cpu - since_cpu_s;
      since_cpu_s = cpu;
    }
    current = next;
  }
};

ThreadStages& This() {
  thread_local ThreadStages stages;
  return stages;
}

}  // namespace

std::string_view StageName(Stage stage) {
  switch (stage) {
    case Stage::kOther: return "other";
    case Stage::kReading: return "reading";
    case Stage::kSumo: return "sumo";
    case Stage::kWorld: return "world";
    case Stage::kVehicle: return "vehicle";
    case Stage::kSensors: return "sensors";
    case Stage::kLidarRaycast: return "lidar_raycast";
    case Stage::kEstimators: return "estimators";
    case Stage::kLidarOdometry: return "lidar_odometry";
    case Stage::kWriting: return "writing";
    case Stage::kScoring: return "scoring";
    case Stage::kCount: break;
  }
  return "?";
}

bool StageIsParallel(Stage stage) {
  return stage == Stage::kLidarRaycast || stage == Stage::kLidarOdometry;
}

StageTimes StageTimes::operator-(const StageTimes& earlier) const {
  StageTimes d;
  for (std::size_t i = 0; i < kStageCount; ++i) {
    d.monotonic_s[i] = monotonic_s[i] - earlier.monotonic_s[i];
    d.process_cpu_s[i] = process_cpu_s[i] - earlier.process_cpu_s[i];
  }
  return d;
}

StageTimes& StageTimes::operator+=(const StageTimes& more) {
  for (std::size_t i = 0; i < kStageCount; ++i) {
    monotonic_s[i] += more.monotonic_s[i];
    process_cpu_s[i] += more.process_cpu_s[i];
  }
  return *this;
}

StageTimes CurrentStageTimes() {
  ThreadStages& t = This();
  t.SwitchTo(t.current);
  return t.times;
}

double ProcessCpuSeconds() {
  timespec ts{};
  if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0) return 0.0;
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

CpuAttribution::CpuAttribution(const StageTimes& span, double process_cpu_s) {
  double parallel_cpu = 0.0;
  double serial_monotonic = 0.0;
  for (std::size_t i = 0; i < kStageCount; ++i) {
    if (StageIsParallel(static_cast<Stage>(i))) {
      parallel_cpu += std::max(0.0, span.process_cpu_s[i]);
    } else {
      serial_monotonic += std::max(0.0, span.monotonic_s[i]);
    }
  }
  const double serial_cpu = std::max(0.0, process_cpu_s - parallel_cpu);
  if (serial_monotonic > 0.0) {
    cpu_per_serial_s_ = serial_cpu / serial_monotonic;
  } else {
    unattributed_cpu_s_ = serial_cpu;
  }
}

std::array<double, kStageCount> CpuAttribution::Split(const StageTimes& part) const {
  std::array<double, kStageCount> cpu{};
  for (std::size_t i = 0; i < kStageCount; ++i) {
    cpu[i] = StageIsParallel(static_cast<Stage>(i))
                 ? std::max(0.0, part.process_cpu_s[i])
                 : cpu_per_serial_s_ * std::max(0.0, part.monotonic_s[i]);
  }
  cpu[static_cast<std::size_t>(Stage::kOther)] += unattributed_cpu_s_;
  return cpu;
}

double CpuAttribution::Total(const StageTimes& part) const {
  double sum = 0.0;
  for (double s : Split(part)) sum += s;
  return sum;
}

StageScope::StageScope(Stage stage) : previous_(This().current) { This().SwitchTo(stage); }

StageScope::~StageScope() { This().SwitchTo(previous_); }

}  // namespace statebench
