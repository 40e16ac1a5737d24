// StateInitializer::WaitingFor(): what a start still lacks, in one line for a user
// (state_initializer.hpp). Each part names the test that failed and its figures.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "estimator/state_initializer.hpp"

namespace statebench::est {
namespace {

std::string Format(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

std::string Join(const std::vector<std::string>& parts) {
  std::string out;
  for (const std::string& p : parts) out += (out.empty() ? "" : " and ") + p;
  return out;
}

}  // namespace

std::string StateInitializer::StillWaitingFor() const {
  const InitializationOptions& o = options_;
  std::string out = "no still period of " + Format("%g", o.static_duration_s) + " s";
  if (!still_record_.tested) {
    const double held_s = ToSeconds(imu_.back().header.stamp_ns - imu_.front().header.stamp_ns);
    return out + " (only " + Format("%.2f", held_s) + " s of IMU data)";
  }
  const StillRecord& r = still_record_;
  if (r.score <= 1.0) {  // the IMU was quiet at least once: the standstill was not proven
    switch (r.not_proven) {
      case NotProven::kFixesMoved:
        return out + " (the IMU was quiet but the GNSS fixes moved)";
      case NotProven::kFixesNoProof:
        return out + " (the IMU was quiet but the GNSS fixes did not bound the speed below " +
               Format("%g", o.static_max_speed_mps) + " m/s)";
      case NotProven::kOdometryMoving:
        return out + " (the IMU was quiet but the odometry did not read zero)";
      case NotProven::kNo:
        return out;
    }
  }
  std::vector<std::string> why;
  if (r.gyro_std > o.static_max_gyro_std_radps) {
    why.push_back("gyro std " + Format("%.3g", r.gyro_std) + " rad/s > " +
                  Format("%g", o.static_max_gyro_std_radps));
  }
  if (r.accel_std > o.static_max_accel_std_mps2) {
    why.push_back("accel std " + Format("%.3g", r.accel_std) + " m/s^2 > " +
                  Format("%g", o.static_max_accel_std_mps2));
  }
  if (r.gravity_error > kMaxStillGravityError) {
    why.push_back("| |f| - g | " + Format("%.3g", r.gravity_error) + " m/s^2 > " +
                  Format("%g", kMaxStillGravityError));
  }
  if (r.mean_rate > 10.0 * o.static_max_gyro_std_radps) {
    why.push_back("mean rate " + Format("%.3g", r.mean_rate) + " rad/s > " +
                  Format("%g", 10.0 * o.static_max_gyro_std_radps));
  }
  std::string detail;
  for (const std::string& w : why) detail += (detail.empty() ? "" : ", ") + w;
  return out + " (quietest window: " + detail + ")";
}

std::string StateInitializer::WaitingFor() const {
  if (imu_.empty()) return "no IMU sample";
  if (local_.enabled) return LocalWaitingFor();
  std::vector<std::string> missing;
  const bool may_use_still = options_.mode != InitializationMode::kMoving;
  // Without any fix a standstill cannot be proven: a quiet IMU then waits for the fix alone.
  const bool quiet_without_fixes =
      fixes_.empty() && still_record_.tested && still_record_.score <= 1.0;
  if (may_use_still && !still_ && !quiet_without_fixes) missing.push_back(StillWaitingFor());
  if (fixes_.empty()) {
    missing.push_back("no GNSS fix");
  } else if (!heading_ && !CourseReference()) {
    // The chord from the newest fix that comes closest to the length a course needs.
    const Fix& b = fixes_.back();
    double best_ratio = -1.0, best_length = 0.0, best_needed = 0.0;
    for (auto it = std::next(fixes_.rbegin()); it != fixes_.rend(); ++it) {
      const double sigma_h = std::sqrt(0.5 * (b.fix.covariance(0, 0) + b.fix.covariance(1, 1) +
                                              it->fix.covariance(0, 0) + it->fix.covariance(1, 1)));
      const double needed = std::max(options_.course_min_distance_m, 15.0 * sigma_h);
      const double length = (b.fix.p_enu - it->fix.p_enu).head<2>().norm();
      if (length / needed > best_ratio) {
        best_ratio = length / needed;
        best_length = length;
        best_needed = needed;
      }
    }
    std::string course = "no GNSS course or dual-antenna heading (" +
                         std::to_string(fixes_.size()) + (fixes_.size() == 1 ? " fix" : " fixes");
    if (best_ratio >= 0.0) {
      course += ", longest chord " + Format("%.3g", best_length) + " m of the " +
                Format("%.3g", best_needed) + " m needed";
    }
    missing.push_back(course + ")");
  }
  if (missing.empty()) {
    return still_ ? "a first state consistent with the yaw reference and the newest fix"
                  : "a moving start (three fixes of one antenna over 2 s or more)";
  }
  return Join(missing);
}

std::string StateInitializer::LocalWaitingFor() const {
  std::vector<std::string> missing;
  const InitializationMode mode = options_.mode;
  if (mode != InitializationMode::kMoving && !still_) missing.push_back(StillWaitingFor());
  if (mode != InitializationMode::kStatic) {
    if (!local_.has_odometry) {
      missing.push_back("no body-frame odometry in the setup for a moving start");
    } else if (odometry_.empty()) {
      missing.push_back("no odometry sample");
    } else if (fit_gravity_) {
      missing.push_back("no odometry fit agreeing with gravity (|g| " +
                        Format("%.3g", *fit_gravity_) + " m/s^2)");
    } else {
      const double span_s = ToSeconds(odometry_.back().t_ns - odometry_.front().t_ns);
      missing.push_back("odometry over " + Format("%.2f", span_s) + " s of the " +
                        Format("%g", kOdometryWindowS) + " s a moving start fits");
    }
  }
  if (missing.empty()) return "a first state in the local frame";
  return Join(missing) + (local_.enu_later
                              ? " (a local-frame start until the GNSS fixes can start it in ENU)"
                              : " (no GNSS antenna in the setup: a local-frame start)");
}

}  // namespace statebench::est
