#include "estimator/gnss_stamp_group.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>

#include "estimator/measurement_gate.hpp"

namespace statebench::est {

StampGroup GroupStamp(const std::map<std::string, GnssPositionEnu>& fixes,
                      const std::map<std::string, DualAntennaHeading>& headings,
                      const EstimatorSensorSetup& setup) {
  StampGroup out;
  for (const DualAntennaPair& pair : setup.dual_antennas) {
    const auto main = fixes.find(pair.main);
    const auto aux = fixes.find(pair.aux);
    const bool both = main != fixes.end() && aux != fixes.end();
    const Vec3 baseline = pair.p_imu_aux - pair.p_imu_main;
    if (const auto h = headings.find(pair.heading_id); h != headings.end()) {
      out.headings.push_back({h->second, baseline, pair.heading_id});
    } else if (both) {
      const std::string id = pair.heading_id.empty() ? pair.main + "+" + pair.aux : pair.heading_id;
      out.headings.push_back({HeadingFromFixes(main->second, aux->second, id), baseline, id});
    } else {
      continue;
    }
    if (both) out.merged.push_back(pair.aux);
  }
  for (const auto& [id, fix] : fixes) {
    if (std::find(out.merged.begin(), out.merged.end(), id) != out.merged.end()) continue;
    out.positions.push_back({fix, setup.FindAntenna(id)->p_imu_antenna});
  }
  return out;
}

Mat3 AntennaCovariance(const GnssAntenna& antenna, const Mat3& reported) {
  Mat3 C = antenna.covariance_scale * 0.5 * (reported + reported.transpose());
  if (antenna.min_sigma_m > 0.0) {
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(C);
    const Vec3 floored = eig.eigenvalues().cwiseMax(antenna.min_sigma_m * antenna.min_sigma_m);
    C = eig.eigenvectors() * floored.asDiagonal() * eig.eigenvectors().transpose();
  }
  return 0.5 * (C + C.transpose());
}

}  // namespace statebench::est
