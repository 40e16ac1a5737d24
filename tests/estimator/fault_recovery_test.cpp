// Injected faults (core/measurement_faults.hpp) on a noisy drive with IMU, RTK-grade GNSS, speed
// and steering encoders, fed to the factor graph and to the EKF: for every fault the estimator
// never crashes, never outputs a non-finite mean or covariance, counts what it rejected (or says
// it started over), and is back within its normal error 10 s after the fault ends. "Normal" is
// the same estimator on the same drive without the fault: the largest horizontal error over the
// scored span, with a margin of 100 % or 0.1 m, whichever is larger.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "core/measurement_faults.hpp"
#include "ekf_test_drive.hpp"
#include "estimator/ekf_single_track.hpp"
#include "estimator/factor_graph_estimator.hpp"

namespace statebench::est {
namespace {

using Kind = MeasurementFaultKind;

constexpr double kDuration = 60.0;
constexpr double kFaultStart = 25.0;
constexpr double kRecovery = 10.0;  // seconds after the fault's end

const testing::Drive& TheDrive() {
  static const testing::Drive drive = [] {
    testing::DriveOptions o;
    o.duration_s = kDuration;
    o.steering = [](double t) { return 0.08 * std::sin(0.15 * t); };
    o.gnss_sigma_m = 0.02;
    o.reported_gnss_sigma_m = 0.03;
    o.speed_sigma_mps = 0.02;
    o.gyro_sigma_radps = 0.003;
    o.accel_sigma_mps2 = 0.03;
    o.seed = 17;
    return testing::MakeDrive(EkfOptions().vehicle, o);
  }();
  return drive;
}

std::unique_ptr<Estimator> MakeFactorGraph() {
  FactorGraphOptions options;
  options.origin = testing::kDriveOrigin;
  return std::make_unique<FactorGraphEstimator>(testing::MakeDriveSetup(), options);
}

std::unique_ptr<Estimator> MakeEkf() {
  return std::make_unique<EkfSingleTrackEstimator>(testing::MakeDriveSetup(), EkfOptions());
}

struct FaultOutcome {
  EstimatorDiagnostics diagnostics;
  int outputs = 0;
  int non_finite = 0;
  std::vector<std::pair<double, double>> errors;  // (t, horizontal error), finite outputs
  bool lost = false;

