// Online calibration of the speed encoder's scale (wheel radius): the kinematic factor's
// distance is only as good as the radius, whose error (tyre wear, pressure, load: about 1 %) is
// the same for every period, while the factor treats the periods as independent. Left alone, a
// 1 % radius error becomes a velocity bias the smoother believes (10 cm/s at 10 m/s).
//
// The scale is the ratio of the distance the rear-axle centre travelled according to the
// smoothed states (final, once they leave the window: fused with GNSS, lidar and IMU) to the
// raw encoder distance over the same spans, summed over the last `window_m` metres of encoder
// distance while moving. The smoothed states carry the kinematic factor's own (scaled) distance
// too, so the estimate is a fixed-point iteration; it converges to the true scale whenever
// another sensor constrains the distance, at a rate set by the kinematic factor's share.
//
// Distance of the axle between two smoothed states a, b (dt apart): the mean IMU-frame velocity
// plus omega x p_imu_axle, omega = Log(R_a^T R_b) / dt, along the axle frame's x axis.
#pragma once

#include <deque>
#include <optional>
#include <vector>

#include "core/se3.hpp"
#include "core/state.hpp"
#include "core/time.hpp"

namespace statebench::est {

class EncoderScaleCalibration {
 public:
  // T_imu_axle: the speed encoder's mount in the IMU frame.
  EncoderScaleCalibration(const SE3& T_imu_axle, double window_m = 300.0,
                          double min_distance_m = 50.0);

  // A raw speed sample: mean speed over (t_ns - dt, t_ns].
  void AddSpeed(TimeNs t_ns, double raw_speed_mps);
  // Smoothed states that left the window, oldest first, in time order across calls.
  void AddSmoothedStates(const std::vector<NavState>& states);
  // nullopt until min_distance_m of moving encoder distance is compared.
  std::optional<double> scale() const;

 private:
  struct Span {
    double smoothed_m = 0.0;
    double encoder_m = 0.0;
  };
  double EncoderDistance(TimeNs t0_ns, TimeNs t1_ns) const;

  SE3 T_imu_axle_;
  double window_m_;
  double min_distance_m_;
  std::deque<std::pair<TimeNs, double>> speeds_;  // (stamp, raw speed), recent
  std::optional<NavState> last_state_;
  std::deque<Span> spans_;
  double sum_smoothed_m_ = 0.0;
  double sum_encoder_m_ = 0.0;
};

}  // namespace statebench::est
