#include "estimator/imu_triad_globals.hpp"

#include <vector>

namespace statebench::est {
namespace {

std::string TermName(const ImuTriadTerm& t) {
  static constexpr const char kAxis[3] = {'x', 'y', 'z'};
  const std::string triad = t.triad == ImuTriadTerm::Triad::kGyro ? "gyro_" : "accel_";
  if (t.row == t.col) return triad + "scale_" + kAxis[t.row];
  return triad + kAxis[t.row] + kAxis[t.col];
}

}  // namespace

void AddImuTriadGlobals(const ImuTriadOptions& options, const std::string& imu_id,
                        FrontEndContext* ctx) {
  if (!options.any()) return;
  std::vector<SlidingWindowSmoother::ImuTriadGlobal> globals;
  const auto add = [&](ImuTriadTerm::Triad triad, double scale_sigma, double cross_sigma) {
    for (const ImuTriadTerm& t : AllTriadTerms(triad)) {
      const double sigma = t.row == t.col ? scale_sigma : cross_sigma;
      globals.push_back({ctx->Global(imu_id, TermName(t), sigma, options.max_sigmas * sigma), t});
    }
  };
  if (options.estimate_gyro) {
    add(ImuTriadTerm::Triad::kGyro, options.gyro_scale_sigma, options.gyro_misalignment_sigma_rad);
  }
  if (options.estimate_accel) {
    add(ImuTriadTerm::Triad::kAccel, options.accel_scale_sigma,
        options.accel_misalignment_sigma_rad);
  }
  ctx->smoother.SetImuTriad(std::move(globals));
}

}  // namespace statebench::est