  double MaxErrorFrom(double t0) const {
    double e = 0.0;
    for (const auto& [t, err] : errors) e = t >= t0 ? std::max(e, err) : e;
    return e;
  }
};

FaultOutcome Feed(Estimator* estimator, const std::vector<MeasurementFault>& faults) {
  const testing::Drive& d = TheDrive();
  MeasurementFaultInjector injector(faults);
  std::vector<Measurement> delivered;
  FaultOutcome out;
  std::size_t next_truth = 0;
  for (const Measurement& m : d.stream) {
    delivered.clear();
    injector.Apply(m, &delivered);
    for (const Measurement& x : delivered) estimator->Add(x);
    // The output at every true IMU stamp, scored against the truth at that stamp.
    const auto* imu = std::get_if<ImuSample>(&m);
    if (imu == nullptr) continue;
    const TimeNs t = imu->header.stamp_ns;
    while (next_truth < d.truth.size() && d.truth[next_truth].t_ns < t) ++next_truth;
    if (next_truth >= d.truth.size() || d.truth[next_truth].t_ns != t) continue;
    const auto e = estimator->StateAt(t);
    if (!e) continue;
    ++out.outputs;
    const bool finite = e->state.p_world.allFinite() && e->state.v_world.allFinite() &&
                        e->state.q_world_imu.coeffs().allFinite() && e->covariance.allFinite() &&
                        std::isfinite(e->latitude_deg) && std::isfinite(e->longitude_deg) &&
                        std::isfinite(e->altitude_m);
    if (!finite) {
      ++out.non_finite;
      continue;
    }
    const Vec3 p = d.frame.ToEnu({e->latitude_deg, e->longitude_deg, e->altitude_m});
    const Vec3 truth = testing::TruthImuPosition(d.truth[next_truth]);
    out.errors.emplace_back(ToSeconds(t), (p - truth).head<2>().norm());
  }
  out.diagnostics = estimator->diagnostics();
  out.lost = !out.diagnostics.lost.empty();
  return out;
}

std::uint64_t TotalRejected(const EstimatorDiagnostics& d) {
  std::uint64_t n = 0;
  for (const auto& [id, s] : d.sensors) n += s.TotalRejected();
  return n;
}

struct FaultCase {
  std::string name;
  MeasurementFault fault;
  bool expect_rejections = true;  // the fault shows in the rejection counters
};

MeasurementFault Fault(Kind kind, std::vector<std::string> sensors, double duration_s) {
  MeasurementFault f;
  f.kind = kind;
  f.sensors = std::move(sensors);
  f.start_s = kFaultStart;
  f.end_s = kFaultStart + duration_s;
  return f;
}

std::vector<FaultCase> Cases() {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<FaultCase> cases;
  for (const std::string sensor : {"imu", "gnss", "speed", "steering"}) {
    for (const auto& [label, value] : std::vector<std::pair<std::string, double>>{
             {"nan", kNaN}, {"inf", kInf}, {"minus_inf", -kInf}, {"huge", 1e300},
             {"denormal", 4.9e-324}}) {
      MeasurementFault f = Fault(Kind::kNonFinite, {sensor}, 5.0);
      f.value = value;
      // A denormal is a legal (tiny) value: nothing to reject, but nothing may break either.
      cases.push_back({"non_finite_" + label + "_" + sensor, f, label != "denormal"});
    }
  }
  cases.push_back({"duplicate_all", Fault(Kind::kDuplicate, {}, 5.0)});
  for (const std::string sensor : {"imu", "gnss", "speed", "steering"}) {
    cases.push_back(
        {"stamps_backwards_" + sensor, Fault(Kind::kStampsBackwards, {sensor}, 5.0)});
  }
  cases.push_back({"imu_gap_10s", Fault(Kind::kGap, {"imu"}, 10.0), false});
  {
    MeasurementFault f = Fault(Kind::kGnssJump, {"gnss"}, 5.0);
    f.offset_m = Vec3(100.0, 0.0, 0.0);
    cases.push_back({"gnss_jump_100m_5s", f});
  }
  {
    MeasurementFault f = Fault(Kind::kGnssOverconfident, {"gnss"}, 5.0);
    f.offset_m = Vec3(0.0, 20.0, 0.0);
    f.sigma_m = 0.01;
    cases.push_back({"gnss_20m_off_reporting_1cm", f});
  }
  cases.push_back({"imu_saturated_1s", Fault(Kind::kImuSaturation, {"imu"}, 1.0)});
  {
    MeasurementFault f = Fault(Kind::kClockJump, {"gnss"}, 5.0);
    f.shift_s = 1.0;
    cases.push_back({"gnss_clock_jump_ahead_1s", f});
    f.shift_s = -1.0;
    cases.push_back({"gnss_clock_jump_back_1s", f});
  }
  return cases;
}

// The clean run once per test, then each fault of the family (a test per fault would run the
// clean drive again in every test process; two families let ctest run them side by side).
// Which cases of Cases() a test takes: the non-finite values, or the other faults.
enum class Family { kNonFinite, kOther };

void CheckFaults(const std::string& estimator, std::unique_ptr<Estimator> (*make)(),
                 Family family) {
  const FaultOutcome clean = Feed(make().get(), {});
  ASSERT_GT(clean.outputs, 0);
  ASSERT_EQ(clean.non_finite, 0);
  ASSERT_FALSE(clean.lost);
  for (const FaultCase& c : Cases()) {
    if ((c.fault.kind == Kind::kNonFinite) != (family == Family::kNonFinite)) continue;
    SCOPED_TRACE(estimator + " / " + c.name);
    const double scored_from = c.fault.end_s + kRecovery;
    const FaultOutcome faulty = Feed(make().get(), {c.fault});
    EXPECT_EQ(faulty.non_finite, 0);
    EXPECT_GT(faulty.outputs, 0);
    if (c.expect_rejections) {
      EXPECT_GT(TotalRejected(faulty.diagnostics), TotalRejected(clean.diagnostics))
          << "the fault left no trace in the rejection counters";
    }
    const double clean_max = clean.MaxErrorFrom(scored_from);
    const double normal = std::max(2.0 * clean_max, clean_max + 0.1);
    EXPECT_LT(faulty.MaxErrorFrom(scored_from), normal)
        << "clean run's max error " << clean_max << " m from " << scored_from
        << " s; lost: " << faulty.lost << ", max error during the fault "
        << faulty.MaxErrorFrom(c.fault.start_s);
  }
}

TEST(FaultRecovery, FactorGraphSurvivesNonFiniteValues) {
  CheckFaults("factor_graph", &MakeFactorGraph, Family::kNonFinite);
}

TEST(FaultRecovery, FactorGraphSurvivesTheOtherFaults) {
  CheckFaults("factor_graph", &MakeFactorGraph, Family::kOther);
}

TEST(FaultRecovery, EkfSurvivesEveryFault) {
  CheckFaults("ekf", &MakeEkf, Family::kNonFinite);
  CheckFaults("ekf", &MakeEkf, Family::kOther);
}

}  // namespace
}  // namespace statebench::est
