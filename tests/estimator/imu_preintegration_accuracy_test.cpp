// Accuracy of the preintegrated mean deltas on noise-free samples of a car-like motion
// (issue 4: "preintegration of noise-free IMU data between two truth states reproduces the truth
// deltas within 1e-6"), for intervals on and between the 100 Hz sample stamps, and the order of
// convergence of the discretisation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/so3.hpp"
#include "core/state.hpp"
#include "estimator/imu_preintegration.hpp"
#include "trajectory_imu.hpp"

namespace statebench::est {
namespace {

// Slalom with a varying speed and small hills, driven along its tangent, with a body roll that
// follows the turns (a car: yaw rate up to ~1 rad/s, lateral acceleration up to ~6 m/s^2):
//   x = V t + B sin(nu t),  y = A sin(W t) + A2 sin(W2 t + 0.7),  z = H sin(mu t)
//   yaw = atan2(y', x'),  pitch = atan2(-z', |(x', y')|),  roll = r1 sin(W t + 0.3) + r2 sin(3.1 t)
// R = Rz(yaw) Ry(pitch) Rx(roll); body rates from the Z-Y-X Euler rates.
class CarTrajectory {
 public:
  static constexpr double kV = 6.0, kB = 1.5, kNu = 0.6, kA = 3.0, kW = 1.2, kA2 = 0.25, kW2 = 2.6,
                          kH = 0.5, kMu = 0.4, kRoll1 = 0.02, kRoll2 = 0.005;

