// The streaming scorer against a direct batch evaluation of the same definitions
// (reports/trajectory_metrics.hpp), and the bounds on what it and the reference track keep.
#include "reports/trajectory_scorer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/so3.hpp"
#include "reports/reference_track.hpp"

namespace statebench::reports {
namespace {

// A wandering drive at 100 Hz with stops (distance does not grow there), and an estimate with a
// slowly varying error and a random covariance.
struct Drive {
  std::vector<ReferenceState> ref;
  std::vector<StateEstimate> est;
};

Drive MakeDrive(double seconds, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  Drive d;
  double yaw = 0.3, speed = 8.0, distance = 0.0;
  Vec3 p = Vec3::Zero(), bias = Vec3::Zero();
  for (int i = 0; i <= static_cast<int>(seconds * 100); ++i) {
    const double t = 0.01 * i;
    const bool stopped = std::fmod(t, 40.0) > 30.0;  // 10 s stops every 40 s
    const double v = stopped ? 0.0 : speed;
    yaw += 0.01 * 0.2 * std::sin(0.1 * t);
    const Quat q = so3::FromRollPitchYaw(0.01 * std::sin(t), 0.0, yaw);
    const Vec3 step = q * Vec3(v * 0.01, 0, 0);
    p += step;
    distance += step.norm();
    ReferenceState r;
    r.t_ns = i * 10 * kNsPerMillisecond;
    r.T_world_frame = SE3(q, p);
    r.v_world = q * Vec3(v, 0, 0);
    r.distance_m = distance;
    d.ref.push_back(r);
    bias = 0.999 * bias + 0.01 * Vec3(n(rng), n(rng), 0.3 * n(rng));
    StateEstimate e;
    e.state.t_ns = r.t_ns;
    e.state.q_world_imu = q * so3::Exp<double>(Vec3(0.001 * n(rng), 0.001 * n(rng), 0.01 * n(rng)));
    e.state.p_world = p + bias + 0.05 * Vec3(n(rng), n(rng), n(rng));
    e.state.v_world = r.v_world + 0.05 * Vec3(n(rng), n(rng), n(rng));
    Mat15 a = Mat15::Random() * 0.1;
    e.covariance = a * a.transpose() + Mat15::Identity() * 0.01;
    d.est.push_back(e);
  }
  return d;
}

SE3 Pose(const StateEstimate& e) { return SE3(e.state.q_world_imu, e.state.p_world); }

double RelativeTranslation(const Drive& d, std::size_t i, std::size_t j) {
  const SE3 e = (d.ref[i].T_world_frame.Inverse() * d.ref[j].T_world_frame).Inverse() *
                (Pose(d.est[i]).Inverse() * Pose(d.est[j]));
  return e.translation().norm();
}

// The first j >= i with distance at least `length` beyond i's, or nullopt.
std::optional<std::size_t> EndOf(const Drive& d, std::size_t i, double length) {
  for (std::size_t j = i; j < d.ref.size(); ++j) {
    if (d.ref[j].distance_m >= d.ref[i].distance_m + length) return j;
  }
  return std::nullopt;
}

// Start indices every `step` metres as the header defines them.
std::vector<std::size_t> Starts(const Drive& d, double step) {
  std::vector<std::size_t> out;
  double next = d.ref.front().distance_m;
  for (std::size_t i = 0; i < d.ref.size(); ++i) {
    if (d.ref[i].distance_m < next) continue;
    out.push_back(i);
    next = d.ref[i].distance_m + step;
  }
  return out;
}

TEST(TrajectoryScorer, MatchesTheDefinitionsEvaluatedOnTheWholeTrajectory) {
  const Drive d = MakeDrive(200.0, 5);
  MetricsOptions options;
  options.outages = {{FromSeconds(50.0), FromSeconds(80.0)}};
  TrajectoryScorer scorer(options);
  for (std::size_t i = 0; i < d.ref.size(); ++i) scorer.Add(d.est[i], d.ref[i]);
  const TrajectoryMetrics m = scorer.Finish();

  const std::size_t n = d.ref.size();
  ASSERT_EQ(m.compared, n);
  double sx = 0, syaw = 0;
  std::vector<double> ape;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 dp = d.est[i].state.p_world - d.ref[i].T_world_frame.translation();
    sx += dp.x() * dp.x();
    const double yaw = so3::WrapAngle(so3::ToRollPitchYaw(d.est[i].state.q_world_imu).z() -
                                      so3::ToRollPitchYaw(d.ref[i].T_world_frame.rotation()).z());
    syaw += yaw * yaw;
    ape.push_back(dp.norm());
  }
  EXPECT_NEAR(m.rmse_x_m, std::sqrt(sx / n), 1e-12);
  EXPECT_NEAR(m.rmse_yaw_rad, std::sqrt(syaw / n), 1e-12);
  std::vector<double> sorted = ape;
  std::sort(sorted.begin(), sorted.end());
  const double median = 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]) * (n % 2 == 0) +
                        sorted[n / 2] * (n % 2 == 1);
  EXPECT_NEAR(m.ape_translation_m.median, median, 5e-4 * median);
  EXPECT_EQ(m.ape_translation_m.max, sorted.back());
  EXPECT_NEAR(m.distance_m, d.ref.back().distance_m - d.ref.front().distance_m, 1e-9);

  // RPE: starts every metre, each with its first end 10 m on.
  std::vector<double> rpe;
  for (const std::size_t i : Starts(d, options.rpe_start_step_m)) {
    if (const auto j = EndOf(d, i, options.rpe_delta_m)) rpe.push_back(RelativeTranslation(d, i, *j));
  }
  ASSERT_EQ(m.rpe_translation_m.count, rpe.size());
  double rpe_sq = 0;
  for (const double e : rpe) rpe_sq += e * e;
  EXPECT_NEAR(m.rpe_translation_m.rmse, std::sqrt(rpe_sq / rpe.size()), 1e-12);

  // KITTI: starts every 10 m, lengths 100..800 m until the first one that does not fit.
  double kitti = 0;
  std::size_t segments = 0;
  for (const std::size_t i : Starts(d, options.kitti_start_step_m)) {
    for (const double length : options.kitti_lengths_m) {
      const auto j = EndOf(d, i, length);
      if (!j) break;
      kitti += RelativeTranslation(d, i, *j) / length;
      ++segments;
    }
  }
  ASSERT_GT(segments, 0u);
  EXPECT_EQ(m.kitti_segments, segments);
  EXPECT_NEAR(m.kitti_translation_percent, 100.0 * kitti / segments, 1e-9);

  // The outage window: the error at its last estimate, its distance.
  ASSERT_EQ(m.outages.size(), 1u);
  const std::size_t first = 5000, last = 8000;
  const Vec3 end_error = d.est[last].state.p_world - d.ref[last].T_world_frame.translation();
  EXPECT_NEAR(m.outages[0].error_end_m, end_error.norm(), 1e-12);
  EXPECT_NEAR(m.outages[0].distance_m, d.ref[last].distance_m - d.ref[first].distance_m, 1e-9);
  EXPECT_EQ(m.outages[0].x.count, last - first + 1);
}

