// GNSS front end: antenna fixes and dual-antenna headings. Fixes are converted to the local ENU
// frame (the first usable fix sets its origin unless the options give one), discarded above the
// covariance threshold, paired into headings where the setup says so (GroupStamp), gated on
// their Mahalanobis distance to the prediction (with a reset after gate_reset_s of rejections),
// and become position and heading factors; before the first state they feed the initialiser.
// With gnss.adapt_covariance a fix's reported covariance is first multiplied by its antenna's
// innovation scale (innovation_scale.hpp: the median of the fixes' Mahalanobis distances, gated
// ones included, against chi-square(3)'s; counted as the event covariance_scale_changed, the
// scale in the sensor's diagnostics).
// A fix's Doppler velocity (when the receiver gives one) becomes a world-frame velocity factor
// of its antenna (body_velocity_factor.hpp, Frame::kWorld), discarded above gnss_velocity's
// max_sigma and gated on its own Mahalanobis distance (raw gyro of the stamp for the lever arm);
// counted as the antenna's events velocity_factors / velocity_gated / velocity_too_noisy.
// With gnss.estimate_time_offset each antenna's fixes carry its time offset, a state of the
// smoother (gnss_time_offset_factor.hpp), created on its first fix after initialisation (again
// after a restart, from 0); the gate predicts the antenna at the stamp minus the offset estimate;
// the estimate and its sigma go to the antenna's diagnostics (globals: time_offset_s) after
// each solve.
// With gnss_calibration.estimate_heading_baseline each heading pair's baseline direction (yaw,
// pitch) is a pair of globals (DualAntennaFactor::CreateWithBaselineCorrection) and its headings
// keep their reported sigmas; the gate turns the baseline by the current estimates.
// Accepted measurements are kept until they leave the window to count those the robust kernel
// down-weighted at the final estimate.
// While the estimate is in a local frame (a start before the GNSS could give the yaw:
// LocalStart::enu_later), each fix instead pairs the antenna's local position at its stamp with
// the fix (enu_alignment.hpp; accepted, event `enu_alignment`); once their alignment gives the
// yaw to initialization.course_yaw_sigma_rad over fixes spread over course_min_distance_m (twice
// their largest distance from their centroid; what a GNSS course start takes), the front end asks
// the orchestrator to move the estimate into ENU (FrontEndContext::enu_switch). Headings and
// Doppler velocities wait for ENU (headings rejected as not_initialized).
#pragma once

#include <array>
#include <deque>
#include <map>
#include <optional>
#include <string>

#include "core/geodetic.hpp"
#include "estimator/doppler_window.hpp"
#include "estimator/estimator_config.hpp"
#include "estimator/front_end.hpp"
#include "estimator/gnss_stamp_group.hpp"
#include "estimator/innovation_scale.hpp"
#include "estimator/refused_fix_track.hpp"

namespace statebench::est {

class GnssFrontEnd final : public MeasurementFrontEnd {
 public:
  // `setup` must outlive the front end.
  GnssFrontEnd(const EstimatorSensorSetup& setup, const FactorGraphOptions& options,
               FrontEndContext& ctx);

  // The local ENU frame; nullopt until the options or the first fix give its origin.
  const std::optional<LocalEnuFrame>& frame() const { return frame_; }
  // A heading with a pitch (and its sigma) has been accepted: the baseline measures pitch.
  bool heading_pitch_seen() const { return heading_pitch_seen_; }
  // The receiver's Doppler velocities, gated or not (doppler_window.hpp): the standstill test's
  // speed reading, independent of the estimate.
  const DopplerWindow& doppler() const { return doppler_; }

  Claim Claims(const Measurement& m) const override;
  void Process(const Measurement& m) override;
  void EndOfStamp() override;
  void OnImu(const ImuSample& sample) override;
  // A start made of the fixes of a receiver whose slow error the smoother estimates (the setup's
  // only antenna): `position_slow_error` (gnss_front_end_start.cpp).
  void RefineInitialState(const ImuSample& sample, InitialState* init) const override;
  // The gates start at the start's stamp; a start with a slow error becomes a fix on the first
  // state's position plus the receiver's error states (created here).
  void OnInitialized(const InitialState& init) override;
  void OnRestart() override;
  void OnMarginalized(std::span<const NavState> left) override;
  TimeNs OldestStampNeeded() const override;

