#include "simulator/terrain.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "simulator/quintic_bspline.hpp"

namespace statebench::sim {
namespace {

constexpr int kWindow = 2 * kQuinticOrder - 1;  // coefficient offsets -5..5 share a point

void CheckOptions(const TerrainOptions& o) {
  if (!(o.grid_spacing_m > 0.0) || !(o.polyline_step_m > 0.0) || !(o.ridge > 0.0) ||
      !(o.curvature_penalty >= 0.0)) {
    throw InputError(
        "terrain options: grid_spacing_m, polyline_step_m and ridge must be positive, "
        "curvature_penalty >= 0");
  }
}

// Segment index and local parameter of coordinate v on a grid starting at v0, spacing d.
inline int Segment(double v, double v0, double d, double* tau) {
  const double t = (v - v0) / d;
  const double k = std::floor(t);
  *tau = t - k;
  return static_cast<int>(k);
}

}  // namespace

Terrain Terrain::Fit(const std::vector<Vec3>& points, const TerrainOptions& options) {
  CheckOptions(options);
  if (points.empty()) throw InputError("terrain: no road points to fit the elevation to");
  double sum_z = 0.0;
  Vec2 lo = points.front().head<2>();
  Vec2 hi = lo;
  for (const Vec3& p : points) {
    if (!p.allFinite()) throw InputError("terrain: road point with a non-finite coordinate");
    sum_z += p.z();
    lo = lo.cwiseMin(p.head<2>());
    hi = hi.cwiseMax(p.head<2>());
  }
  const double base = sum_z / static_cast<double>(points.size());
  double max_dev = 0.0;
  for (const Vec3& p : points) max_dev = std::max(max_dev, std::abs(p.z() - base));
  Terrain t(base);
  if (max_dev < 1e-9) return t;

  // Grid: one spacing of margin around the points; segment k uses coefficients k .. k + 5.
  const double d = options.grid_spacing_m;
  t.spacing_m_ = d;
  t.x0_m_ = std::floor(lo.x() / d) * d - d;
  t.y0_m_ = std::floor(lo.y() / d) * d - d;
  t.nx_ = static_cast<int>(std::floor((hi.x() - t.x0_m_) / d)) + 1 + kQuinticOrder;
  t.ny_ = static_cast<int>(std::floor((hi.y() - t.y0_m_) / d)) + 1 + kQuinticOrder;
  const int n = t.nx_ * t.ny_;

  // Data normal equations A^T A, stored per coefficient over the 11 x 11 window of
  // coefficients it can share a point with, and A^T (z - h0).
  std::vector<double> ata(static_cast<std::size_t>(n) * kWindow * kWindow, 0.0);
  std::vector<double> atb(n, 0.0);
  double basis_x[1][kQuinticOrder];
  double basis_y[1][kQuinticOrder];
  const double* bx = basis_x[0];
  const double* by = basis_y[0];
  for (const Vec3& p : points) {
    double tx = 0.0;
    double ty = 0.0;
    const int kx = Segment(p.x(), t.x0_m_, d, &tx);
    const int ky = Segment(p.y(), t.y0_m_, d, &ty);
    QuinticBasis(tx, 0, basis_x);
    QuinticBasis(ty, 0, basis_y);
    const double r = p.z() - base;
    for (int ja = 0; ja < kQuinticOrder; ++ja) {
      for (int ia = 0; ia < kQuinticOrder; ++ia) {
        const int a = (ky + ja) * t.nx_ + kx + ia;
        const double fa = bx[ia] * by[ja];
        atb[a] += fa * r;
        double* row = &ata[static_cast<std::size_t>(a) * kWindow * kWindow];
        for (int jb = 0; jb < kQuinticOrder; ++jb) {
          for (int ib = 0; ib < kQuinticOrder; ++ib) {
            row[(jb - ja + kQuinticOrder - 1) * kWindow + (ib - ia + kQuinticOrder - 1)] +=
                fa * bx[ib] * by[jb];
          }
        }
      }
    }
  }

  double diag_sum = 0.0;
  constexpr int kCentre = (kQuinticOrder - 1) * kWindow + kQuinticOrder - 1;
  for (int a = 0; a < n; ++a)
    diag_sum += ata[static_cast<std::size_t>(a) * kWindow * kWindow + kCentre];
  const double scale = diag_sum / n;
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::VectorXd rhs(n);
  for (int a = 0; a < n; ++a) {
    rhs[a] = atb[a];
    triplets.emplace_back(a, a, options.ridge * scale);
    const double* row = &ata[static_cast<std::size_t>(a) * kWindow * kWindow];
    for (int dj = 0; dj < kWindow; ++dj) {
      for (int di = 0; di < kWindow; ++di) {
        const double v = row[dj * kWindow + di];
        if (v == 0.0) continue;
        triplets.emplace_back(a, a + (dj - kQuinticOrder + 1) * t.nx_ + di - kQuinticOrder + 1, v);
      }
    }
  }
  // Penalty on second differences c_{i-1} - 2 c_i + c_{i+1} along x and along y.
  const double c = options.curvature_penalty * scale;
  for (int j = 0; j < t.ny_; ++j) {
    for (int i = 0; i < t.nx_; ++i) {
      const int a = j * t.nx_ + i;
      for (const auto& [step, inside] :
           {std::pair{1, i > 0 && i + 1 < t.nx_}, std::pair{t.nx_, j > 0 && j + 1 < t.ny_}}) {
        if (!inside) continue;
        const int ids[3] = {a - step, a, a + step};
        const double coef[3] = {1.0, -2.0, 1.0};
        for (int p = 0; p < 3; ++p) {
          for (int q = 0; q < 3; ++q) triplets.emplace_back(ids[p], ids[q], c * coef[p] * coef[q]);
        }
      }
    }
  }
  Eigen::SparseMatrix<double> normal(n, n);
  normal.setFromTriplets(triplets.begin(), triplets.end());
  // Conjugate gradients (Jacobi preconditioned) scale to large networks far better than a
  // sparse Cholesky of this 2D stencil; the direct solver is the fallback.
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg;
  cg.setTolerance(1e-10);
  cg.setMaxIterations(20 * n);
  cg.compute(normal);
  Eigen::VectorXd x = cg.solve(rhs);
  if (cg.info() != Eigen::Success) {
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(normal);
    if (ldlt.info() != Eigen::Success) {
      throw InputError("terrain: elevation fit failed (degenerate road points)");
    }
    x = ldlt.solve(rhs);
  }
  t.coefficients_.assign(x.data(), x.data() + n);
  return t;
}

Terrain Terrain::FitPolylines(const std::vector<std::vector<Vec3>>& polylines,
                              const TerrainOptions& options) {
  CheckOptions(options);
  std::vector<Vec3> points;
  for (const auto& line : polylines) {
    if (line.empty()) continue;
    points.push_back(line.front());
    for (std::size_t i = 1; i < line.size(); ++i) {
      const Vec3& a = line[i - 1];
      const Vec3& b = line[i];
      const int steps = std::max(
          1, static_cast<int>(std::ceil((b - a).head<2>().norm() / options.polyline_step_m)));
      for (int s = 1; s <= steps; ++s) points.push_back(a + (b - a) * (double(s) / steps));
    }
  }
  return Fit(points, options);
}

TerrainSample Terrain::Evaluate(double x_m, double y_m, int order) const {
  TerrainSample out;
  out.h = base_m_;
  if (coefficients_.empty()) return out;
  double tx = 0.0;
  double ty = 0.0;
  const int kx = Segment(x_m, x0_m_, spacing_m_, &tx);
  const int ky = Segment(y_m, y0_m_, spacing_m_, &ty);
  if (kx + kQuinticOrder <= 0 || kx >= nx_ || ky + kQuinticOrder <= 0 || ky >= ny_) return out;
  // Basis values and derivatives in x and y (per metre: d/dx = (1/d) d/dtau).
  double bx[4][kQuinticOrder];
  double by[4][kQuinticOrder];
  QuinticBasis(tx, order, bx);
  QuinticBasis(ty, order, by);
  double inv_d = 1.0;
  for (int r = 0; r <= order; ++r) {
    for (int m = 0; m < kQuinticOrder; ++m) {
      bx[r][m] *= inv_d;
      by[r][m] *= inv_d;
    }
    inv_d /= spacing_m_;
  }
  // g[r][m]: sum over i of c_{m,i} d^r/dx^r N_i, for the six rows m in y.
  double g[4][kQuinticOrder] = {};
  for (int m = 0; m < kQuinticOrder; ++m) {
    const int j = ky + m;
    if (j < 0 || j >= ny_) continue;
    for (int i_off = 0; i_off < kQuinticOrder; ++i_off) {
      const int i = kx + i_off;
      if (i < 0 || i >= nx_) continue;
      const double coef = coefficients_[static_cast<std::size_t>(j) * nx_ + i];
      for (int r = 0; r <= order; ++r) g[r][m] += coef * bx[r][i_off];
    }
  }
  // h_{x^r y^q} = sum_m g[r][m] by[q][m].
  auto partial = [&](int r, int q) {
    double s = 0.0;
    for (int m = 0; m < kQuinticOrder; ++m) s += g[r][m] * by[q][m];
    return s;
  };
  out.h += partial(0, 0);
  if (order >= 1) out.gradient = Vec2(partial(1, 0), partial(0, 1));
  if (order >= 2) {
    out.hessian << partial(2, 0), partial(1, 1), partial(1, 1), partial(0, 2);
  }
  if (order >= 3) out.third = Vec4(partial(3, 0), partial(2, 1), partial(1, 2), partial(0, 3));
  return out;
}

Vec3 Terrain::Normal(double x_m, double y_m) const {
  const Vec2 g = Evaluate(x_m, y_m, 1).gradient;
  return Vec3(-g.x(), -g.y(), 1.0).normalized();
}

}  // namespace statebench::sim
