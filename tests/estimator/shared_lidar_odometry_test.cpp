// The shared lidar odometry (lidar.motion_prior: constant_velocity): factor graphs built with one
// pool register each scan once between them and give, bit for bit, the estimates each gives
// alone; the pool keys on everything a registration depends on; a scan asked for out of
// sequence is refused with its reason, not registered twice.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "core/error.hpp"
#include "core/so3.hpp"
#include "estimator/factor_graph_estimator.hpp"
#include "estimator/shared_lidar_odometry.hpp"
#include "lidar_test_stream.hpp"

namespace statebench::est {
namespace {

using testing::kLidarEntry;
using testing::MakeScenario;
using testing::MakeSetup;
using testing::Scenario;
using testing::ScenarioOptions;
using testing::WithScans;

FactorGraphOptions SharedPriorOptions(double window_s, LidarPriorSource prior) {
  FactorGraphOptions o;
  o.origin = testing::kTestOrigin;
  o.window_s = window_s;
  o.lidar.motion_prior = prior;
  return o;
}

struct Outputs {
  std::vector<StateEstimate> estimates;
  EstimatorDiagnostics diagnostics;
};

// Feeds the stream to every estimator in step (as `statebench run` does) and keeps each one's
// estimates at the IMU samples.
std::vector<Outputs> FeedInStep(std::vector<std::unique_ptr<FactorGraphEstimator>>& estimators,
                                const std::vector<Measurement>& stream) {
  std::vector<Outputs> out(estimators.size());
  for (const Measurement& m : stream) {
    for (std::size_t k = 0; k < estimators.size(); ++k) {
      estimators[k]->Add(m);
      if (!std::holds_alternative<ImuSample>(m)) continue;
      if (auto e = estimators[k]->StateAt(HeaderOf(m).stamp_ns)) {
        out[k].estimates.push_back(*e);
      }
    }
  }
  for (std::size_t k = 0; k < estimators.size(); ++k) {
    out[k].diagnostics = estimators[k]->diagnostics();
  }
  return out;
}

void ExpectBitIdentical(const std::vector<StateEstimate>& a, const std::vector<StateEstimate>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].state.t_ns, b[i].state.t_ns);
    ASSERT_EQ(a[i].state.p_world, b[i].state.p_world) << "at epoch " << i;
    ASSERT_EQ(a[i].state.v_world, b[i].state.v_world) << "at epoch " << i;
    ASSERT_EQ(a[i].state.q_world_imu.coeffs(), b[i].state.q_world_imu.coeffs()) << "epoch " << i;
    ASSERT_EQ(a[i].covariance, b[i].covariance) << "at epoch " << i;
  }
}

class SharedLidarOdometryPrior : public ::testing::TestWithParam<LidarPriorSource> {};

TEST_P(SharedLidarOdometryPrior, EstimatorsSharingAPoolGiveWhatEachGivesAlone) {
  const LidarPriorSource prior = GetParam();
  ScenarioOptions so;
  so.duration_s = 12.0;
  const Scenario sc = MakeScenario(so);
  const std::vector<Measurement> stream = WithScans(sc, 0.5, 12.0);
  const EstimatorSensorSetup setup = MakeSetup(sc.options, kLidarEntry);

  LidarOdometryPool pool;
  std::vector<std::unique_ptr<FactorGraphEstimator>> shared;
  for (double window_s : {0.5, 1.0, 2.0}) {
    shared.push_back(
        std::make_unique<FactorGraphEstimator>(setup, SharedPriorOptions(window_s, prior), &pool));
  }
  const std::vector<Outputs> together = FeedInStep(shared, stream);
  EXPECT_EQ(pool.size(), 1u);  // one lidar, one set of odometry options
  // Each scan registered once, handed to the two others.
  const auto counts = pool.Counts();
  ASSERT_EQ(counts.size(), 1u);
  EXPECT_GE(counts[0].first, 100u);
  EXPECT_EQ(counts[0].second, 2 * counts[0].first);

  for (std::size_t k = 0; k < shared.size(); ++k) {
    std::vector<std::unique_ptr<FactorGraphEstimator>> one;
    one.push_back(std::make_unique<FactorGraphEstimator>(
        setup, SharedPriorOptions(std::vector<double>{0.5, 1.0, 2.0}[k], prior)));
    const std::vector<Outputs> alone = FeedInStep(one, stream);
    ExpectBitIdentical(together[k].estimates, alone[0].estimates);
    const SensorCounters& a = together[k].diagnostics.sensors.at("lidar_roof");
    const SensorCounters& b = alone[0].diagnostics.sensors.at("lidar_roof");
    EXPECT_EQ(a.accepted, b.accepted);
    EXPECT_EQ(a.events, b.events);
  }
  // The lidar factors were used, and the estimate follows the truth (noise-free inputs).
  const SensorCounters& lidar = together[1].diagnostics.sensors.at("lidar_roof");
  EXPECT_GE(lidar.events.at("registered"), 75u);  // of 115 scans; the rest before the first state
  EXPECT_GE(lidar.events.at("registered_before_initialization"), 1u);
  double max_error = 0.0;
  for (const StateEstimate& e : together[1].estimates) {
    max_error = std::max(max_error, (e.state.p_world - sc.Truth(e.state.t_ns).p_world).norm());
  }
  std::printf("%s: max position error %.3f m, %llu scans registered\n",
              LidarPriorSourceName(prior), max_error,
              static_cast<unsigned long long>(lidar.events.at("registered")));
  EXPECT_LT(max_error, 0.05);
}

