// Synthetic measurement streams for the recorded-log tests: every measurement type, values drawn
// as random finite bit patterns (any exponent, subnormals, signed zeros) so that only an exact
// round trip reproduces them, in arrival order.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "core/random.hpp"
#include "sensors/log_reader.hpp"
#include "sensors/log_writer.hpp"
#include "sensors/measurement_stream.hpp"

namespace statebench::sensors::testing {

class TempLogDir {
 public:
  // The process id keeps test programs that ctest runs in parallel out of each other's folders.
  explicit TempLogDir(const std::string& name)
      : path_(std::filesystem::temp_directory_path() /
              ("statebench_log_test_" + std::to_string(::getpid()) + "_" + name)) {
    std::filesystem::remove_all(path_);
  }
  ~TempLogDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

class AnyBits {
 public:
  explicit AnyBits(std::uint64_t seed) : rng_(MakeRng(seed, "log_test")) {}
  double Double() {
    while (true) {
      const double v = std::bit_cast<double>(rng_());
      if (std::isfinite(v)) return v;
    }
  }
  float Float() {
    while (true) {
      const float v = std::bit_cast<float>(static_cast<std::uint32_t>(rng_()));
      if (std::isfinite(v)) return v;
    }
  }
  std::uint16_t Ring() { return static_cast<std::uint16_t>(rng_() % 32); }

 private:
  std::mt19937_64 rng_;
};

// `seconds` of: IMU 100 Hz, two GNSS antennas (the front one with a velocity at every other
// fix) and a heading at 10 Hz, wheels, speed and
// steering at 50 Hz, body velocity at 20 Hz, a lidar at 10 Hz (`points_per_scan` points, the
// second sweep empty). Latencies make the arrival order differ from the stamp order.
inline std::vector<Measurement> SyntheticStream(double seconds, std::uint64_t seed,
                                                std::size_t points_per_scan = 300) {
  AnyBits bits(seed);
  std::vector<Measurement> out;
  const auto header = [](const char* id, TimeNs t, TimeNs latency_ms) {
    return MeasurementHeader{id, t, t + latency_ms * kNsPerMillisecond};
  };
  const TimeNs end = FromSeconds(seconds);
  for (TimeNs t = 0; t <= end; t += 10 * kNsPerMillisecond) {
    out.push_back(ImuSample{header("imu", t, 2), Vec3(bits.Double(), bits.Double(), -0.0),
                            Vec3(bits.Double(), bits.Double(), bits.Double())});
    if (t % (20 * kNsPerMillisecond) == 0) {
      WheelSpeeds w{header("wheels", t, 10)};
      for (double& o : w.omega_radps) o = bits.Double();
      out.push_back(w);
      out.push_back(VehicleSpeed{header("speed", t, 10), bits.Double()});
      out.push_back(SteeringAngle{header("steering", t, 10), bits.Double()});
    }
    if (t % (50 * kNsPerMillisecond) == 0) {
      BodyVelocity b{header("radar", t, 30)};
      b.velocity = Vec3(bits.Double(), bits.Double(), bits.Double());
      b.angular_velocity = Vec3(bits.Double(), bits.Double(), bits.Double());
      for (int i = 0; i < 36; ++i) b.covariance.data()[i] = bits.Double();
      out.push_back(b);
    }
    if (t % (100 * kNsPerMillisecond) == 0) {
      for (const char* id : {"gnss_front", "gnss_rear"}) {
        GnssFix f;
        f.header = header(id, t, 100);
        f.latitude_deg = 48.0 + 1e-3 * std::fmod(std::abs(bits.Double()), 1.0);
        f.longitude_deg = bits.Double();
        f.altitude_m = bits.Double();
        for (int i = 0; i < 9; ++i) f.covariance_enu.data()[i] = bits.Double();
        f.status = static_cast<GnssFixStatus>((t / (100 * kNsPerMillisecond)) % 4);
        // The front receiver gives a Doppler velocity at every other fix (the first one too,
        // so its file has the velocity columns): empty velocity cells in between.
        if (std::string_view(id) == "gnss_front" && t % (200 * kNsPerMillisecond) == 0) {
          f.velocity = GnssVelocity{
              Vec3(bits.Double(), bits.Double(), bits.Double()),
              Vec3(bits.Double(), bits.Double(), bits.Double()).cwiseAbs().cwiseMax(1e-3)};
        }
        out.push_back(f);
      }
      out.push_back(DualAntennaHeading{header("gnss_heading", t, 100), bits.Double(), bits.Double(),
                                       bits.Double(), bits.Double()});
      LidarScan scan{header("lidar", t, 120), nullptr};
      auto points = std::make_shared<std::vector<LidarPoint>>();
      if (t != 100 * kNsPerMillisecond) {
        for (std::size_t i = 0; i < points_per_scan; ++i) {
          points->push_back(LidarPoint{bits.Float(), bits.Float(), bits.Float(), bits.Float(),
                                       bits.Float(), bits.Ring()});
        }
      }
      scan.points = points;
      out.push_back(scan);
    }
  }
  std::stable_sort(out.begin(), out.end(), ArrivesBefore);
  return out;
}

}  // namespace statebench::sensors::testing
