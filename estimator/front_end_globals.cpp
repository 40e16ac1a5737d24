// FrontEndContext's globals of the window, by sensor and name, and their diagnostics
// (front_end.hpp).
#include "estimator/front_end.hpp"

namespace statebench::est {
namespace {

// The names of a mount correction's globals, roll, pitch, yaw (about the frame's own axes).
constexpr const char* kMountAxisGlobals[3] = {"mount_roll_rad", "mount_pitch_rad",
                                              "mount_yaw_rad"};

}  // namespace

int FrontEndContext::Global(const std::string& sensor_id, const std::string& name,
                            double prior_sigma, double max_abs,
                            std::optional<double> correlation_time_s) {
  const auto key = std::make_pair(sensor_id, name);
  auto it = globals_.find(key);
  if (it == globals_.end()) {
    const int index = smoother.AddGlobal(sensor_id + " " + name, prior_sigma, max_abs,
                                           correlation_time_s);
    it = globals_.emplace(key, index).first;
  }
  return it->second;
}

std::optional<int> FrontEndContext::FindGlobal(const std::string& sensor_id,
                                               const std::string& name) const {
  const auto it = globals_.find(std::make_pair(sensor_id, name));
  if (it == globals_.end()) return std::nullopt;
  return it->second;
}

SlidingWindowSmoother::MountCorrection FrontEndContext::MountGlobals(const std::string& sensor_id,
                                                                    double prior_sigma_rad,
                                                                    double max_rad,
                                                                    bool with_roll) {
  SlidingWindowSmoother::MountCorrection c;
  if (with_roll) c.roll = Global(sensor_id, kMountAxisGlobals[0], prior_sigma_rad, max_rad);
  c.pitch = Global(sensor_id, kMountAxisGlobals[1], prior_sigma_rad, max_rad);
  c.yaw = Global(sensor_id, kMountAxisGlobals[2], prior_sigma_rad, max_rad);
  return c;
}

Vec3 FrontEndContext::MountEstimate(const std::string& sensor_id) const {
  Vec3 c = Vec3::Zero();
  for (int axis = 0; axis < 3; ++axis) {
    if (const std::optional<int> i = FindGlobal(sensor_id, kMountAxisGlobals[axis])) {
      c[axis] = smoother.Global(*i).value;
    }
  }
  return c;
}

void FrontEndContext::RecordGlobals() {
  if (globals_.empty()) return;
  const TimeNs t = smoother.NewestState().t_ns;
  const std::vector<SlidingWindowSmoother::GlobalEstimate> estimates = smoother.Globals();
  for (const auto& [key, index] : globals_) {
    const SlidingWindowSmoother::GlobalEstimate& e = estimates[index];
    GlobalDiagnostics& d = Counters(key.first).globals[key.second];
    d.value = e.value;
    d.sigma = e.sigma;
    d.clamped = e.num_clamped;
    if (d.history.empty() || t - d.history.back().t_ns >= FromSeconds(kGlobalHistoryPeriodS)) {
      d.history.push_back({t, e.value, e.sigma});
    }
  }
}

}  // namespace statebench::est