  Vec3 Position(double t) const {
    return Vec3(kV * t + kB * std::sin(kNu * t),
                kA * std::sin(kW * t) + kA2 * std::sin(kW2 * t + 0.7), kH * std::sin(kMu * t));
  }
  Vec3 Velocity(double t) const {
    return Vec3(kV + kB * kNu * std::cos(kNu * t),
                kA * kW * std::cos(kW * t) + kA2 * kW2 * std::cos(kW2 * t + 0.7),
                kH * kMu * std::cos(kMu * t));
  }
  Vec3 Acceleration(double t) const {
    return Vec3(-kB * kNu * kNu * std::sin(kNu * t),
                -kA * kW * kW * std::sin(kW * t) - kA2 * kW2 * kW2 * std::sin(kW2 * t + 0.7),
                -kH * kMu * kMu * std::sin(kMu * t));
  }
  // (roll, pitch, yaw) and their time derivatives.
  void Euler(double t, Vec3* angles, Vec3* rates) const {
    const Vec3 v = Velocity(t), a = Acceleration(t);
    const double h = v.head<2>().norm();
    const double dh = (v.x() * a.x() + v.y() * a.y()) / h;
    angles->x() = kRoll1 * std::sin(kW * t + 0.3) + kRoll2 * std::sin(3.1 * t);
    angles->y() = std::atan2(-v.z(), h);
    angles->z() = std::atan2(v.y(), v.x());
    rates->x() = kRoll1 * kW * std::cos(kW * t + 0.3) + kRoll2 * 3.1 * std::cos(3.1 * t);
    rates->y() = (-a.z() * h + v.z() * dh) / (h * h + v.z() * v.z());
    rates->z() = (v.x() * a.y() - v.y() * a.x()) / (h * h);
  }
  Quat Orientation(double t) const {
    Vec3 e, d;
    Euler(t, &e, &d);
    return so3::FromRollPitchYaw(e.x(), e.y(), e.z());
  }
  Vec3 Gyro(double t) const {
    Vec3 e, d;
    Euler(t, &e, &d);
    const double sr = std::sin(e.x()), cr = std::cos(e.x());
    const double sp = std::sin(e.y()), cp = std::cos(e.y());
    return Vec3(d.x() - sp * d.z(), cr * d.y() + sr * cp * d.z(), -sr * d.y() + cr * cp * d.z());
  }
  Vec3 Accel(double t) const { return testing::SpecificForce(*this, t); }
  NavState State(TimeNs t_ns) const { return testing::StateOf(*this, t_ns); }
};

using testing::DeltaErrors;

// Noise-free samples every step_ns over [t0_ns, t1_ns] (both on the grid).
std::vector<ImuSample> CarSamples(TimeNs t0_ns, TimeNs t1_ns, TimeNs step_ns) {
  const CarTrajectory car;
  std::vector<ImuSample> samples;
  for (TimeNs t_ns = t0_ns; t_ns <= t1_ns; t_ns += step_ns) {
    samples.push_back(testing::SampleOf(car, t_ns));
  }
  return samples;
}

constexpr TimeNs kStep100Hz = 10'000'000;

// Deltas over [t_begin, t_end] from a 100 Hz-style buffer at the given step that starts
// `context` samples before the interval (as the smoother's buffer does) and reaches one sample
// past its end.
DeltaErrors IntervalError(TimeNs t_begin_ns, TimeNs t_end_ns, TimeNs step_ns, int context,
                          const char* label) {
  const TimeNs first_ns = (t_begin_ns / step_ns - context) * step_ns;
  const TimeNs last_ns = (t_end_ns / step_ns + 1) * step_ns;
  const auto samples = CarSamples(first_ns, last_ns, step_ns);
  const auto pim =
      ImuPreintegration::FromSamples(samples, t_begin_ns, t_end_ns, ImuNoise{}, ImuBias{});
  EXPECT_EQ(pim.start_ns(), t_begin_ns);
  EXPECT_EQ(pim.end_ns(), t_end_ns);
  const DeltaErrors e = testing::PreintegrationErrors(CarTrajectory{}, pim);
  std::printf("%-34s %4.0f Hz: rot %.2e rad, vel %.2e m/s, pos %.2e m\n", label,
              1e9 / static_cast<double>(step_ns), e.rotation, e.velocity, e.position);
  return e;
}

TEST(CarTrajectory, RatesMatchFiniteDifferencesAndAreCarLike) {
  const CarTrajectory car;
  double max_yaw_rate = 0.0, max_lateral = 0.0;
  for (double t = 0.0; t < 12.0; t += 0.05) {
    const double h = 1e-5;
    const Vec3 w_num =
        so3::Log<double>(car.Orientation(t - h).conjugate() * car.Orientation(t + h)) / (2 * h);
    EXPECT_LT((w_num - car.Gyro(t)).norm(), 1e-8);
    const Vec3 a_num = (car.Velocity(t + h) - car.Velocity(t - h)) / (2 * h);
    EXPECT_LT((a_num - car.Acceleration(t)).norm(), 1e-7);
    const Vec3 v_num = (car.Position(t + h) - car.Position(t - h)) / (2 * h);
    EXPECT_LT((v_num - car.Velocity(t)).norm(), 1e-7);
    max_yaw_rate = std::max(max_yaw_rate, std::abs(car.Gyro(t).z()));
    max_lateral = std::max(
        max_lateral, std::abs((car.Accel(t) + car.Orientation(t).conjugate() * kGravityWorld).y()));
  }
  std::printf("car trajectory: max yaw rate %.2f rad/s, max lateral acceleration %.2f m/s^2\n",
              max_yaw_rate, max_lateral);
  EXPECT_GT(max_yaw_rate, 0.8);
  EXPECT_GT(max_lateral, 4.0);
}

// Intervals of 0.1 s (the smoother's keyframe interval) and 1 s, with the ends on sample stamps
// and at arbitrary stamps between samples (states and measurements at their own stamps).
// Largest errors measured at 100 Hz (rotation rad, velocity m/s, position m):
//   0.1 s: 4.8e-10, 2.4e-9, 1.4e-10   (former trapezoidal scheme: 1.1e-6, 4.5e-6, 2.6e-7)
//   1 s:   2.2e-9,  3.2e-8, 1.4e-8    (former trapezoidal scheme: 1.4e-5, 1.0e-4, 3.8e-5)
// without earlier samples (linear first step): 9.9e-8, 6.0e-7, 5.3e-7.
TEST(ImuPreintegrationAccuracy, NoiseFreeDeltasMatchTruthWithin1e6) {
  const TimeNs t0 = FromSeconds(3.0);
  const TimeNs off_a = 3'456'789, off_b = 7'654'321;  // ns into a 10 ms sample gap
  for (const TimeNs length : {FromSeconds(0.1), FromSeconds(1.0)}) {
    for (int start = 0; start < 4; ++start) {  // several phases of the slalom
      const TimeNs t_begin = t0 + start * FromSeconds(1.7);
      const DeltaErrors on = IntervalError(t_begin, t_begin + length, kStep100Hz, 3, "on grid");
      const DeltaErrors off_begin =
          IntervalError(t_begin + off_a, t_begin + length, kStep100Hz, 3, "begin between samples");
      const DeltaErrors off_end =
          IntervalError(t_begin, t_begin + length + off_b, kStep100Hz, 3, "end between samples");
      const DeltaErrors off_both = IntervalError(t_begin + off_a, t_begin + length + off_b,
                                                 kStep100Hz, 3, "both between samples");
      // Without earlier samples in the buffer the first steps fall back to lower order.
      const DeltaErrors no_context =
          IntervalError(t_begin, t_begin + length, kStep100Hz, 0, "on grid, no earlier samples");
      for (const DeltaErrors& e : {on, off_begin, off_end, off_both, no_context}) {
        EXPECT_LT(e.Max(), 1e-6);
      }
    }
  }
  // Both ends inside one sample gap, and an end just after a sample (a GNSS fix 0.1 ms later).
  EXPECT_LT(IntervalError(t0 + off_a, t0 + off_b, kStep100Hz, 3, "inside one gap").Max(), 1e-6);
  EXPECT_LT(
      IntervalError(t0, t0 + FromSeconds(0.1) + 100'000, kStep100Hz, 3, "end 0.1 ms after").Max(),
      1e-6);
}

// Halving the sample interval divides the error by ~16 (fourth order), measured with steps of
// 20, 10 and 5 ms over 1 s (errors far above rounding). On stretches with faster changing rates
// the rotation error approaches the asymptotic ratio only below 10 ms (e.g. over [4 s, 5 s]:
// 5.6, 11.9, 14.1, 15.1 from 40 ms down to 2.5 ms), velocity and position already at 40 ms.
TEST(ImuPreintegrationAccuracy, ErrorIsFourthOrderInTheSampleInterval) {
  const TimeNs t_begin = FromSeconds(2.0), t_end = FromSeconds(3.0);
  const DeltaErrors coarse = IntervalError(t_begin, t_end, 2 * kStep100Hz, 3, "order, h = 20 ms");
  const DeltaErrors fine = IntervalError(t_begin, t_end, kStep100Hz, 3, "order, h = 10 ms");
  const DeltaErrors finer = IntervalError(t_begin, t_end, kStep100Hz / 2, 3, "order, h = 5 ms");
  std::printf("error ratios h -> h/2: rot %.1f %.1f, vel %.1f %.1f, pos %.1f %.1f\n",
              coarse.rotation / fine.rotation, fine.rotation / finer.rotation,
              coarse.velocity / fine.velocity, fine.velocity / finer.velocity,
              coarse.position / fine.position, fine.position / finer.position);
  for (const auto& [c, f] : {std::pair{coarse, fine}, std::pair{fine, finer}}) {
    EXPECT_NEAR(c.rotation / f.rotation, 16.0, 2.0);
    EXPECT_NEAR(c.velocity / f.velocity, 16.0, 2.0);
    EXPECT_NEAR(c.position / f.position, 16.0, 2.0);
  }
}

// The interval may be extended sample by sample (Integrate), also after an end between samples;
// the result is the interval integrated at once. Reintegrated() keeps the earlier samples used
// as interpolation context: with the same bias it reproduces the deltas exactly, with another
// bias it equals integrating the buffer with that bias.
TEST(ImuPreintegrationAccuracy, StreamingAndReintegrationUseTheSameScheme) {
  const auto samples = CarSamples(FromSeconds(2.0), FromSeconds(3.0), kStep100Hz);
  const TimeNs t_a = FromSeconds(2.2) + 3'000'000, t_b = FromSeconds(2.5) + 6'000'000;
  const TimeNs t_c = FromSeconds(2.8);
  const ImuBias bias{Vec3(0.01, -0.02, 0.005), Vec3(0.1, 0.05, -0.2)};
  const auto whole = ImuPreintegration::FromSamples(samples, t_a, t_c, ImuNoise{}, bias);
  auto streamed = ImuPreintegration::FromSamples(samples, t_a, t_b, ImuNoise{}, bias);
  for (const ImuSample& s : samples) {
    if (s.header.stamp_ns > t_b && s.header.stamp_ns <= t_c) streamed.Integrate(s);
  }
  EXPECT_EQ(streamed.end_ns(), t_c);
  EXPECT_EQ(streamed.num_steps(), whole.num_steps() + 1);  // t_b stays a node
  EXPECT_LT(so3::Log<double>(whole.delta_q().conjugate() * streamed.delta_q()).norm(), 1e-12);
  EXPECT_LT((whole.delta_v() - streamed.delta_v()).norm(), 1e-9);  // split partial step
  EXPECT_LT((whole.delta_p() - streamed.delta_p()).norm(), 1e-10);

  const auto same = whole.Reintegrated(bias);
  EXPECT_EQ(same.delta_q().coeffs(), whole.delta_q().coeffs());
  EXPECT_EQ(same.delta_v(), whole.delta_v());
  EXPECT_EQ(same.delta_p(), whole.delta_p());
  EXPECT_EQ(same.d_p_d_bg(), whole.d_p_d_bg());
  const ImuBias other{Vec3(-0.01, 0.0, 0.02), Vec3(0.0, -0.1, 0.1)};
  const auto moved = whole.Reintegrated(other);
  const auto direct = ImuPreintegration::FromSamples(samples, t_a, t_c, ImuNoise{}, other);
  EXPECT_EQ(moved.delta_q().coeffs(), direct.delta_q().coeffs());
  EXPECT_EQ(moved.delta_v(), direct.delta_v());
  EXPECT_EQ(moved.delta_p(), direct.delta_p());
  EXPECT_EQ(moved.covariance(), direct.covariance());

  // First-order bias correction: the error against re-integration is quadratic in the change.
  double previous = 0.0;
  for (const double scale : {1.0, 0.5, 0.25}) {
    const ImuBias b = ImuBias::FromVector(bias.AsVector() + scale * other.AsVector());
    const auto exact = whole.Reintegrated(b);
    const double error =
        so3::Log<double>(exact.delta_q().conjugate() * whole.CorrectedDeltaQ(b)).norm() +
        (exact.delta_v() - whole.CorrectedDeltaV(b)).norm() +
        (exact.delta_p() - whole.CorrectedDeltaP(b)).norm();
    std::printf("bias change x %.2f: corrected deltas off by %.2e\n", scale, error);
    if (previous > 0.0) {
      EXPECT_NEAR(previous / error, 4.0, 0.4);
    }
    previous = error;
  }
}

}  // namespace
}  // namespace statebench::est
