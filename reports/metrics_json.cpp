#include "reports/metrics_json.hpp"

namespace statebench::reports {

nlohmann::json ToJson(const ErrorStatistics& s) {
  return {{"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median},
          {"std", s.std},   {"max", s.max},   {"count", s.count}};
}

nlohmann::json ToJson(const StepStatistics& s) {
  return {{"p50", s.p50}, {"p99", s.p99}, {"max", s.max}, {"count", s.count}};
}

nlohmann::json ToJson(const OutputSteps& s) {
  return {{"position_m", ToJson(s.position_m)}, {"yaw_rad", ToJson(s.yaw_rad)}};
}

nlohmann::json ToJson(const TrajectoryMetrics& m) {
  nlohmann::json outages = nlohmann::json::array();
  for (const OutageDrift& d : m.outages) {
    outages.push_back({{"begin_s", ToSeconds(d.window.begin_ns)},
                       {"end_s", ToSeconds(d.window.end_ns)},
                       {"distance_m", d.distance_m},
                       {"error_end_m", d.error_end_m},
                       {"error_end_x_m", d.error_end_world.x()},
                       {"error_end_y_m", d.error_end_world.y()},
                       {"max_error_m", d.max_error_m},
                       {"drift_percent_of_distance", 100.0 * d.drift_per_metre},
                       {"rmse_x_m", d.x.rmse},
                       {"rmse_y_m", d.y.rmse}});
  }
  return {{"compared", m.compared},
          {"skipped", m.skipped},
          {"non_finite", m.non_finite},
          {"distance_m", m.distance_m},
          {"rmse",
           {{"x_m", m.rmse_x_m},
            {"y_m", m.rmse_y_m},
            {"z_m", m.rmse_z_m},
            {"roll_rad", m.rmse_roll_rad},
            {"pitch_rad", m.rmse_pitch_rad},
            {"yaw_rad", m.rmse_yaw_rad},
            {"v_longitudinal_mps", m.rmse_v_longitudinal_mps},
            {"v_lateral_mps", m.rmse_v_lateral_mps},
            {"position_m", m.rmse_position_m},
            {"velocity_mps", m.rmse_velocity_mps}}},
          {"ape", {{"translation_m", ToJson(m.ape_translation_m)},
                   {"rotation_rad", ToJson(m.ape_rotation_rad)}}},
          {"rpe", {{"translation_m", ToJson(m.rpe_translation_m)},
                   {"rotation_rad", ToJson(m.rpe_rotation_rad)}}},
          {"kitti", {{"translation_percent", m.kitti_translation_percent},
                     {"rotation_deg_per_m", m.kitti_rotation_deg_per_m},
                     {"segments", m.kitti_segments}}},
          {"outages", outages},
          {"nees", {{"pose_6dof_mean", m.mean_pose_nees},
                    {"position_3dof_mean", m.mean_position_nees},
                    {"count", m.nees_count}}},
          {"output_step", ToJson(m.output_step)}};
}

}  // namespace statebench::reports
