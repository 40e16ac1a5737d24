// Issue 14, second half of the differential-drive acceptance point: the robot of
// local_frame_start_test.cpp (IMU + wheel odometry, robot_drive.hpp, robot_gnss.hpp) with an
// SBAS-grade GNSS receiver added: white noise of 1 m horizontal / 2 m vertical sigma at 2.5 Hz,
// its reported covariance under-reported by 2x (sigmas 0.5 m / 1 m). Default options. The factor
// graph's output must be continuous (an estimate at every IMU stamp from its first one, no jump
// beyond the frame change itself), its horizontal RMS error in ENU under 1 m, and its gate must
// reject fewer than 10 % of the fixes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/geodetic.hpp"
#include "core/yaml_node.hpp"
#include "estimator/factor_graph_estimator.hpp"
#include "estimator_scenario.hpp"
#include "robot_gnss.hpp"

namespace statebench::est {
namespace {

using testing::DifferentialDriveTrajectory;

struct RobotGnssRun {
  EstimatorDiagnostics diagnostics;
  std::optional<TimeNs> first_ns;   // the first estimate's stamp
  std::optional<TimeNs> global_ns;  // the first estimate in ENU (status not `local`)
  int imu_after_first = 0;          // IMU stamps from the first estimate on
  int estimates = 0;
  int gaps = 0;  // IMU stamps after the first estimate without one
  std::map<std::string, int> statuses;
  double rms_m = 0.0;  // horizontal, ENU, over the estimates in ENU
  double max_m = 0.0;
  double end_m = 0.0;
  int enu_estimates = 0;
  std::vector<double> steps_m;  // |estimated step - true step| between consecutive estimates
  double p99_step_m = 0.0, max_step_m = 0.0;
  double max_step_at_s = 0.0;
  std::uint64_t fixes = 0, gated = 0, rejected = 0;
  // The step across the switch into ENU: the last local estimate moved by the switch's
  // transform (diagnostics enu_switches) against the first ENU estimate, minus the true step.
  std::optional<double> switch_step_m;
};

RobotGnssRun RunRobotWithGnss(const DifferentialDriveTrajectory& traj,
                              const std::vector<Measurement>& stream) {
  const EstimatorSensorSetup setup = testing::RobotGnssSetup();
  FactorGraphEstimator estimator(setup, FactorGraphOptions{});
  const LocalEnuFrame frame(testing::kRobotOrigin);
  RobotGnssRun run;
  std::optional<Vec3> previous_p, previous_truth;
  bool previous_enu = false;
  std::optional<Vec3> last_local_p, last_local_truth;  // the last local estimate before ENU
  Vec3 first_enu_p = Vec3::Zero(), first_enu_truth = Vec3::Zero();
  double sum_squares = 0.0;
  testing::FeedOutputs(estimator, stream, [&](TimeNs t, const std::optional<StateEstimate>& e) {
    if (run.first_ns) ++run.imu_after_first;
    if (!e) {
      if (run.first_ns) ++run.gaps;
      previous_p.reset();
      return;
    }
    if (!run.first_ns) {
      run.first_ns = t;
      run.imu_after_first = 1;
    }
    ++run.estimates;
    ++run.statuses[EstimateStatusName(e->status)];
    const bool enu = e->status != EstimateStatus::kLocal;
    const Vec3 truth = testing::RobotTruth(traj, t).p_world;
    const Vec3& p = e->state.p_world;  // in the estimator's frame (steps do not see its origin)
    if (!enu) {
      last_local_p = p;
      last_local_truth = truth;
    } else if (!run.global_ns) {
      first_enu_p = p;
      first_enu_truth = truth;
    }
    // A step across the frame change is the change of frame, not a jump of the estimate.
    if (previous_p && enu == previous_enu) {
      const double step = ((p - *previous_p) - (truth - *previous_truth)).norm();
      run.steps_m.push_back(step);
      if (step > run.max_step_m) {
        run.max_step_m = step;
        run.max_step_at_s = ToSeconds(t);
      }
    }
    previous_p = p;
    previous_truth = truth;
    previous_enu = enu;
    if (!enu) return;
    if (!run.global_ns) run.global_ns = t;
    const Vec3 p_enu = frame.ToEnu({e->latitude_deg, e->longitude_deg, e->altitude_m});
    const double error = (p_enu - truth).head<2>().norm();
    sum_squares += error * error;
    ++run.enu_estimates;
    run.max_m = std::max(run.max_m, error);
    run.end_m = error;
  });
  run.rms_m = run.enu_estimates > 0 ? std::sqrt(sum_squares / run.enu_estimates) : 0.0;
  if (!run.steps_m.empty()) {
    std::vector<double> sorted = run.steps_m;
    std::sort(sorted.begin(), sorted.end());
    run.p99_step_m = sorted[static_cast<std::size_t>(0.99 * (sorted.size() - 1))];
  }
  run.diagnostics = estimator.diagnostics();
  if (last_local_p && run.global_ns && !run.diagnostics.enu_switches.empty()) {
    const EnuSwitch& s = run.diagnostics.enu_switches.front();
    const Vec3 moved = Eigen::AngleAxisd(s.yaw_rad, Vec3::UnitZ()) * *last_local_p +
                       Vec3(s.translation_m[0], s.translation_m[1], s.translation_m[2]);
    run.switch_step_m = ((first_enu_p - moved) - (first_enu_truth - *last_local_truth)).norm();
  }
  const auto it = run.diagnostics.sensors.find("gnss");
  if (it != run.diagnostics.sensors.end()) {
    const SensorCounters& c = it->second;
    run.fixes = c.received;
    run.rejected = c.TotalRejected();
    const auto gated = c.rejected.find(RejectReason::kMahalanobisGate);
    run.gated = gated != c.rejected.end() ? gated->second : 0;
  }
  return run;
}

void PrintRobotGnssRun(std::uint64_t seed, const RobotGnssRun& run) {
  std::string statuses;
  for (const auto& [name, count] : run.statuses) {
    statuses += " " + name + " " + std::to_string(count);
  }
  if (!run.diagnostics.enu_switches.empty()) {
    const EnuSwitch& s = run.diagnostics.enu_switches.front();
    const SensorCounters& gnss = run.diagnostics.sensors.at("gnss");
    std::printf(
        "seed %llu: into ENU at %.2f s from %d fixes over %.1f m, yaw sigma %.4f rad, "
        "sigma %.3f m (residuals %.3f m); GNSS covariance scale %.2f\n",
        static_cast<unsigned long long>(seed), ToSeconds(s.at_ns), s.fixes, s.span_m,
        s.yaw_sigma_rad, s.sigma_h_m, s.residual_sigma_h_m, gnss.covariance_scale.value_or(1.0));
  }
  std::printf(
      "seed %llu: first estimate %.2f s (%s), in ENU from %.2f s; %d estimates of %d IMU stamps "
      "(%d gaps;%s); horizontal error in ENU RMS %.3f m, max %.3f m, end %.3f m; output step "
      "p99 %.4f m, max %.4f m at %.2f s, across the switch %.4f m; fixes %llu, gated %llu "
      "(%.1f %%), rejected %llu\n",
      static_cast<unsigned long long>(seed), run.first_ns ? ToSeconds(*run.first_ns) : -1.0,
      run.diagnostics.initialization.c_str(), run.global_ns ? ToSeconds(*run.global_ns) : -1.0,
      run.estimates, run.imu_after_first, run.gaps, statuses.c_str(), run.rms_m, run.max_m,
      run.end_m, run.p99_step_m, run.max_step_m, run.max_step_at_s,
      run.switch_step_m.value_or(-1.0), static_cast<unsigned long long>(run.fixes),
      static_cast<unsigned long long>(run.gated),
      run.fixes > 0 ? 100.0 * run.gated / run.fixes : 0.0,
      static_cast<unsigned long long>(run.rejected));
}

// The acceptance point's checks on one run: started within 2 s in the local frame, moved into
// ENU once (the output's step across it under 1 cm beyond the change of frame), an estimate at
// every IMU stamp from the first one, RMS under 1 m, fewer than 10 % of the fixes gated out.
void ExpectAcceptance(const RobotGnssRun& run) {
  ASSERT_TRUE(run.first_ns.has_value()) << run.diagnostics.waiting_for;
  EXPECT_LT(ToSeconds(*run.first_ns), 2.0);
  EXPECT_EQ(run.diagnostics.initialization, "static (local frame)");
  ASSERT_EQ(run.diagnostics.enu_switches.size(), 1u);
  EXPECT_FALSE(run.diagnostics.local_frame);
  ASSERT_TRUE(run.switch_step_m.has_value());
  EXPECT_LT(*run.switch_step_m, 0.01);
  EXPECT_GT(run.statuses.at("local"), 0);
  EXPECT_EQ(run.gaps, 0);
  EXPECT_EQ(run.estimates, run.imu_after_first);
  EXPECT_LT(run.rms_m, 1.0);
  EXPECT_LT(static_cast<double>(run.gated), 0.1 * static_cast<double>(run.fixes));
}

TEST(LocalFrameGnss, DifferentialDriveWithSbasGnssIsContinuousAndUnderOneMetre) {
  const DifferentialDriveTrajectory traj = testing::RobotDrive(2.0);
  for (std::uint64_t seed : {11u, 12u, 13u, 14u, 15u}) {
    testing::RobotStreamOptions o;
    o.seed = seed;
    const RobotGnssRun run =
        RunRobotWithGnss(traj, testing::RobotStreamWithGnss(traj, o, testing::RobotGnssOptions{}));
    PrintRobotGnssRun(seed, run);
    ExpectAcceptance(run);
  }
}

TEST(LocalFrameGnss, SameWithASlowCorrelatedGnssErrorAsSbasHas) {
  // On top of the white noise, a first-order Gauss-Markov error of 0.5 m horizontal / 1 m
  // vertical per axis with a 100 s time constant (shared/REFERENCE.md), not in the reported
  // covariance either. The estimate follows the fixes' slow error: it is part of the RMS.
  const DifferentialDriveTrajectory traj = testing::RobotDrive(2.0);
  for (std::uint64_t seed : {11u, 12u, 13u}) {
    testing::RobotStreamOptions o;
    o.seed = seed;
    testing::RobotGnssOptions g;
    g.correlated_sigma_h_m = 0.5;
    g.correlated_sigma_v_m = 1.0;
    const RobotGnssRun run = RunRobotWithGnss(traj, testing::RobotStreamWithGnss(traj, o, g));
    PrintRobotGnssRun(seed, run);
    ExpectAcceptance(run);
  }
}

// The smoothed output (lagged_output) of the same run: its states before the switch into ENU are
// in the local frame and say so (status `local`), as the real-time ones did; after the switch they
// are in ENU, within a metre of the truth like the real-time ones.
TEST(LocalFrameGnss, TheLaggedOutputKeepsTheLocalStatesLocal) {
  const DifferentialDriveTrajectory traj = testing::RobotDrive(2.0);
  testing::RobotStreamOptions o;
  o.seed = 11;
  const std::vector<Measurement> stream =
      testing::RobotStreamWithGnss(traj, o, testing::RobotGnssOptions{});
  const EstimatorSensorSetup setup = testing::RobotGnssSetup();
  std::map<TimeNs, EstimateStatus> real_time;
  FactorGraphEstimator online(setup, FactorGraphOptions{});
  testing::FeedOutputs(online, stream, [&](TimeNs t, const std::optional<StateEstimate>& e) {
    if (e) real_time[t] = e->status;
  });
  FactorGraphOptions lagged_options;
  lagged_options.lagged_output = true;
  FactorGraphEstimator lagged(setup, lagged_options);
  testing::FeedOutputs(lagged, stream, [](TimeNs, const std::optional<StateEstimate>&) {});
  lagged.EndOfLog();
  ASSERT_EQ(lagged.diagnostics().enu_switches.size(), 1u);
  const TimeNs switch_ns = lagged.diagnostics().enu_switches.front().at_ns;
  const LocalEnuFrame frame(testing::kRobotOrigin);
  int local = 0, enu = 0;
  double max_error_m = 0.0;
  for (const auto& [t, status] : real_time) {
    const std::optional<StateEstimate> e = lagged.StateAt(t);
    if (!e) continue;
    // The smoother switched at the newest sample released to it; the real-time output was then
    // ahead by the reorder latency, and those few stamps were shown local: the lagged output has
    // them in ENU. Before the switch and after that latency both agree.
    const bool near_switch = t >= switch_ns && t < switch_ns + FromSeconds(0.5);
    if (!near_switch) {
      EXPECT_EQ(e->status == EstimateStatus::kLocal, status == EstimateStatus::kLocal)
          << ToSeconds(t);
    }
    if (t < switch_ns) EXPECT_EQ(e->status, EstimateStatus::kLocal) << ToSeconds(t);
    if (e->status == EstimateStatus::kLocal) {
      ++local;
      continue;
    }
    ++enu;
    const Vec3 p_enu = frame.ToEnu({e->latitude_deg, e->longitude_deg, e->altitude_m});
    max_error_m =
        std::max(max_error_m, (p_enu - testing::RobotTruth(traj, t).p_world).head<2>().norm());
  }
  std::printf("lagged output: %d local, %d ENU estimates, ENU horizontal error up to %.2f m\n",
              local, enu, max_error_m);
  EXPECT_GT(local, 0);
  EXPECT_GT(enu, 1000);
  EXPECT_LT(max_error_m, 3.0);
}

}  // namespace
}  // namespace statebench::est
