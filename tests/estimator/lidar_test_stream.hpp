// A lidar for the estimator tests (test fixture): a Hesai XT32 entry for MakeSetup, walls and
// poles around the figure eight of estimator_scenario.hpp, and the scenario's stream with the
// scans of that scene inserted at their arrival times.
#pragma once

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "estimator_scenario.hpp"
#include "synthetic_lidar_scene.hpp"

namespace statebench::est::testing {

inline const SE3 kImuLidar(Quat::Identity(), Vec3(-0.2, 0.0, 1.4));
inline const std::string kLidarEntry =
    "  - {type: lidar, id: lidar_roof, rate_hz: 10, latency_s: 0.02, "
    "T_body_sensor: {translation: [-0.2, 0, 1.4]}, model: hesai_xt32}\n";

// Walls and poles around the test's figure eight (|x| < 40, |y| < 20), never on it.
inline Scene Surroundings() {
  Scene s;
  s.boxes.push_back({Vec3(-60, 28, 0), Vec3(60, 30, 8)});
  s.boxes.push_back({Vec3(-60, -30, 0), Vec3(60, -28, 6)});
  s.boxes.push_back({Vec3(50, -30, 0), Vec3(52, 30, 10)});
  s.boxes.push_back({Vec3(-52, -30, 0), Vec3(-50, 30, 7)});
  for (double x : {-30.0, -25.0, -20.0, 20.0, 25.0, 30.0}) {
    for (double y : {-4.0, 0.0, 4.0}) s.poles.push_back({x, y + 0.3 * x / 10.0, 0.3, 4.0});
  }
  s.boxes.push_back({Vec3(-3, -45, 0), Vec3(3, -35, 5)});
  return s;
}

// `stream` with a scan of lidar `id` every 0.1 s over [from_s, to_s) inserted at its arrival
// time, scanned from the lidar's true mount T_imu_lidar (which a test may set apart from the
// setup's).
inline std::vector<Measurement> WithScansOf(const Scenario& sc, std::vector<Measurement> stream,
                                            const std::string& id, const SE3& T_imu_lidar,
                                            double from_s, double to_s) {
  const Scene scene = Surroundings();
  ScannerModel model;
  model.columns = 360;
  for (double t = from_s; t < to_s - 1e-9; t += 0.1) {
    LidarScan scan;
    scan.header.sensor_id = id;
    scan.header.stamp_ns = FromSeconds(t);
    scan.header.arrival_ns = FromSeconds(t + 0.12);
    const auto pose = [&](double dt) {
      const NavState x = sc.Truth(FromSeconds(t + dt));
      return SE3(x.q_world_imu, x.p_world) * T_imu_lidar;
    };
    scan.points = std::make_shared<std::vector<LidarPoint>>(Scan(scene, pose, model));
    const auto at = std::find_if(stream.begin(), stream.end(), [&](const Measurement& m) {
      return HeaderOf(m).arrival_ns > scan.header.arrival_ns;
    });
    stream.insert(at, scan);
  }
  return stream;
}

// The scenario's stream with a scan of lidar_roof (kImuLidar) every 0.1 s over [from_s, to_s).
inline std::vector<Measurement> WithScans(const Scenario& sc, double from_s, double to_s) {
  return WithScansOf(sc, sc.stream, "lidar_roof", kImuLidar, from_s, to_s);
}

}  // namespace statebench::est::testing