INSTANTIATE_TEST_SUITE_P(Priors, SharedLidarOdometryPrior,
                         ::testing::Values(LidarPriorSource::kConstantVelocity,
                                           LidarPriorSource::kGyro));

TEST(SharedLidarOdometry, EachScanIsRegisteredOnceAndOutOfSequenceScansAreRefused) {
  ScenarioOptions so;
  so.duration_s = 4.0;
  const Scenario sc = MakeScenario(so);
  std::vector<LidarScan> scans;
  for (const Measurement& m : WithScans(sc, 0.5, 3.0)) {
    if (const auto* s = std::get_if<LidarScan>(&m)) scans.push_back(*s);
  }
  ASSERT_EQ(scans.size(), 25u);
  SharedLidarOdometry shared(LidarOdometryOptions{});
  LidarOdometry own(LidarOdometryOptions{});
  for (const LidarScan& scan : scans) {
    bool computed = false;
    const TimeNs end = scan.header.stamp_ns + FromSeconds(0.1);
    const LidarOdometryResult first = shared.Register(scan, end, nullptr, &computed);
    EXPECT_TRUE(computed);
    const LidarOdometryResult again = shared.Register(scan, end, nullptr, &computed);
    EXPECT_FALSE(computed);
    const LidarOdometryResult reference = own.RegisterScan(scan);
    for (const LidarOdometryResult* r : {&first, &again}) {
      EXPECT_EQ(r->accepted, reference.accepted);
      EXPECT_EQ(r->prev_stamp_ns, reference.prev_stamp_ns);
      EXPECT_EQ(r->T_prev_curr.translation(), reference.T_prev_curr.translation());
      EXPECT_EQ(r->covariance, reference.covariance);
    }
  }
  EXPECT_EQ(shared.registered(), scans.size());
  EXPECT_EQ(shared.reused(), scans.size());

  // A scan the odometry has moved past (never registered) is refused, and says why.
  LidarScan late = scans[3];
  late.header.stamp_ns += 1;
  const LidarOdometryResult refused = shared.Register(late, late.header.stamp_ns);
  EXPECT_FALSE(refused.accepted);
  EXPECT_NE(refused.reject_reason.find("past this scan"), std::string::npos);
  // Another scan under a registered stamp is refused too, not mistaken for it.
  LidarScan other = scans[20];
  other.points = std::make_shared<std::vector<LidarPoint>>(scans[20].points->begin(),
                                                           scans[20].points->begin() + 500);
  EXPECT_FALSE(shared.Register(other, other.header.stamp_ns).accepted);
  EXPECT_EQ(shared.registered(), scans.size());
}

// A store in memory: what a pool records, a later pool replays.
class MemoryRegistrationStore final : public RegistrationStore {
 public:
  std::optional<std::vector<RecordedRegistration>> Load(const std::string& key) override {
    const auto it = saved.find(key);
    if (it == saved.end()) return std::nullopt;
    return it->second;
  }
  void Save(const std::string& key, const std::vector<RecordedRegistration>& r) override {
    saved[key] = r;
  }
  std::map<std::string, std::vector<RecordedRegistration>> saved;
};

