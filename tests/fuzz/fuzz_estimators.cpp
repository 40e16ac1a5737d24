// Fuzz target: the factor graph and the EKF fed arbitrary measurement streams: any type, any
// sensor id, stamps in any order, any values (every double is taken raw from the input, so NaN,
// inf, 1e300 and denormals all occur). A prefix of a clean synthetic drive (its length from the
// input) lets the estimators initialise first, so the fuzzed records reach a running filter.
// The contract (estimator/estimator.hpp): never crash, never throw, and StateAt returns either
// nothing or a finite mean with a finite covariance.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "../estimator/ekf_test_drive.hpp"
#include "estimator/ekf_single_track.hpp"
#include "estimator/factor_graph_estimator.hpp"
#include "fuzz_support.hpp"

namespace {

using namespace statebench;
using namespace statebench::est;

const std::string kSetup =
    "name: fuzz\nsensors:\n"
    "  - {type: imu, id: imu, T_body_sensor: {translation: [0, 0, 0.5]}}\n"
    "  - {type: gnss, id: gnss, T_body_sensor: {translation: [0.8, 0, 1.4]}}\n"
    "  - {type: gnss, id: gnss_rear, T_body_sensor: {translation: [-0.8, 0, 1.4]}}\n"
    "  - {type: speed_encoder, id: speed, T_body_sensor: {translation: [-0.76, 0, 0.27]}}\n"
    "  - {type: steering_encoder, id: steering, T_body_sensor: {translation: [0.93, 0, 0]}}\n"
    "  - {type: wheel_encoders, id: wheels, T_body_sensor: {translation: [0, 0, 0]}}\n"
    "  - {type: lidar, id: lidar, T_body_sensor: {translation: [0, 0, 1.8]}, model: hesai_xt32}\n"
    "dual_antenna_headings:\n  - {id: heading, main: gnss_rear, aux: gnss}\n";

const char* const kIds[] = {"imu",   "gnss",  "gnss_rear", "heading", "speed",
                            "steering", "wheels", "lidar",     "nobody"};

const EstimatorSensorSetup& Setup() {
  static const EstimatorSensorSetup setup =
      ParseEstimatorSensorSetup(YamlNode::LoadString(kSetup, "fuzz_setup.yaml"));
  return setup;
}

// 1.5 s of a clean drive with dual-antenna headings (arrival order).
const std::vector<Measurement>& CleanPrefix() {
  static const std::vector<Measurement> stream = [] {
    testing::DriveOptions o;
    o.duration_s = 1.5;
    o.heading_sigma_rad = 0.01;
    return testing::MakeDrive(EkfOptions().vehicle, o).stream;
  }();
  return stream;
}

class Bytes {
 public:
  Bytes(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  bool empty() const { return pos_ >= size_; }
  template <typename T>
  T Take() {
    T v{};
    const std::size_t n = std::min(sizeof(T), size_ - std::min(pos_, size_));
    std::memcpy(&v, data_ + pos_, n);
    pos_ += sizeof(T);
    return v;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

Measurement Decode(Bytes& in, TimeNs* stamp_ns) {
  const int kind = in.Take<std::uint8_t>() % 8;
  MeasurementHeader h;
  h.sensor_id = kIds[in.Take<std::uint8_t>() % (sizeof(kIds) / sizeof(kIds[0]))];
  *stamp_ns += static_cast<TimeNs>(in.Take<std::int16_t>()) * kNsPerMillisecond;
  h.stamp_ns = *stamp_ns;
  h.arrival_ns = *stamp_ns + static_cast<TimeNs>(in.Take<std::int16_t>()) * kNsPerMillisecond;
  const auto d = [&in] { return in.Take<double>(); };
  switch (kind) {
    case 0: {
      ImuSample s;
      s.header = h;
      s.gyro = Vec3(d(), d(), d());
      s.accel = Vec3(d(), d(), d());
      return s;
    }
    case 1: {
      GnssFix f;
      f.header = h;
      f.latitude_deg = d();
      f.longitude_deg = d();
      f.altitude_m = d();
      for (int i = 0; i < 9; ++i) f.covariance_enu(i / 3, i % 3) = d();
      f.status = static_cast<GnssFixStatus>(in.Take<std::uint8_t>() % 5);
      return f;
    }
    case 2: {
      DualAntennaHeading a;
      a.header = h;
      a.yaw_rad = d();
      a.pitch_rad = d();
      a.yaw_sigma_rad = d();
      a.pitch_sigma_rad = d();
      return a;
    }
    case 3: {
      WheelSpeeds w;
      w.header = h;
      for (double& x : w.omega_radps) x = d();
      return w;
    }
    case 4:
      return VehicleSpeed{h, d()};
    case 5:
      return SteeringAngle{h, d()};
    case 6: {
      LidarScan scan;
      scan.header = h;
      auto points = std::make_shared<std::vector<LidarPoint>>(in.Take<std::uint8_t>() % 64);
      for (LidarPoint& p : *points) {
        p.x = in.Take<float>();
        p.y = in.Take<float>();
        p.z = in.Take<float>();
        p.intensity = in.Take<float>();
        p.t = in.Take<float>();
        p.ring = in.Take<std::uint16_t>();
      }
      scan.points = points;
      return scan;
    }
    default: {
      BodyVelocity v;
      v.header = h;
      v.velocity = Vec3(d(), d(), d());
      v.angular_velocity = Vec3(d(), d(), d());
      for (int i = 0; i < 36; ++i) v.covariance(i / 6, i % 6) = d();
      return v;
    }
  }
}

void Check(const Estimator& e, TimeNs t_ns) {
  const auto s = e.StateAt(t_ns);
  if (!s) return;
  if (!s->state.p_world.allFinite() || !s->state.v_world.allFinite() ||
      !s->state.q_world_imu.coeffs().allFinite() || !s->covariance.allFinite() ||
      !std::isfinite(s->latitude_deg) || !std::isfinite(s->longitude_deg)) {
    std::fprintf(stderr, "fuzz_estimators: %s returned a non-finite state\n", e.name().c_str());
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  Bytes in(data, size);
  const int which = in.Take<std::uint8_t>() % 3;  // 0: both, 1: factor graph, 2: EKF
  const double prefix_s = (in.Take<std::uint8_t>() % 16) * 0.1;
  try {
    std::vector<std::unique_ptr<Estimator>> estimators;
    if (which != 2) {
      FactorGraphOptions o;
      o.origin = testing::kDriveOrigin;
      estimators.push_back(std::make_unique<FactorGraphEstimator>(Setup(), o));
    }
    if (which != 1) estimators.push_back(std::make_unique<EkfSingleTrackEstimator>(Setup(), EkfOptions()));
    TimeNs stamp_ns = 0;
    for (const Measurement& m : CleanPrefix()) {
      if (ToSeconds(HeaderOf(m).arrival_ns) > prefix_s) break;
      stamp_ns = std::max(stamp_ns, HeaderOf(m).stamp_ns);
      for (auto& e : estimators) e->Add(m);
    }
    for (int n = 0; n < 2000 && !in.empty(); ++n) {
      const Measurement m = Decode(in, &stamp_ns);
      for (auto& e : estimators) {
        e->Add(m);
        e->diagnostics();
        Check(*e, HeaderOf(m).stamp_ns);
        Check(*e, stamp_ns - kNsPerMillisecond);
      }
    }
  } catch (const std::exception& e) {
    statebench::fuzz::Unexpected("fuzz_estimators", e);
  }
  return 0;
}
