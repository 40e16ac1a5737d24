#include "sensors/gnss_receiver.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "truth_fixtures.hpp"

namespace statebench::sensors {
namespace {

const GeodeticPoint kOrigin{48.7126, 2.2085, 160.0};

SensorSpec AntennaSpec(double rate_hz, const Vec3& lever_arm = Vec3(0.45, 0.0, 1.47)) {
  SensorSpec spec;
  spec.id = "gnss_front";
  spec.rate_hz = rate_hz;
  spec.T_body_sensor = SE3(Quat::Identity(), lever_arm);
  spec.latency_s = 0.1;
  return spec;
}

Vec3 AntennaTruth(const TruthSample& truth, const SensorSpec& spec) {
  return truth.body.T_world_frame * spec.T_body_sensor.translation();
}

Vec3 FixEnu(const GnssFix& fix, const LocalEnuFrame& frame) {
  return frame.ToEnu({fix.latitude_deg, fix.longitude_deg, fix.altitude_m});
}

// Errors (ENU, m) of `n` fixes taken at `rate_hz` by a vehicle parked away from the origin.
std::vector<Vec3> FixErrors(const GnssOptions& options, int n, double rate_hz, std::uint64_t seed,
                            std::vector<GnssFix>* fixes = nullptr) {
  const LocalEnuFrame frame(kOrigin);
  const SensorSpec spec = AntennaSpec(rate_hz);
  GnssReceiver receiver(spec, options, frame, seed);
  std::vector<Vec3> errors;
  for (int k = 0; k < n; ++k) {
    const TruthSample truth =
        testing::StaticTruth(k * spec.PeriodNs(), Vec3(1500.0, -800.0, 12.0), 0.4);
    const std::optional<GnssFix> fix = receiver.Sample(truth);
    if (!fix) continue;
    errors.push_back(FixEnu(*fix, frame) - AntennaTruth(truth, spec));
    if (fixes) fixes->push_back(*fix);
  }
  return errors;
}

double Median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

TEST(GnssReceiver, Cep2mReceiverHasMeasuredCep50Of2m) {
  GnssOptions o;
  o.mode = GnssMode::kSingle;  // default single-point accuracy: CEP 2 m
  ASSERT_DOUBLE_EQ(o.AccuracyOf(GnssMode::kSingle).cep_m, 2.0);
  std::vector<GnssFix> fixes;
  const std::vector<Vec3> errors = FixErrors(o, 10000, 10.0, 11, &fixes);
  ASSERT_EQ(errors.size(), 10000u);
  std::vector<double> radius, up;
  double sum_e2 = 0.0, sum_n2 = 0.0, sum_u2 = 0.0;
  for (const Vec3& e : errors) {
    radius.push_back(e.head<2>().norm());
    sum_e2 += e.x() * e.x();
    sum_n2 += e.y() * e.y();
    sum_u2 += e.z() * e.z();
  }
  const double cep50 = Median(radius);
  std::printf("[ measured ] CEP50 %.4f m (configured 2 m), sigma E %.4f N %.4f U %.4f m\n", cep50,
              std::sqrt(sum_e2 / 1e4), std::sqrt(sum_n2 / 1e4), std::sqrt(sum_u2 / 1e4));
  EXPECT_NEAR(cep50, 2.0, 0.05 * 2.0);
  // Per-axis sigma 2 / 1.1774 = 1.699 m (std of the estimate ~0.7 %).
  EXPECT_NEAR(std::sqrt(sum_e2 / 1e4), 1.699, 0.04);
  EXPECT_NEAR(std::sqrt(sum_n2 / 1e4), 1.699, 0.04);
  EXPECT_NEAR(std::sqrt(sum_u2 / 1e4), 1.5 * 1.699, 0.06);
  // The receiver reports what it does.
  const double sigma = 2.0 / kCep50PerSigma;
  EXPECT_NEAR(fixes[0].covariance_enu(0, 0), sigma * sigma, 1e-12);
  EXPECT_NEAR(fixes[0].covariance_enu(2, 2), std::pow(1.5 * sigma, 2), 1e-12);
  EXPECT_EQ(fixes[0].status, GnssFixStatus::kSingle);
}

// Sample autocorrelation of one axis at lags 1..max_lag.
std::vector<double> Autocorrelation(const std::vector<Vec3>& x, int axis, int max_lag) {
  const std::size_t n = x.size();
  double mean = 0.0;
  for (const Vec3& v : x) mean += v[axis];
  mean /= static_cast<double>(n);
  double c0 = 0.0;
  for (const Vec3& v : x) c0 += (v[axis] - mean) * (v[axis] - mean);
  std::vector<double> rho;
  for (int k = 1; k <= max_lag; ++k) {
    double c = 0.0;
    for (std::size_t i = 0; i + k < n; ++i) c += (x[i][axis] - mean) * (x[i + k][axis] - mean);
    rho.push_back(c / c0);
  }
  return rho;
}

// White + Gauss-Markov with 70 % of the variance correlated: for lags k >= 1 the
// autocorrelation is 0.7 exp(-k dt / tau). A log-linear fit over lags 1..tau/dt gives back tau
// (within 15 %) and the fraction.
TEST(GnssReceiver, GaussMarkovAutocorrelationTimeMatchesTau) {
  GnssOptions o;
  o.mode = GnssMode::kRtkFloat;
  o.correlated_fraction = 0.7;
  o.gauss_markov_tau_s = 20.0;
  const double dt = 1.0;
  const std::vector<Vec3> errors = FixErrors(o, 20000, 1.0 / dt, 5);
  for (int axis = 0; axis < 3; ++axis) {
    const int max_lag = 20;
    const std::vector<double> rho = Autocorrelation(errors, axis, max_lag);
    // Least squares of log rho_k = a + b k.
    double sk = 0, sy = 0, skk = 0, sky = 0;
    for (int k = 1; k <= max_lag; ++k) {
      const double y = std::log(rho[k - 1]);
      sk += k;
      sy += y;
      skk += k * k;
      sky += k * y;
    }
    const double b = (max_lag * sky - sk * sy) / (max_lag * skk - sk * sk);
    const double a = (sy - b * sk) / max_lag;
    const double tau = -dt / b;
    std::printf("[ measured ] axis %d: tau %.2f s (configured 20 s), correlated fraction %.3f\n",
                axis, tau, std::exp(a));
    EXPECT_NEAR(tau / o.gauss_markov_tau_s, 1.0, 0.15);
    EXPECT_NEAR(std::exp(a), 0.7, 0.07);
  }
}

// The total sigma does not depend on the correlated fraction.
TEST(GnssReceiver, CorrelatedFractionKeepsTheConfiguredSigma) {
  GnssOptions o;
  o.mode = GnssMode::kSingle;
  o.correlated_fraction = 1.0;
  o.gauss_markov_tau_s = 2.0;
  const std::vector<Vec3> errors = FixErrors(o, 20000, 1.0, 9);
  double sum_e2 = 0.0;
  for (const Vec3& e : errors) sum_e2 += e.x() * e.x();
  EXPECT_NEAR(std::sqrt(sum_e2 / errors.size()), 1.699, 0.05);
}

TEST(GnssReceiver, NoiseFreeFixRoundTripsToTheAntennaWithin1mm) {
  GnssOptions o;
  o.mode = GnssMode::kRtkFixed;
  o.AccuracyOf(GnssMode::kRtkFixed) = GnssAccuracy{0.0, 0.0};
  const LocalEnuFrame frame(kOrigin);
  const SensorSpec spec = AntennaSpec(10.0, Vec3(-0.75, 0.2, 1.47));
  GnssReceiver receiver(spec, o, frame, 1);
  testing::Circle circle;
  circle.radius_m = 800.0;
  circle.centre = Vec3(4000.0, -6000.0, 85.0);  // km away: Earth curvature matters here
  for (int k = 0; k < 50; ++k) {
    const TruthSample truth = circle.At(k * 3 * kNsPerSecond);
    const std::optional<GnssFix> fix = receiver.Sample(truth);
    ASSERT_TRUE(fix);
    EXPECT_LT((FixEnu(*fix, frame) - AntennaTruth(truth, spec)).norm(), 1e-3);
    EXPECT_EQ(fix->status, GnssFixStatus::kRtkFixed);
  }
}

TEST(GnssReceiver, OutageProducesNoFixesInsideTheWindow) {
  GnssOptions o;
  o.outages = {GnssOutage{10.0, 20.0}};
  const LocalEnuFrame frame(kOrigin);
  GnssReceiver receiver(AntennaSpec(10.0), o, frame, 2);
  std::vector<Measurement> out;
  for (TimeNs t = 0; t <= 30 * kNsPerSecond; t += kNsPerMillisecond) {
    receiver.Observe(testing::StaticTruth(t), &out);
  }
  std::vector<TimeNs> stamps;
  for (const Measurement& m : out) stamps.push_back(HeaderOf(m).stamp_ns);
  EXPECT_EQ(out.size(), 100u + 101u);  // [0, 10) and [20, 30] at 10 Hz
  for (const TimeNs t : stamps) {
    EXPECT_FALSE(t >= 10 * kNsPerSecond && t < 20 * kNsPerSecond) << ToSeconds(t);
  }
  EXPECT_NE(std::find(stamps.begin(), stamps.end(), 9'900 * kNsPerMillisecond), stamps.end());
  EXPECT_NE(std::find(stamps.begin(), stamps.end(), 20 * kNsPerSecond), stamps.end());
}

// RTK fixed (1 cm) with multipath events of ~6 m lasting ~3 s, 60 per hour, over 2 h at 5 Hz.
TEST(GnssReceiver, MultipathProducesOutliersOfSeveralMetresForSeconds) {
  GnssOptions o;
  o.mode = GnssMode::kRtkFixed;
  o.multipath = GnssMultipathOptions{60.0, 6.0, 3.0};
  const double rate_hz = 5.0;
  const std::vector<Vec3> errors = FixErrors(o, static_cast<int>(7200 * rate_hz), rate_hz, 3);
  // An event is a run of outlier fixes with the same offset (two events may follow each other
  // without a clean fix in between; their offsets differ).
  struct Event {
    int first, last;
    Vec3 offset;
  };
  std::vector<Event> events;
  for (int i = 0; i < static_cast<int>(errors.size()); ++i) {
    if (errors[i].head<2>().norm() < 1.0) continue;
    if (!events.empty() && events.back().last == i - 1 &&
        (errors[i] - events.back().offset).norm() < 0.1) {
      events.back().last = i;
    } else {
      events.push_back({i, i, errors[i]});
    }
  }
  // Events start at 60 per hour of event-free time: ~114 in 2 h (Poisson sd ~11).
  std::printf("[ measured ] %zu multipath events in 2 h\n", events.size());
  EXPECT_GT(events.size(), 80u);
  EXPECT_LT(events.size(), 150u);
  for (const Event& e : events) {
    const double duration_s = (e.last - e.first + 1) / rate_hz;
    EXPECT_GE(duration_s, 1.5 - 1.0 / rate_hz);
    EXPECT_LE(duration_s, 4.5 + 1.0 / rate_hz);
    EXPECT_GE(e.offset.head<2>().norm(), 3.0 - 0.05);
    EXPECT_LE(e.offset.head<2>().norm(), 9.0 + 0.05);
  }
}

TEST(GnssReceiver, LatencyShiftsArrival) {
  GnssOptions o;
  const LocalEnuFrame frame(kOrigin);
  SensorSpec spec = AntennaSpec(20.0);
  spec.latency_s = 0.15;
  GnssReceiver receiver(spec, o, frame, 4);
  const std::optional<GnssFix> fix = receiver.Sample(testing::StaticTruth(2 * kNsPerSecond));
  ASSERT_TRUE(fix);
  EXPECT_EQ(fix->header.stamp_ns, 2 * kNsPerSecond);
  EXPECT_EQ(fix->header.arrival_ns, 2 * kNsPerSecond + 150 * kNsPerMillisecond);
  EXPECT_EQ(fix->header.sensor_id, "gnss_front");
}

TEST(GnssReceiver, CovarianceScaleMakesTheReceiverLie) {
  GnssOptions honest, liar;
  liar.covariance_scale = 0.25;
  const LocalEnuFrame frame(kOrigin);
  GnssReceiver a(AntennaSpec(10.0), honest, frame, 4), b(AntennaSpec(10.0), liar, frame, 4);
  const TruthSample truth = testing::StaticTruth(0);
  const GnssFix fa = *a.Sample(truth), fb = *b.Sample(truth);
  EXPECT_LT((fb.covariance_enu - 0.25 * fa.covariance_enu).norm(), 1e-15);
  // Same seed, same errors: only the report differs.
  EXPECT_EQ(fa.latitude_deg, fb.latitude_deg);
}

class ScheduledVisibility : public SatelliteVisibility {
 public:
  int VisibleSatellites(const Vec3&, TimeNs t_ns) const override {
    const std::int64_t s = t_ns / kNsPerSecond;
    return s < 1 ? 10 : s < 2 ? 6 : s < 3 ? 4 : 2;
  }
};

TEST(GnssReceiver, FewerSatellitesDegradeTheFix) {
  GnssOptions o;
  o.mode = GnssMode::kRtkFixed;
  const LocalEnuFrame frame(kOrigin);
  GnssReceiver receiver(AntennaSpec(1.0), o, frame, 6);
  receiver.SetSatelliteVisibility(std::make_shared<ScheduledVisibility>());
  const auto fix_at = [&](int s) {
    return receiver.Sample(testing::StaticTruth(s * kNsPerSecond));
  };
  EXPECT_EQ(fix_at(0)->status, GnssFixStatus::kRtkFixed);
  const GnssFix degraded = *fix_at(1);
  EXPECT_EQ(degraded.status, GnssFixStatus::kRtkFloat);
  EXPECT_NEAR(std::sqrt(degraded.covariance_enu(0, 0)), 0.25, 1e-9);
  EXPECT_EQ(fix_at(2)->status, GnssFixStatus::kSingle);
  EXPECT_FALSE(fix_at(3).has_value());

  // Never better than the configured mode.
  o.mode = GnssMode::kRtkFloat;
  GnssReceiver float_receiver(AntennaSpec(1.0), o, frame, 6);
  float_receiver.SetSatelliteVisibility(std::make_shared<ScheduledVisibility>());
  EXPECT_EQ(float_receiver.Sample(testing::StaticTruth(0))->status, GnssFixStatus::kRtkFloat);
}

// Doppler velocity (off by default): the antenna's velocity v + R (w x l) plus white noise of
// the configured sigmas, reported as sigma x sqrt(covariance_scale); turning it on leaves the
// position bits unchanged (own random stream).
TEST(GnssReceiver, DopplerVelocityOfTheAntenna) {
  const LocalEnuFrame frame(kOrigin);
  const SensorSpec spec = AntennaSpec(4.0);
  GnssOptions plain;
  plain.mode = GnssMode::kSingle;
  GnssOptions doppler = plain;
  doppler.velocity.enabled = true;
  doppler.covariance_scale = 4.0;
  GnssOptions doppler_same_scale = doppler;
  doppler_same_scale.covariance_scale = 1.0;
  GnssReceiver a(spec, plain, frame, 7), b(spec, doppler_same_scale, frame, 7);
  GnssReceiver c(spec, doppler, frame, 7);
  Vec3 sum = Vec3::Zero(), sum2 = Vec3::Zero();
  const int n = 4000;
  for (int k = 0; k < n; ++k) {
    TruthSample truth = testing::StaticTruth(k * spec.PeriodNs(), Vec3(10.0, 20.0, 1.0), 0.4);
    truth.body.v_world = Vec3(8.0 * std::cos(0.4), 8.0 * std::sin(0.4), 0.1);
    truth.body.omega_frame = Vec3(0.0, 0.02, 0.3);
    const auto fa = a.Sample(truth), fb = b.Sample(truth), fc = c.Sample(truth);
    ASSERT_TRUE(fa && fb && fc);
    EXPECT_FALSE(fa->velocity.has_value());
    ASSERT_TRUE(fb->velocity.has_value());
    EXPECT_EQ(fa->latitude_deg, fb->latitude_deg);
    EXPECT_EQ(fa->altitude_m, fb->altitude_m);
    const Vec3 expected = truth.body.AtMount(spec.T_body_sensor).v_world;
    const Vec3 e = fb->velocity->v_enu - expected;
    sum += e;
    sum2 += e.cwiseAbs2();
    EXPECT_EQ(fb->velocity->sigma_enu, Vec3(0.07, 0.07, 0.12));
    EXPECT_EQ(fc->velocity->sigma_enu, Vec3(0.14, 0.14, 0.24));
  }
  const Vec3 mean = sum / n;
  const Vec3 sigma = (sum2 / n - mean.cwiseAbs2()).cwiseSqrt();
  std::printf("doppler velocity error: mean %.4f %.4f %.4f, sigma %.4f %.4f %.4f m/s\n", mean.x(),
              mean.y(), mean.z(), sigma.x(), sigma.y(), sigma.z());
  EXPECT_LT(mean.cwiseAbs().maxCoeff(), 0.01);
  EXPECT_NEAR(sigma.x(), 0.07, 0.005);
  EXPECT_NEAR(sigma.y(), 0.07, 0.005);
  EXPECT_NEAR(sigma.z(), 0.12, 0.008);
  // The lever arm term is in: 0.3 rad/s about z with the antenna 0.45 m ahead moves it sideways.
  TruthSample turning = testing::StaticTruth(0, Vec3::Zero(), 0.0);
  turning.body.omega_frame = Vec3(0.0, 0.0, 0.3);
  EXPECT_NEAR(turning.body.AtMount(spec.T_body_sensor).v_world.y(), 0.3 * 0.45, 1e-12);
}

}  // namespace
}  // namespace statebench::sensors