TEST(TrajectoryScorer, NonFiniteEstimatesAreCountedNotCompared) {
  Drive d = MakeDrive(5.0, 9);
  d.est[10].state.p_world.x() = std::nan("");
  d.est[20].state.v_world.y() = INFINITY;
  TrajectoryScorer scorer;
  for (std::size_t i = 0; i < d.ref.size(); ++i) scorer.Add(d.est[i], d.ref[i]);
  const TrajectoryMetrics m = scorer.Finish();
  EXPECT_EQ(m.non_finite, 2u);
  EXPECT_EQ(m.compared, d.ref.size() - 2);
  EXPECT_TRUE(std::isfinite(m.rmse_x_m));
  EXPECT_TRUE(std::isfinite(m.rmse_velocity_mps));
}

// Truth at 1 kHz along a circle of 50 m at 10 m/s, samples 0..last_ms.
std::vector<TruthSample> CircleTruthAt1kHz(int last_ms) {
  std::vector<TruthSample> truth;
  for (int i = 0; i <= last_ms; ++i) {
    TruthSample s;
    s.t_ns = i * kNsPerMillisecond;
    const double a = 0.2 * ToSeconds(s.t_ns);
    s.body.T_world_frame = SE3(so3::FromRollPitchYaw(0, 0, a + M_PI / 2),
                              Vec3(50 * std::cos(a), 50 * std::sin(a), 0));
    s.body.v_world = Vec3(-10 * std::sin(a), 10 * std::cos(a), 0);
    truth.push_back(s);
  }
  return truth;
}

