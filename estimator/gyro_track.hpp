// The raw gyro's rotation between two stamps: the samples as they come, each rate held until the
// next sample (no bias correction: over a lidar sweep an industrial gyro's bias turns the frame
// by micro-radians, and the registration corrects the rest).
#pragma once

#include <deque>
#include <optional>

#include "core/se3.hpp"
#include "core/time.hpp"

namespace statebench::est {

class GyroTrack {
 public:
  // Samples in increasing stamp order (an older or equal stamp is ignored).
  void Add(TimeNs t_ns, const Vec3& gyro_radps);
  // Rotation of the IMU frame from t0 to t1 (R_t0_t1), nullopt if the samples do not cover
  // [t0, t1] (t0 <= t1).
  std::optional<Quat> Rotation(TimeNs t0_ns, TimeNs t1_ns) const;
  // Forgets the samples no longer needed for rotations from t_ns on.
  void DropBefore(TimeNs t_ns);

  TimeNs newest_ns() const { return samples_.empty() ? INT64_MIN : samples_.back().t_ns; }

 private:
  struct Sample {
    TimeNs t_ns;
    Vec3 gyro;
  };
  std::deque<Sample> samples_;
};

}  // namespace statebench::est
