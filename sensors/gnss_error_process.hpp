// The position error of one GNSS antenna over time: white + first-order Gauss-Markov +
// multipath jumps (gnss_options.hpp gives the model). The white and Gauss-Markov parts are kept
// at unit variance and scaled by the sigmas of the current fix mode, so a mode change (urban
// canyon) changes the error magnitude without a jump in the process state.
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

  GnssOptions options_;
  std::mt19937_64 white_rng_, gm_rng_, multipath_rng_;
  NormalSampler white_normal_, gm_normal_, multipath_normal_;
  GaussMarkov3 unit_gm_;
  std::optional<TimeNs> last_t_ns_;
  // Multipath timeline: the next event's start, or the current event once drawn.
  bool event_drawn_ = false;
  TimeNs event_start_ns_ = 0;
  TimeNs event_end_ns_ = 0;
  Vec3 event_offset_ = Vec3::Zero();
  bool in_multipath_ = false;
};

}  // namespace statebench::sensors
