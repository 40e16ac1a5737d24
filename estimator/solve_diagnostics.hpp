// One solve of the sliding-window smoother as a line of the estimator's diagnostics.
#pragma once

#include "estimator/estimator_diagnostics.hpp"
#include "estimator/sliding_window_smoother.hpp"

namespace statebench::est {

inline UpdateDiagnostics SolveDiagnostics(const SmootherSolveSummary& summary, TimeNs t_ns,
                                          double solve_time_s) {
  UpdateDiagnostics u;
  u.t_ns = t_ns;
  u.solve_time_s = solve_time_s;
  u.iterations = summary.iterations;
  u.usable = summary.usable;
  u.num_states = summary.num_states;
  u.num_marginalized = summary.num_marginalized;
  u.marginalization_deferred = summary.marginalization_deferred;
  u.num_marginalized_unusable = summary.num_marginalized_unusable;
  u.num_left_out_of_prior = summary.num_left_out_of_prior;
  u.factors = {{"prior", 1},
               {"imu", summary.num_imu_factors},
               {"bias", summary.num_imu_factors},
               {"gnss", summary.num_gnss_factors},
               {"heading", summary.num_heading_factors},
               {"relative_pose", summary.num_relative_pose_factors},
               {"velocity", summary.num_velocity_factors}};
  return u;
}

}  // namespace statebench::est