TEST(SharedLidarOdometry, ARecordedRunReplaysBitForBitThroughAFile) {
  ScenarioOptions so;
  so.duration_s = 8.0;
  const Scenario sc = MakeScenario(so);
  const std::vector<Measurement> stream = WithScans(sc, 0.5, 8.0);
  const EstimatorSensorSetup setup = MakeSetup(sc.options, kLidarEntry);
  const auto run = [&](LidarOdometryPool& pool) {
    std::vector<std::unique_ptr<FactorGraphEstimator>> one;
    one.push_back(std::make_unique<FactorGraphEstimator>(
        setup, SharedPriorOptions(1.0, LidarPriorSource::kGyro), &pool));
    std::vector<Outputs> out = FeedInStep(one, stream);
    pool.Finish();
    return out[0];
  };
  MemoryRegistrationStore store;
  LidarOdometryPool recording(&store);
  const Outputs first = run(recording);
  ASSERT_EQ(store.saved.size(), 1u);
  std::vector<RecordedRegistration>& recorded = store.saved.begin()->second;
  EXPECT_GE(recorded.size(), 70u);  // of 75 scans: the last wait for IMU beyond the stream

  // Through a file: every field back, bit for bit (the replay below compares the estimates).
  const std::filesystem::path file = std::filesystem::temp_directory_path() /
                                     ("shared_lidar_odometry_test_" + std::to_string(getpid()));
  WriteRegistrations(file, recorded);
  recorded = ReadRegistrations(file);
  std::filesystem::remove(file);

  LidarOdometryPool replaying(&store);
  const Outputs second = run(replaying);
  ExpectBitIdentical(first.estimates, second.estimates);
  EXPECT_EQ(first.diagnostics.sensors.at("lidar_roof").events,
            second.diagnostics.sensors.at("lidar_roof").events);
  EXPECT_EQ(replaying.Counts()[0].first, recorded.size());

  // A record of other scans is refused, not replayed.
  recorded.erase(recorded.begin() + 3);
  LidarOdometryPool wrong(&store);
  EXPECT_THROW(run(wrong), InputError);
}

TEST(SharedLidarOdometry, ATruncatedRecordIsAnErrorNamingTheFile) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() /
                                     ("shared_lidar_odometry_trunc_" + std::to_string(getpid()));
  RecordedRegistration r;
  r.stamp_ns = 7;
  r.result.reject_reason = "too few points";
  WriteRegistrations(file, {r, r});
  std::filesystem::resize_file(file, std::filesystem::file_size(file) - 9);
  try {
    ReadRegistrations(file);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
  std::filesystem::remove(file);
}

TEST(SharedLidarOdometry, PoolKeysOnLidarsAndEveryOdometryOption) {
  LidarOdometryPool pool;
  LidarSetKey roof;
  roof.mounts = {{"lidar_roof", SE3::Identity()}};
  LidarSetKey pair = roof;
  pair.mounts.push_back({"lidar_rear", SE3(Quat::Identity(), Vec3(-1.0, 0.0, 0.0))});
  LidarSetKey roof_late = roof;
  roof_late.intake = "reorder 0.2 s";
  LidarSetKey pair_moved = pair;
  pair_moved.mounts[1].second = SE3(Quat::Identity(), Vec3(-1.0, 0.0, 1e-6));
  const LidarOdometryOptions base;
  LidarOdometryOptions voxel = base;
  voxel.voxel_size_m = 0.5;
  LidarOdometryOptions icp = base;
  icp.icp.thin_ratio = 0.03;

  const Quat level = Quat::Identity();
  const Quat tilted = so3::Exp(Vec3(0.0, 1e-6, 0.0));
  const auto a = pool.For(roof, std::nullopt, base);
  EXPECT_EQ(pool.For(roof, std::nullopt, base), a);
  const auto g = pool.For(roof, level, base);
  EXPECT_EQ(pool.For(roof, level, base), g);
  for (const auto& other :
       {g, pool.For(roof, tilted, base), pool.For(pair, std::nullopt, base),
        pool.For(pair_moved, std::nullopt, base), pool.For(roof, std::nullopt, voxel),
        pool.For(roof, std::nullopt, icp), pool.For(roof_late, std::nullopt, base)}) {
    EXPECT_NE(other, a);
  }
  EXPECT_NE(pool.For(roof, tilted, base), g);
  EXPECT_EQ(pool.size(), 8u);
}

}  // namespace
}  // namespace statebench::est
