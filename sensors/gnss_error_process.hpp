// The position error of one GNSS antenna over time: white + first-order Gauss-Markov +
// multipath jumps (gnss_options.hpp gives the model). The white and Gauss-Markov parts are kept
// at unit variance and scaled by the sigmas of the current fix mode, so a mode change (urban
// canyon) changes the error magnitude without a jump in the process state.
//
// Common mode: the Gauss-Markov part is the slowly varying error of the RTK solution (reference
// station, atmosphere and orbit residuals of the correction stream), which antennas on one
// vehicle a few metres apart share; only the white part and multipath are antenna-specific. So
// the unit Gauss-Markov process is a function of time alone, common to every antenna of a run:
// it is driven by one random stream (seed, "gnss_common_mode/gauss_markov") and stepped on a
// fixed grid of kCommonModeStep from t = 0 (held between grid points; 10 ms << tau), so two
// antennas with the same tau get the same value at any stamp whatever their rates, outages or
// fix stamps. A dual-antenna heading (difference of two fixes) thus sees the antenna-specific
// errors only, as with a real moving-baseline receiver.
#pragma once

#include <cstdint>
#include <optional>
#include <random>
#include <string>

#include "core/eigen_types.hpp"
#include "core/random.hpp"
#include "core/time.hpp"
#include "sensors/gauss_markov.hpp"
#include "sensors/gnss_options.hpp"

namespace statebench::sensors {

class GnssErrorProcess {
 public:
  GnssErrorProcess(const GnssOptions& options, std::uint64_t seed, const std::string& stream_name);

  // ENU error (m) of the fix at t_ns (strictly increasing between calls) for an accuracy.
  Vec3 Sample(TimeNs t_ns, const GnssAccuracy& accuracy);

  // True if the last sample was inside a multipath event.
  bool in_multipath() const { return in_multipath_; }

 private:
  void AdvanceMultipath(TimeNs t_ns);
  // Steps the common-mode unit process along its grid up to the last grid point <= t_ns.
  void AdvanceCommonMode(TimeNs t_ns);

  static constexpr TimeNs kCommonModeStep = 10'000'000;  // 10 ms

  GnssOptions options_;
  std::mt19937_64 white_rng_, gm_rng_, multipath_rng_;
  NormalSampler white_normal_, gm_normal_, multipath_normal_;
  GaussMarkov3 unit_gm_;
  TimeNs gm_grid_ns_ = 0;  // grid stamp of unit_gm_'s value
  std::optional<TimeNs> last_t_ns_;
  // Multipath timeline: the next event's start, or the current event once drawn.
  bool event_drawn_ = false;
  TimeNs event_start_ns_ = 0;
  TimeNs event_end_ns_ = 0;
  Vec3 event_offset_ = Vec3::Zero();
  bool in_multipath_ = false;
};

}  // namespace statebench::sensors
