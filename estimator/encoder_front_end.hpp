// Encoder front end: the speed and steering encoders. With both (and the kinematic factor on),
// the single-track kinematics between speed samples (KinematicOdometry) become relative-pose
// factors at the rear axle, with the wheel radius calibrated online from the smoothed states.
// The newest speed sample also serves the moving initialisation (velocity from the encoder) and
// the standstill test of the motion constraints.
#pragma once

#include <deque>
#include <optional>
#include <utility>

#include "estimator/encoder_scale_calibration.hpp"
#include "estimator/factor_plan.hpp"
#include "estimator/front_end.hpp"
#include "estimator/kinematic_odometry.hpp"

namespace statebench::est {

class EncoderFrontEnd final : public MeasurementFrontEnd {
 public:
  // `setup` (through `plan`) and `options` must outlive the front end.
  EncoderFrontEnd(const EstimatorSensorSetup& setup, const FactorPlan& plan,
                  const FactorGraphOptions& options, FrontEndContext& ctx);

  // The newest speed sample (stamp, m/s), if any.
  std::optional<std::pair<TimeNs, double>> last_speed() const {
    if (recent_speeds_.empty()) return std::nullopt;
    return recent_speeds_.back();
  }
  // Every speed sample from from_ns to the newest reads at most max_mps (and there is one at
  // from_ns or before, so the span is covered). A creeping car's encoder reads zero between
  // its ticks: one zero sample is not a standstill, a window without a tick is.
  bool ReadsZeroSince(TimeNs from_ns, double max_mps) const;
  bool has_speed_encoder() const { return plan_.speed != nullptr; }
  // A kinematic factor ends less than 0.5 s before t_ns.
  bool KinematicActive(TimeNs t_ns) const;

  Claim Claims(const Measurement& m) const override;
  int Pass(const Measurement& m) const override;
  void Process(const Measurement& m) override;
  void RefineInitialState(const ImuSample& sample, InitialState* init) const override;
  void OnMarginalized(std::span<const NavState> left) override;

 private:
  void ProcessSteering(const SteeringAngle& a);
  void ProcessSpeed(const VehicleSpeed& v);

  const EstimatorSensorSetup& setup_;
  const FactorPlan& plan_;
  const FactorGraphOptions& options_;
  FrontEndContext& ctx_;
  std::optional<KinematicOdometry> kinematic_;
  std::optional<EncoderScaleCalibration> encoder_scale_;
  TimeNs last_kinematic_ns_ = INT64_MIN;  // t2 of the newest kinematic factor
  std::deque<std::pair<TimeNs, double>> recent_speeds_;  // (stamp, m/s) of the last second
};

}  // namespace statebench::est
