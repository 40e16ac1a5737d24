#include "estimator/icp_registration.hpp"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_reduce.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace statebench::est {
namespace {

constexpr std::size_t kGrain = 256;

// Sum of J^T W J, J^T W r, r^T W r, sum of w * rank(W), over accepted correspondences.
struct NormalEquations {
  Mat6 H = Mat6::Zero();
  Vec6 g = Vec6::Zero();
  double weighted_sq = 0.0;
  double weighted_dof = 0.0;
  std::size_t count = 0;

  NormalEquations operator+(const NormalEquations& o) const {
    NormalEquations s;
    s.H = H + o.H;
    s.g = g + o.g;
    s.weighted_sq = weighted_sq + o.weighted_sq;
    s.weighted_dof = weighted_dof + o.weighted_dof;
    s.count = count + o.count;
    return s;
  }
};

// Eigen-decomposition of the spread of the map points within radius of q (ascending
// eigenvalues); false when fewer than 5 points.
bool LocalShape(const VoxelHashMap& map, const Vec3& q, double radius, std::vector<Vec3>* scratch,
                Eigen::SelfAdjointEigenSolver<Mat3>* eig) {
  map.NeighborsWithin(q, radius, scratch);
  if (scratch->size() < 5) return false;
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : *scratch) mean += p;
  mean /= static_cast<double>(scratch->size());
  // The six distinct sums of the scatter matrix, kept in registers (Eigen's C += d d^T went
  // through the stack at every point); each sum adds the same products in the same order.
  double cxx = 0.0, cxy = 0.0, cxz = 0.0, cyy = 0.0, cyz = 0.0, czz = 0.0;
  for (const Vec3& p : *scratch) {
    const double dx = p.x() - mean.x(), dy = p.y() - mean.y(), dz = p.z() - mean.z();
    cxx += dx * dx;
    cxy += dx * dy;
    cxz += dx * dz;
    cyy += dy * dy;
    cyz += dy * dz;
    czz += dz * dz;
  }
  Mat3 C;
  C << cxx, cxy, cxz, cxy, cyy, cyz, cxz, cyz, czz;
  eig->computeDirect(C);
  return true;
}

// Projector on the directions in which the map is thin around q (see header). A linear
// neighbourhood is most often one ring of a sparse lidar on the ground (rings lie metres apart
// there) or one azimuth column on a distant wall seen at grazing incidence: both would pull the
// scan along the sampling pattern, not the surface. It is looked at again over a wider radius
// to find the surface, and skipped (zero projector) when still linear, as are isolated points.
// (Thin poles far away are lost with them; near ones are sampled by several columns.)
Mat3 ThinProjector(const VoxelHashMap& map, const Vec3& q, const IcpOptions& options,
                   std::vector<Vec3>* scratch) {
  Eigen::SelfAdjointEigenSolver<Mat3> eig;
  for (const double radius : {options.surface_radius_m, options.wide_surface_radius_m}) {
    if (!LocalShape(map, q, radius, scratch, &eig)) continue;
    const Vec3 lambda = eig.eigenvalues();  // ascending
    const double thin = options.thin_ratio * lambda(2);
    if (lambda(1) <= thin) continue;  // linear
    Mat3 P = Mat3::Zero();
    for (int k = 0; k < 3; ++k) {
      if (lambda(k) <= thin) P += eig.eigenvectors().col(k) * eig.eigenvectors().col(k).transpose();
    }
    return P;  // zero when the neighbourhood is a blob: no thin direction
  }
  return Mat3::Zero();
}

// Thin projectors per source point, reused while its correspondence stays within a tenth of
// the surface radius of the one they were computed at (the local shape is the same there);
// each slot is written only by the task that owns its index.
struct ProjectorCache {
  explicit ProjectorCache(std::size_t n) : P(n), q(n), valid(n, 0), zero(n, 0), nearest(n) {}
  std::vector<Mat3> P;
  std::vector<Vec3> q;
  std::vector<char> valid;
  std::vector<char> zero;  // P is all zeros
  // Per source point, what its last correspondence search proved: the next iterations, whose
  // small pose steps move the point a few millimetres, mostly skip the search.
  std::vector<NearestNeighborProof> nearest;
};

