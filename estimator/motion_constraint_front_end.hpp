// Motion-constraint front end: vehicle-model-free factors on the IMU stream. Non-holonomic: the
// rear axle moves neither sideways nor vertically (sigma growing with the lateral acceleration
// for slip), at `rate_hz` while no kinematic factor constrains the same motion; optionally in a
// frame turned by the IMU mount's estimated pitch and yaw (`estimate_mount`). Zero velocity:
// the IMU is quiet over a window (raw, or below ~3 Hz with an engine running) and a speed
// reading says the vehicle stands: the speed encoder reads zero, else the receiver's Doppler
// velocity is near zero, else (neither in the setup, or a GNSS outage) the estimated speed is
// low (motion_factor_options.hpp, ZeroVelocityOptions). The factor's sigma is the creep the
// speed reading cannot rule out: sigma_mps with an encoder, the sigma of the Doppler mean when
// that mean agrees with zero, else sigma_without_encoder_mps.
#pragma once

#include <optional>

#include "estimator/encoder_front_end.hpp"
#include "estimator/factor_plan.hpp"
#include "estimator/front_end.hpp"
#include "estimator/gnss_front_end.hpp"
#include "estimator/imu_still_window.hpp"

namespace statebench::est {

// With non_holonomic.estimate_mount: the IMU mount's pitch and yaw against the vehicle frame as
// globals of the window (the IMU's "mount_pitch_rad", "mount_yaw_rad"), shared by the
// non-holonomic constraint and the kinematic factor (both measure in that frame); else none.
std::optional<SlidingWindowSmoother::MountCorrection> ImuMountCorrection(
    const NonHolonomicOptions& nhc, const std::string& imu_id, FrontEndContext& ctx);

class MotionConstraintFrontEnd final : public MeasurementFrontEnd {
 public:
  // `plan`, `options`, `encoders` and `gnss` must outlive the front end.
  MotionConstraintFrontEnd(const EstimatorSensorSetup& setup, const FactorPlan& plan,
                           const FactorGraphOptions& options, const EncoderFrontEnd& encoders,
                           const GnssFrontEnd& gnss, FrontEndContext& ctx);

  Claim Claims(const Measurement&) const override { return Claim::kOtherKind; }
  void Process(const Measurement&) override {}
  void OnImu(const ImuSample& s) override;

 private:
  void AddNonHolonomic(const ImuSample& s);
  // The zero-velocity factor's sigma when the vehicle stands still, nullopt when it does not.
  std::optional<double> StandingStill(TimeNs t_ns) const;

  const std::string imu_id_;
  const FactorPlan& plan_;
  const FactorGraphOptions& options_;
  const EncoderFrontEnd& encoders_;
  const GnssFrontEnd& gnss_;
  FrontEndContext& ctx_;
  ImuStillWindow recent_imu_;  // released samples over the zero-velocity window
  TimeNs next_nhc_ns_ = INT64_MIN;
  TimeNs next_zupt_ns_ = INT64_MIN;
};

}  // namespace statebench::est
