// Robust ICP of a scan against the voxel-hash local map, with an information-based covariance
// and a degeneracy test.
//
// Pose and perturbation: T_map_scan maps scan points into the map; it is perturbed on the right,
// T = T_hat * Exp(xi), xi = (rho, phi) in the scan frame (core/se3.hpp ordering). For a scan point
// p with map correspondence q the residual r = T p - q has the Jacobian dr/dxi = R [I, -hat(p)].
// Each Gauss-Newton step solves (sum_i J_i^T W_i J_i) dx = -sum_i J_i^T W_i r_i with the
// Geman-McClure weight w(r) = k^4 / (k^2 + |r|^2)^2 (k the kernel scale, w(0) = 1), then
// T <- T Exp(dx); it stops when |dx| < convergence_dx.
//
// Metrics: kPointToPoint uses W_i = w_i I (KISS-ICP). kSurfaceProjected uses W_i = w_i P_i, where
// P_i projects on the directions in which the map is thin around q (the normal of a plane, the
// two directions across a pole), estimated from the map points around q; ambiguous or isolated
// neighbourhoods contribute nothing (see ThinProjector). It removes the pull of sparse lidar rings
// along the ground (the forward-motion under-estimate of plain point-to-point ICP).
//
// Covariance: whatever metric drove the iterations, the information is the geometric one,
// H = sum_i w_i J_i^T P_i J_i (a point-to-point Hessian is sum w I in translation whatever the
// geometry and cannot see degeneracy), and Cov = s^2 H^-1 with s^2 the weighted residual
// variance along the constrained directions (floored at min_residual_sigma). The eigen
// analysis is done on the scaled Hessian D^-1 H D^-1, D = diag(1, 1, 1, L, L, L) (a rotation phi
// is compared with the displacement L phi it causes at L = degeneracy_length).
//
// Degeneracy: with unit-weight correspondences, an eigenvalue of the scaled Hessian counts the
// point-equivalents that constrain its direction (a plane point facing a translation direction
// adds w (n.u)^2 <= 1). A direction with less than min_information of them gets the variance
// degenerate_variance (m^2 in scaled units) instead, and the result is flagged degenerate. The
// bound is absolute, not relative to the largest eigenvalue: far ground points make the scaled
// roll/pitch eigenvalue grow with (range / L)^2, and "below 0.003 times the largest" flagged
// 291 of 2400 setup-2 XT32 scans along z where 44-202 point-equivalents constrained it, while
// the synthetic corridor's axis sat at 0.0026 times the largest. It must stay above what
// sampling artifacts fake: in the synthetic corridor, neighbourhoods where one wall column
// meets one ground ring look like planes across the axis and give it 10-14 point-equivalents.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/eigen_types.hpp"
#include "core/se3.hpp"
#include "estimator/voxel_hash_map.hpp"

namespace statebench::est {

enum class IcpMetric { kPointToPoint, kSurfaceProjected };

struct IcpOptions {
  IcpMetric metric = IcpMetric::kSurfaceProjected;
  int max_iterations = 500;
  double convergence_dx = 1e-4;
  std::size_t min_correspondences = 50;
  double surface_radius_m = 1.0;
  double wide_surface_radius_m = 3.0;  // second look when the first neighbourhood is one ring
  // Local eigenvalue below thin_ratio times the largest: thin direction. A plane patch of radius
  // r spreads r^2 / 4 in-plane, so 0.02 accepts a thickness (noise plus the map's accumulated
  // misalignment) up to sigma = r sqrt(0.02) / 2 = 7 cm at r = 1 m. With 0.005 (3.5 cm) the
  // shuttle's two-VLP-16 map ground, blurred by a little pitch drift over a crest, read as a
  // blob and was dropped: z rested on 6-10 point-equivalents and the height drifted 2 m in 90 s.
  double thin_ratio = 0.02;
  double degeneracy_length_m = 5.0;
  double min_information = 15.0;  // point-equivalents per direction, see above
  double degenerate_variance = 100.0;
  double min_residual_sigma_m = 0.005;
};

struct IcpResult {
  bool ok = false;
  std::string failure;  // why ok is false
  SE3 T_map_scan;
  Mat6 covariance = Mat6::Identity();  // of xi (rho, phi), right perturbation of T_map_scan
  bool converged = false;
  int iterations = 0;
  std::size_t correspondences = 0;
  double residual_sigma_m = 0.0;
  bool degenerate = false;
  int degenerate_directions = 0;
  Vec6 scaled_eigenvalues = Vec6::Zero();       // of D^-1 H D^-1, ascending
  Mat6 scaled_eigenvectors = Mat6::Identity();  // columns, in scaled (rho, L phi) coordinates
};

IcpResult RegisterScanToMap(const std::vector<Vec3>& points_scan, const VoxelHashMap& map,
                            const SE3& T_map_scan_initial, double max_correspondence_m,
                            double kernel_scale_m, const IcpOptions& options);

}  // namespace statebench::est
