#include "simulator/path.hpp"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "simulator/quintic_bspline.hpp"

namespace statebench::sim {
namespace {

constexpr int kTableSubdivisions = 8;  // arc-length table entries per knot segment
constexpr double kGapWeight =
    1e-6;  // data weight inside a corner gap  // arc-length table entries per knot segment
// 3-point Gauss-Legendre on [0, 1]: exact for polynomials of degree 5.
constexpr double kGaussT[3] = {0.5 - 0.3872983346207417, 0.5, 0.5 + 0.3872983346207417};
constexpr double kGaussW[3] = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};

double Cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

std::vector<Vec2> CleanPolyline(const std::vector<Vec3>& polyline) {
  std::vector<Vec2> out;
  for (const Vec3& p : polyline) {
    if (!p.allFinite()) throw InputError("route polyline: non-finite coordinate");
    if (out.empty() || (p.head<2>() - out.back()).norm() > 1e-3) out.push_back(p.head<2>());
  }
  if (out.size() < 2) throw InputError("route polyline: fewer than two distinct points");
  return out;
}

// G[a][b] = int_0^1 B_a''(tau) B_b''(tau) dtau (the integrand has degree 6: 4-point Gauss).
std::array<std::array<double, kQuinticOrder>, kQuinticOrder> SecondDerivativeGram() {
  constexpr double t[4] = {0.0694318442029737, 0.3300094782075719, 0.6699905217924281,
                           0.9305681557970263};
  constexpr double w[4] = {0.1739274225687269, 0.3260725774312731, 0.3260725774312731,
                           0.1739274225687269};
  std::array<std::array<double, kQuinticOrder>, kQuinticOrder> g{};
  for (int q = 0; q < 4; ++q) {
    double b[3][kQuinticOrder];
    QuinticBasis(t[q], 2, b);
    for (int a = 0; a < kQuinticOrder; ++a) {
      for (int c = 0; c < kQuinticOrder; ++c) g[a][c] += w[q] * b[2][a] * b[2][c];
    }
  }
  return g;
}

}  // namespace

