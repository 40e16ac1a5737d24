// The errors of one estimate against the reference at its stamp, as every metric and the run
// report define them (trajectory_metrics.hpp), and the estimate's own standard deviations of the
// same quantities, for plotting error bands.
#pragma once

#include <optional>

#include "core/state.hpp"
#include "reports/trajectory_metrics.hpp"

namespace statebench::reports {

struct PoseErrors {
  Vec3 dp_world = Vec3::Zero();    // p_est - p_ref, ENU, m
  Vec3 drpy = Vec3::Zero();        // roll, pitch, yaw of est minus ref, each wrapped, rad
  Vec3 dtheta = Vec3::Zero();      // Log(R_est^T R_ref): the right-perturbation rotation error
  Vec3 dv_own_frame = Vec3::Zero();  // R_est^T v_est - R_ref^T v_ref: longitudinal, lateral, up
  Vec3 dv_world = Vec3::Zero();    // v_est - v_ref, ENU
};

PoseErrors ErrorsOf(const NavState& estimate, const ReferenceState& reference);

// One scored epoch of one estimator for the run report (errors.csv, docs/estimate-format.md).
struct EpochErrors {
  TimeNs t_ns = 0;
  EstimateStatus status = EstimateStatus::kGlobal;
  PoseErrors errors;
  double along_m = 0.0, across_m = 0.0;  // horizontal error along / across the reference heading
  Vec3 sigma_world = Vec3::Zero();       // position standard deviation per ENU axis
  double sigma_along_m = 0.0, sigma_across_m = 0.0;
  double sigma_yaw_rad = 0.0;
  double sigma_v_longitudinal_mps = 0.0;
  double sigma_roll_rad = 0.0, sigma_pitch_rad = 0.0;  // of the estimate's roll and pitch angles
  std::optional<double> nees_pose, nees_position;
};

// pose_covariance: [rotation, position] block; velocity_covariance: the velocity block.
EpochErrors EpochErrorsOf(const NavState& estimate, EstimateStatus status,
                          const Mat6& pose_covariance, const Mat3& velocity_covariance,
                          const ReferenceState& reference);

// NEES of the pose error (dtheta, -dp) against the [rotation, position] covariance, and of the
// position alone; nullopt when the covariance is not usable.
std::optional<std::pair<double, double>> PoseNees(const PoseErrors& e, const Mat6& pose_covariance);

}  // namespace statebench::reports