// Normal equations at T. use_projector selects W = w P instead of w I.
NormalEquations Accumulate(const std::vector<Vec3>& points, const VoxelHashMap& map, const SE3& T,
                           double max_dist, double kernel, bool use_projector,
                           const IcpOptions& options, ProjectorCache* cache) {
  const double reuse2 = 0.01 * options.surface_radius_m * options.surface_radius_m;
  const Mat3 R = T.RotationMatrix();
  const Mat3 Rt = R.transpose();
  const double k2 = kernel * kernel;
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<std::size_t>(0, points.size(), kGrain), NormalEquations{},
      [&](const tbb::blocked_range<std::size_t>& range, NormalEquations acc) {
        std::vector<Vec3> scratch;
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          const Vec3& p = points[i];
          const Vec3 p_map = T * p;
          Vec3 q;
          double d = 0.0;
          if (!map.NearestNeighborFromProof(cache->nearest[i], p_map, &q, &d) &&
              !map.NearestNeighbor(p_map, &q, &d, &cache->nearest[i])) {
            continue;
          }
          if (d > max_dist) continue;
          const double w = k2 * k2 / ((k2 + d * d) * (k2 + d * d));
          // In the scan-frame rotated residual r_s = R^T r: J_s = [I, -hat(p)], W_s = R^T W R.
          const Vec3 r_s = Rt * (p_map - q);
          Mat3 W_s = Mat3::Identity();
          double dof = 3.0;
          if (use_projector) {
            if (!cache->valid[i] || (cache->q[i] - q).squaredNorm() > reuse2) {
              cache->P[i] = ThinProjector(map, q, options, &scratch);
              cache->q[i] = q;
              cache->valid[i] = 1;
              cache->zero[i] = (cache->P[i].array() == 0.0).all();
            }
            // A zero projector (no thin direction) adds only exact zeros (of either sign) to
            // H, g and the weighted sums, which change none of them: they start at +0 and a sum
            // is -0 only when both terms are. The correspondence still counts.
            if (cache->zero[i]) {
              ++acc.count;
              continue;
            }
            W_s = Rt * cache->P[i] * R;
            dof = W_s.trace();
          }
          // J = [I, N] with N = -hat(p): J^T W = [w W; w N^T W] and J^T W J = [J^T W, J^T W N],
          // without the products by the identity's ones and zeros (each entry is the same sum of
          // the same products, so the same bits as the full 6 x 3 and 6 x 6 products).
          const Mat3 N = -so3::Hat(p);
          Eigen::Matrix<double, 6, 3> JtW;
          JtW.topRows<3>() = w * W_s;
          JtW.bottomRows<3>() = (w * N.transpose()) * W_s;
          acc.H.leftCols<3>() += JtW;
          acc.H.rightCols<3>().noalias() += JtW * N;
          acc.g.noalias() += JtW * r_s;
          acc.weighted_sq += w * r_s.dot(W_s * r_s);
          acc.weighted_dof += w * dof;
          ++acc.count;
        }
        return acc;
      },
      [](const NormalEquations& a, const NormalEquations& b) { return a + b; });
}

void FillCovariance(const NormalEquations& eq, const IcpOptions& options, IcpResult* result) {
  const double L = options.degeneracy_length_m;
  Vec6 d_inv;
  d_inv << 1, 1, 1, 1 / L, 1 / L, 1 / L;
  const Mat6 H_scaled = d_inv.asDiagonal() * eq.H * d_inv.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Mat6> eig(H_scaled);
  const Vec6 lambda = eig.eigenvalues();
  const double dof = std::max(eq.weighted_dof - 6.0, 1.0);
  const double s2 =
      std::max(eq.weighted_sq / dof, options.min_residual_sigma_m * options.min_residual_sigma_m);
  Vec6 variance;
  int degenerate = 0;
  for (int k = 0; k < 6; ++k) {
    if (!(lambda(k) >= options.min_information)) {
      variance(k) = std::max(options.degenerate_variance, lambda(k) > 0 ? s2 / lambda(k) : 0.0);
      ++degenerate;
    } else {
      variance(k) = s2 / lambda(k);
    }
  }
  const Mat6 V = eig.eigenvectors();
  const Mat6 cov_scaled = V * variance.asDiagonal() * V.transpose();
  result->covariance = d_inv.asDiagonal() * cov_scaled * d_inv.asDiagonal();
  result->residual_sigma_m = std::sqrt(s2);
  result->degenerate_directions = degenerate;
  result->degenerate = degenerate > 0;
  result->scaled_eigenvalues = lambda;
  result->scaled_eigenvectors = V;
}

}  // namespace

IcpResult RegisterScanToMap(const std::vector<Vec3>& points_scan, const VoxelHashMap& map,
                            const SE3& T_map_scan_initial, double max_correspondence_m,
                            double kernel_scale_m, const IcpOptions& options) {
  IcpResult result;
  result.T_map_scan = T_map_scan_initial;
  if (map.Empty()) {
    result.failure = "empty map";
    return result;
  }
  const bool projected = options.metric == IcpMetric::kSurfaceProjected;
  ProjectorCache cache(points_scan.size());
  for (int it = 0; it < options.max_iterations; ++it) {
    const NormalEquations eq = Accumulate(points_scan, map, result.T_map_scan, max_correspondence_m,
                                          kernel_scale_m, projected, options, &cache);
    result.iterations = it + 1;
    result.correspondences = eq.count;
    if (eq.count < options.min_correspondences) {
      result.failure = "too few correspondences (" + std::to_string(eq.count) + " < " +
                       std::to_string(options.min_correspondences) + ")";
      return result;
    }
    // The projected metric leaves directions unconstrained when the scene is degenerate; a
    // tiny damping keeps the step there at zero (the prediction is kept).
    const Vec6 dx = -(eq.H + 1e-9 * eq.H.trace() * Mat6::Identity()).ldlt().solve(eq.g);
    result.T_map_scan = result.T_map_scan * SE3::Exp(dx);
    if (dx.norm() < options.convergence_dx) {
      result.converged = true;
      break;
    }
  }
  const NormalEquations info = Accumulate(points_scan, map, result.T_map_scan, max_correspondence_m,
                                          kernel_scale_m, true, options, &cache);
  result.correspondences = info.count;
  FillCovariance(info, options, &result);
  result.ok = true;
  return result;
}

}  // namespace statebench::est