Path Path::Build(const std::vector<Vec3>& polyline, const PathOptions& options) {
  if (!(options.knot_spacing_m > 0.0) || !(options.sample_spacing_m > 0.0) ||
      !(options.smoothing_length_m > 0.0) || !(options.max_curvature_1pm > 0.0)) {
    throw InputError("path options: spacings, smoothing length and max curvature must be > 0");
  }
  Path path;
  path.raw_ = CleanPolyline(polyline);
  std::vector<double> raw_s(path.raw_.size(), 0.0);
  for (std::size_t i = 1; i < path.raw_.size(); ++i) {
    raw_s[i] = raw_s[i - 1] + (path.raw_[i] - path.raw_[i - 1]).norm();
  }
  const double length = raw_s.back();
  path.raw_length_m_ = length;
  path.segments_ = std::max(1, static_cast<int>(std::lround(length / options.knot_spacing_m)));
  path.knot_m_ = length / path.segments_;
  const double h = path.knot_m_;
  const int n = path.segments_ + kQuinticOrder - 1;

  // Samples of the raw polyline at uniform raw arc length (u_i, p_i).
  const int samples = std::max(2 * path.segments_ + 1,
                               static_cast<int>(std::ceil(length / options.sample_spacing_m)) + 1);
  std::vector<double> sample_u(samples);
  std::vector<Vec2> sample_p(samples);
  std::size_t seg = 0;
  for (int i = 0; i < samples; ++i) {
    const double u = length * i / (samples - 1);
    while (seg + 2 < raw_s.size() && raw_s[seg + 1] < u) ++seg;
    const double a = (u - raw_s[seg]) / (raw_s[seg + 1] - raw_s[seg]);
    sample_u[i] = u;
    sample_p[i] = path.raw_[seg] + std::clamp(a, 0.0, 1.0) * (path.raw_[seg + 1] - path.raw_[seg]);
  }

  // Data weights: 1, or ~0 inside "gaps" where the raw polyline turns faster than the vehicle
  // can; across a gap the spline is the smoothest bridge between the lanes on either side.
  std::vector<double> weight(samples, 1.0);
  const auto gram = SecondDerivativeGram();
  const double rho = (samples - 1) / length;
  // int |r''(u)|^2 du over a segment = h^-3 int |d2r/dtau2|^2 dtau.
  const double penalty = rho * std::pow(options.smoothing_length_m, 4) / (h * h * h);
  const int grow = std::max(1, static_cast<int>(std::lround(options.gap_growth_m * rho)));
  for (int iteration = 0;; ++iteration) {
    std::vector<Eigen::Triplet<double>> triplets;
    Eigen::VectorXd rhs_x = Eigen::VectorXd::Zero(n);
    Eigen::VectorXd rhs_y = Eigen::VectorXd::Zero(n);
    for (int i = 0; i < samples; ++i) {
      const double t = sample_u[i] / h;
      const int k = std::min(path.segments_ - 1, static_cast<int>(std::floor(t)));
      double basis[1][kQuinticOrder];
      QuinticBasis(t - k, 0, basis);
      const double* b = basis[0];
      for (int a = 0; a < kQuinticOrder; ++a) {
        rhs_x[k + a] += weight[i] * b[a] * sample_p[i].x();
        rhs_y[k + a] += weight[i] * b[a] * sample_p[i].y();
        for (int c = 0; c < kQuinticOrder; ++c) {
          triplets.emplace_back(k + a, k + c, weight[i] * b[a] * b[c]);
        }
      }
    }
    for (int k = 0; k < path.segments_; ++k) {
      for (int a = 0; a < kQuinticOrder; ++a) {
        for (int c = 0; c < kQuinticOrder; ++c) {
          triplets.emplace_back(k + a, k + c, penalty * gram[a][c]);
        }
      }
    }
    Eigen::SparseMatrix<double> normal(n, n);
    normal.setFromTriplets(triplets.begin(), triplets.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(normal);
    if (solver.info() != Eigen::Success) throw InputError("route polyline: smoothing failed");
    const Eigen::VectorXd cx = solver.solve(rhs_x);
    const Eigen::VectorXd cy = solver.solve(rhs_y);
    path.poly_.assign(path.segments_, {});
    for (int k = 0; k < path.segments_; ++k) {
      for (int i = 0; i < kQuinticOrder; ++i) {
        Vec2 c = Vec2::Zero();
        for (int j = 0; j < kQuinticOrder; ++j) {
          c += kQuinticPowerMatrix[i][j] * Vec2(cx[k + j], cy[k + j]);
        }
        path.poly_[k][i] = c;
      }
    }
    if (iteration + 1 >= options.max_iterations) break;

    // Where the curvature exceeds the limit, open a gap in the data or widen the gap there.
    std::vector<double> next = weight;
    bool violated = false;
    for (int i = 0; i < samples; ++i) {
      const Derivatives d = path.Eval(sample_u[i], 2);
      const double speed = d.d1.norm();
      if (std::abs(Cross(d.d1, d.d2)) <= options.max_curvature_1pm * speed * speed * speed) {
        continue;
      }
      violated = true;
      int lo = i;
      int hi = i;
      while (lo > 0 && weight[lo - 1] < 1.0) --lo;
      while (hi + 1 < samples && weight[hi + 1] < 1.0) ++hi;
      for (int j = std::max(0, lo - grow); j <= std::min(samples - 1, hi + grow); ++j) {
        next[j] = kGapWeight;
      }
    }
    if (!violated) break;
    weight = next;
  }

  // Arc-length table S(u_k), u_k = k h / 8, by 3-point Gauss on each sub-interval.
  path.table_step_m_ = h / kTableSubdivisions;
  const int entries = path.segments_ * kTableSubdivisions + 1;
  path.arc_.assign(entries, 0.0);
  for (int k = 1; k < entries; ++k) {
    double piece = 0.0;
    for (int g = 0; g < 3; ++g) {
      piece += kGaussW[g] * path.SpeedAt((k - 1 + kGaussT[g]) * path.table_step_m_);
    }
    path.arc_[k] = path.arc_[k - 1] + piece * path.table_step_m_;
  }
  return path;
}

Path::Derivatives Path::Eval(double u, int order) const {
  const double t = std::clamp(u, 0.0, raw_length_m_) / knot_m_;
  const int k = std::clamp(static_cast<int>(std::floor(t)), 0, segments_ - 1);
  const double tau = t - k;
  const std::array<Vec2, kQuinticOrder>& c = poly_[k];
  // Horner on the polynomial and its derivatives in tau, then d/du = (1/h) d/dtau.
  Derivatives out;
  out.r = c[0] + tau * (c[1] + tau * (c[2] + tau * (c[3] + tau * (c[4] + tau * c[5]))));
  if (order < 1) return out;
  const double inv_h = 1.0 / knot_m_;
  out.d1 =
      (c[1] + tau * (2.0 * c[2] + tau * (3.0 * c[3] + tau * (4.0 * c[4] + tau * 5.0 * c[5])))) *
      inv_h;
  if (order < 2) return out;
  out.d2 =
      (2.0 * c[2] + tau * (6.0 * c[3] + tau * (12.0 * c[4] + tau * 20.0 * c[5]))) * (inv_h * inv_h);
  if (order < 3) return out;
  out.d3 = (6.0 * c[3] + tau * (24.0 * c[4] + tau * 60.0 * c[5])) * (inv_h * inv_h * inv_h);
  return out;
}

double Path::ArcAt(double u) const {
  const double uc = std::clamp(u, 0.0, raw_length_m_);
  const int k =
      std::min(static_cast<int>(arc_.size()) - 2, static_cast<int>(std::floor(uc / table_step_m_)));
  const double u0 = k * table_step_m_;
  const double du = uc - u0;
  double piece = 0.0;
  for (int g = 0; g < 3; ++g) piece += kGaussW[g] * SpeedAt(u0 + kGaussT[g] * du);
  return arc_[k] + piece * du;
}

double Path::ParamAt(double s) const {
  const double sc = std::clamp(s, 0.0, length_m());
  const auto it = std::upper_bound(arc_.begin(), arc_.end(), sc);
  const int k =
      std::clamp(static_cast<int>(it - arc_.begin()) - 1, 0, static_cast<int>(arc_.size()) - 2);
  // Linear start inside the table interval, then Newton on S(u) = s (S' = |r'| > 0).
  const double a = (sc - arc_[k]) / (arc_[k + 1] - arc_[k]);
  double u = (k + a) * table_step_m_;
  for (int i = 0; i < 4; ++i) {
    const double step = (ArcAt(u) - sc) / SpeedAt(u);
    u = std::clamp(u - step, 0.0, raw_length_m_);
    if (std::abs(step) < 1e-13) break;
  }
  return u;
}

PathPoint Path::At(double s_m) const {
  PathPoint out;
  const double len = length_m();
  const double sc = std::clamp(s_m, 0.0, len);
  const Derivatives d = Eval(ParamAt(sc), 3);
  const double speed = d.d1.norm();
  const Vec2 tangent = d.d1 / speed;
  out.position = d.r + (s_m - sc) * tangent;
  out.heading_rad = std::atan2(tangent.y(), tangent.x());
  if (s_m != sc) return out;  // straight extension
  // kappa = (r' x r'') / |r'|^3 and its derivative in u, divided by |r'| for d/ds.
  const double c = Cross(d.d1, d.d2);
  const double speed2 = speed * speed;
  out.curvature_1pm = c / (speed2 * speed);
  const double dkappa_du =
      (Cross(d.d1, d.d3) * speed2 - 3.0 * c * d.d1.dot(d.d2)) / (speed2 * speed2 * speed);
  out.curvature_rate_1pm2 = dkappa_du / speed;
  return out;
}

Vec2 Path::Position(double s_m) const {
  const double len = length_m();
  const double sc = std::clamp(s_m, 0.0, len);
  const Derivatives d = Eval(ParamAt(sc), sc == s_m ? 0 : 1);
  if (sc == s_m) return d.r;
  return d.r + (s_m - sc) * d.d1.normalized();
}

PathProjection Path::ProjectFrom(const Vec2& p, double u) const {
  // Newton on g(u) = (r(u) - p) . r'(u) = 0, g' = |r'|^2 + (r - p) . r''; steps at most one
  // knot so the iteration stays on the local branch.
  for (int i = 0; i < 30; ++i) {
    const Derivatives d = Eval(u, 2);
    const Vec2 e = d.r - p;
    const double g = e.dot(d.d1);
    double gp = d.d1.squaredNorm() + e.dot(d.d2);
    if (gp <= 0.0) gp = d.d1.squaredNorm();
    const double step = std::clamp(g / gp, -knot_m_, knot_m_);
    const double next = std::clamp(u - step, 0.0, raw_length_m_);
    const bool done = std::abs(next - u) < 1e-9;
    u = next;
    if (done) break;
  }
  const Derivatives d = Eval(u, 1);
  const Vec2 tangent = d.d1.normalized();
  const Vec2 e = p - d.r;
  PathProjection out;
  out.lateral_m = Cross(tangent, e);
  out.s_m = ArcAt(u);
  out.raw_s_m = u;
  // Before the start or after the end: along the straight extension.
  if (u <= 0.0 || u >= raw_length_m_) out.s_m += tangent.dot(e);
  return out;
}

PathProjection Path::Project(const Vec2& p, const PathProjection& hint) const {
  return ProjectFrom(p, hint.raw_s_m);
}

PathProjection Path::HintAt(double s_m) const {
  PathProjection out;
  out.s_m = s_m;
  out.raw_s_m = ParamAt(s_m);
  return out;
}

Vec2 Path::PositionAtRaw(double s_raw_m) const {
  const double uc = std::clamp(s_raw_m, 0.0, raw_length_m_);
  if (uc == s_raw_m) return Eval(uc, 0).r;
  const Derivatives d = Eval(uc, 1);
  return d.r + (s_raw_m - uc) * d.d1.normalized();
}

PathProjection Path::Project(const Vec2& p) const {
  double best_u = 0.0;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < arc_.size(); ++k) {
    const double u = k * table_step_m_;
    const double d2 = (Eval(u, 0).r - p).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best_u = u;
    }
  }
  return ProjectFrom(p, best_u);
}

RawToPath Path::FromRaw(double s_raw_m) const {
  RawToPath out;
  const double uc = std::clamp(s_raw_m, 0.0, raw_length_m_);
  const Derivatives d = Eval(uc, 2);
  const double speed = d.d1.norm();
  out.s_m = ArcAt(uc) + (s_raw_m - uc);  // unit speed beyond the ends
  if (uc != s_raw_m) return out;
  out.ds_draw = speed;
  out.d2s_draw2 = d.d1.dot(d.d2) / speed;
  return out;
}

}  // namespace statebench::sim