TEST(ReferenceTrack, InterpolatesLikeTheWholeReferenceAndKeepsOnlyWhatIsAhead) {
  // Estimates at 100 Hz shifted by 3.7 ms between truth samples.
  const std::vector<TruthSample> truth = CircleTruthAt1kHz(20000);
  const SE3 T_body_imu(Quat::Identity(), Vec3(0.5, 0.1, 0.3));
  const std::vector<ReferenceState> all = ReferenceFromTruth(truth, T_body_imu);
  ReferenceTrack track(T_body_imu);
  std::size_t next = 0, most_held = 0;
  for (int k = 0; k < 1990; ++k) {
    const TimeNs t = k * 10 * kNsPerMillisecond + 3'700'000;
    while (next < truth.size() && (track.empty() || track.newest_ns() < t)) {
      track.Add(truth[next++]);
    }
    const auto a = track.At(t);
    const auto b = InterpolateReference(all, t);
    ASSERT_TRUE(a && b);
    EXPECT_NEAR((a->T_world_frame.translation() - b->T_world_frame.translation()).norm(), 0.0,
                1e-12);
    EXPECT_NEAR(a->distance_m, b->distance_m, 1e-12);
    track.DropBefore(t);
    EXPECT_FALSE(track.At(t - 2 * kNsPerMillisecond).has_value());  // dropped
    most_held = std::max(most_held, static_cast<std::size_t>(
                                        (track.newest_ns() - track.oldest_ns()) / kNsPerMillisecond));
  }
  EXPECT_LE(most_held, 2u);  // a sample before t and one after
}

TEST(ReferenceTrack, KeepsWhatItHoldsWhileDroppedStatesAreReclaimed) {
  // Truth runs ahead of the queries by a varying amount (0 to 3 s), so the track both holds
  // thousands of states and is reclaimed many times; every query matches the whole reference.
  const std::vector<TruthSample> truth = CircleTruthAt1kHz(30000);
  const SE3 T_body_imu(Quat::Identity(), Vec3(-0.2, 0.0, 0.9));
  const std::vector<ReferenceState> all = ReferenceFromTruth(truth, T_body_imu);
  ReferenceTrack track(T_body_imu);
  std::size_t next = 0;
  for (int k = 0; k < 2500; ++k) {
    const TimeNs t = k * 10 * kNsPerMillisecond + 1'300'000;
    const TimeNs ahead = ((k / 100) % 4) * kNsPerSecond;  // 0, 1, 2, 3 s of truth ahead
    while (next < truth.size() && (track.empty() || track.newest_ns() < t + ahead)) {
      track.Add(truth[next++]);
    }
    ASSERT_FALSE(track.empty());
    EXPECT_EQ(track.size(),
              static_cast<std::size_t>((track.newest_ns() - track.oldest_ns()) / kNsPerMillisecond) + 1);
    for (const TimeNs q : {t, t + ahead / 2, track.newest_ns()}) {
      const auto a = track.At(q);
      const auto b = InterpolateReference(all, q);
      ASSERT_TRUE(a && b) << "t " << q;
      EXPECT_EQ(a->t_ns, b->t_ns);
      EXPECT_NEAR((a->T_world_frame.translation() - b->T_world_frame.translation()).norm(), 0.0,
                  1e-12);
      EXPECT_NEAR(a->distance_m, b->distance_m, 1e-12);
    }
    track.DropBefore(t);
    EXPECT_LE(track.oldest_ns(), t);
    EXPECT_GT(track.oldest_ns(), t - kNsPerMillisecond);
  }
}

}  // namespace
}  // namespace statebench::reports
