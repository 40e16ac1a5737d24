#include "estimator/linear_system.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>

namespace statebench::est {

void BlockLayout::Add(double* block, int ambient_size, const ceres::Manifold* manifold) {
  Entry e;
  e.offset = dimension_;
  e.ambient_size = ambient_size;
  e.tangent_size = manifold != nullptr ? manifold->TangentSize() : ambient_size;
  e.manifold = manifold;
  entries_[block] = e;
  dimension_ += e.tangent_size;
}

bool Linearize(const std::vector<const FactorRecord*>& factors, const BlockLayout& layout,
               LinearSystem* system) {
  using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const int n = layout.dimension();
  system->H = Eigen::MatrixXd::Zero(n, n);
  system->g = Eigen::VectorXd::Zero(n);
  system->num_skipped = 0;
  for (const FactorRecord* f : factors) {
    const int num_residuals = f->cost->num_residuals();
    const auto& sizes = f->cost->parameter_block_sizes();
    std::vector<RowMajorMatrix> ambient;
    std::vector<double*> jacobian_ptrs;
    for (int32_t s : sizes) ambient.emplace_back(num_residuals, s);
    for (auto& a : ambient) jacobian_ptrs.push_back(a.data());
    Eigen::VectorXd r(num_residuals);
    if (!f->cost->Evaluate(f->blocks.data(), r.data(), jacobian_ptrs.data())) {
      ++system->num_skipped;
      continue;
    }

    // Tangent Jacobian of the whole factor, laid out in the system's columns.
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(num_residuals, n);
    for (std::size_t b = 0; b < sizes.size(); ++b) {
      const BlockLayout::Entry& e = layout.At(f->blocks[b]);
      if (e.manifold != nullptr) {
        RowMajorMatrix plus(e.ambient_size, e.tangent_size);
        e.manifold->PlusJacobian(f->blocks[b], plus.data());
        J.middleCols(e.offset, e.tangent_size) += ambient[b] * plus;
      } else {
        J.middleCols(e.offset, e.tangent_size) += ambient[b];
      }
    }
    if (f->loss != nullptr) {
      double rho[3];
      f->loss->Evaluate(r.squaredNorm(), rho);
      const double w = std::sqrt(std::max(rho[1], 0.0));
      r *= w;
      J *= w;
    }
    if (!std::isfinite(r.squaredNorm()) || !J.allFinite()) {  // |r|^2 may overflow
      ++system->num_skipped;
      continue;
    }
    system->H.noalias() += J.transpose() * J;
    system->g.noalias() += J.transpose() * r;
  }
  return system->num_skipped == 0;
}

LinearSystem SchurComplement(const LinearSystem& system, int m) {
  const int k = static_cast<int>(system.g.size()) - m;
  const Eigen::MatrixXd H_mm =
      0.5 * (system.H.topLeftCorner(m, m) + system.H.topLeftCorner(m, m).transpose());
  const Eigen::MatrixXd H_km = system.H.bottomLeftCorner(k, m);
  // X = H_mm^-1 [H_mk, g_m]: Cholesky when H_mm is well conditioned, else the eigen pseudo-inverse.
  Eigen::MatrixXd rhs(m, k + 1);
  rhs << H_km.transpose(), system.g.head(m);
  Eigen::MatrixXd X;
  const Eigen::LLT<Eigen::MatrixXd> llt(H_mm);
  const Eigen::VectorXd d = H_mm.diagonal();
  const bool well_conditioned =
      llt.info() == Eigen::Success &&
      llt.matrixL().toDenseMatrix().diagonal().array().square().minCoeff() > 1e-10 * d.maxCoeff();
  if (well_conditioned) {
    X = llt.solve(rhs);
  } else {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(H_mm);
    const double threshold = 1e-12 * std::max(eig.eigenvalues().maxCoeff(), 0.0);
    const Eigen::VectorXd inv_values =
        eig.eigenvalues().unaryExpr([&](double l) { return l > threshold ? 1.0 / l : 0.0; });
    X = eig.eigenvectors() * inv_values.asDiagonal() * eig.eigenvectors().transpose() * rhs;
  }
  LinearSystem out;
  out.H = system.H.bottomRightCorner(k, k) - H_km * X.leftCols(k);
  out.H = 0.5 * (out.H + out.H.transpose());
  out.g = system.g.tail(k) - H_km * X.col(k);
  return out;
}

}  // namespace statebench::est
