#include "estimator/gnss_enu.hpp"

#include <Eigen/Cholesky>
#include <cmath>

namespace statebench::est {
namespace {

std::optional<GnssPositionEnu> Reject(const GnssFix& fix, const std::string& reason,
                                      std::string* why) {
  if (why != nullptr) {
    *why = "gnss fix '" + fix.header.sensor_id + "' at " + std::to_string(fix.header.stamp_ns) +
           " ns: " + reason;
  }
  return std::nullopt;
}

}  // namespace

std::optional<GnssPositionEnu> GnssFixToEnu(const GnssFix& fix, const LocalEnuFrame& frame,
                                            std::string* why) {
  if (fix.status == GnssFixStatus::kNone) return Reject(fix, "no fix", why);
  if (!std::isfinite(fix.latitude_deg) || !std::isfinite(fix.longitude_deg) ||
      !std::isfinite(fix.altitude_m)) {
    return Reject(fix, "non-finite position", why);
  }
  if (std::abs(fix.latitude_deg) > 90.0 || std::abs(fix.longitude_deg) > 180.0 ||
      fix.altitude_m < -1000.0 || fix.altitude_m > 100000.0) {
    return Reject(fix, "position out of range", why);
  }
  const Mat3& cov = fix.covariance_enu;
  if (!cov.allFinite()) return Reject(fix, "non-finite covariance", why);
  if ((cov - cov.transpose()).cwiseAbs().maxCoeff() > 1e-9 * cov.cwiseAbs().maxCoeff()) {
    return Reject(fix, "covariance is not symmetric", why);
  }
  if (Eigen::LLT<Mat3>(cov).info() != Eigen::Success) {
    return Reject(fix, "covariance is not positive definite", why);
  }
  GnssPositionEnu out;
  out.header = fix.header;
  out.p_enu = frame.ToEnu({fix.latitude_deg, fix.longitude_deg, fix.altitude_m});
  out.covariance = 0.5 * (cov + cov.transpose());
  out.status = fix.status;
  if (fix.velocity && fix.velocity->v_enu.allFinite() && fix.velocity->sigma_enu.allFinite() &&
      (fix.velocity->sigma_enu.array() > 0.0).all()) {
    out.velocity = fix.velocity;
  }
  return out;
}

}  // namespace statebench::est