 private:
  // Last time a measurement of a kind passed the gate, for the gate's reset.
  struct GateState {
    TimeNs last_accepted_ns = INT64_MIN;
    bool rejected_since = false;
  };
  // A measurement in the smoother, kept until it leaves the window.
  struct Accepted {
    TimeNs stamp_ns = 0;
    std::string sensor_id;
    bool is_heading = false;
    GnssPositionEnu fix;
    Vec3 p_imu_antenna = Vec3::Zero();
    DualAntennaHeading heading;
    Vec3 baseline_imu = Vec3::Zero();
  };

  std::optional<GnssPositionEnu> ToEnu(const GnssFix& fix);
  bool PassesGate(const MeasurementGateOptions& gate, GateState& state, TimeNs t_ns,
                  double mahalanobis_squared);
  void AddPosition(const PositionInput& in);
  // In a local frame (FrontEndContext::local_frame): the fix aligns the local track with ENU.
  void AlignLocalFrame(const GnssPositionEnu& fix, const Vec3& p_imu_antenna);
  void AddVelocity(const PositionInput& in);
  // The smoother's time offset of the antenna (a global created on its first fix, reported as
  // the antenna's "time_offset_s") when gnss.estimate_time_offset; nullopt otherwise.
  static constexpr const char* kTimeOffsetGlobal = "time_offset_s";
  std::optional<int> TimeOffsetOf(const std::string& antenna_id);
  // The antenna's current offset estimate (0 when not estimated).
  double TimeOffsetEstimate(const std::string& antenna_id) const;
  // The smoother's error states of the antenna (globals created on its first fix, reported as
  // the antenna's "error_east_m", "error_north_m", "error_up_m") when
  // gnss.estimate_correlated_error is true, or auto and the antenna's setup describes its slow
  // error (with the setup's sigmas and tau where it does); nullopt otherwise.
  static constexpr const char* kErrorGlobals[3] = {"error_east_m", "error_north_m", "error_up_m"};
  std::optional<std::array<int, 3>> ErrorStateOf(const std::string& antenna_id);
  // The antenna's slow error as the smoother models it: stationary sigmas (east, north, up) and
  // correlation time, the setup's figures where it describes them, else the options'.
  struct SlowError {
    Vec3 sigma = Vec3::Zero();
    double tau_s = 0.0;
  };
  SlowError SlowErrorOf(const GnssAntenna& antenna) const;
  // The antenna whose slow error a GNSS start shares (the setup's only antenna, when its error
  // is estimated), else null.
  const GnssAntenna* StartErrorAntenna() const;
  // With a start's position_slow_error: the start's position and covariance as a fix on the
  // first state's IMU position plus the antenna's error states.
  void AddStartAsFix(const InitialState& init);
  // The fix as the gate sees it: less the antenna's current error estimate, its covariance
  // plus the estimate's (unchanged when the error is not estimated).
  GnssPositionEnu LessErrorEstimate(const GnssPositionEnu& fix) const;
  // The smoother's baseline corrections (yaw, pitch) of the heading pair (globals created on
  // its first heading, reported as the pair's "baseline_yaw_rad", "baseline_pitch_rad") when
  // gnss_calibration.estimate_heading_baseline and the mount sigmas give them a prior; their
  // prior variances are what HeadingCalibration would widen each heading by.
  static constexpr const char* kBaselineGlobals[2] = {"baseline_yaw_rad", "baseline_pitch_rad"};
  std::optional<std::array<int, 2>> BaselineOf(const std::string& heading_id,
                                               const Vec3& baseline_imu);
  // The raw gyro of the released sample nearest t_ns (zero before any).
  Vec3 RecentGyro(TimeNs t_ns) const;
  void AddHeading(const HeadingInput& in);

  const EstimatorSensorSetup& setup_;
  const FactorGraphOptions& options_;
  FrontEndContext& ctx_;
  std::optional<LocalEnuFrame> frame_;
  // The fixes and headings of the stamp being handed over.
  std::map<std::string, GnssPositionEnu> fixes_;        // by antenna id
  std::map<std::string, DualAntennaHeading> headings_;  // by heading id
  TimeNs stamp_ns_ = 0;
  GateState gnss_gate_, heading_gate_, velocity_gate_;
  DopplerWindow doppler_;
  std::deque<ImuSample> recent_imu_;  // the last kRecentImuNs of released samples
  std::deque<Accepted> accepted_;     // in the smoother, oldest first
  // Fixes the gate refused since the last accepted one: when they agree, the estimate is lost.
  RefusedFixTrack refused_;
  EnuAlignment alignment_;  // while the estimate is in a local frame
  std::map<std::string, InnovationScale> covariance_scales_;  // by antenna (gnss.adapt_covariance)
  bool heading_pitch_seen_ = false;
};

}  // namespace statebench::est
