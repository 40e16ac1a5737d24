#include "estimator/bordered_chain.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>

namespace statebench::est {
namespace {

using BorderBlock = Eigen::Matrix<double, 15, Eigen::Dynamic>;

// Pseudo-inverse of a small symmetric matrix (eigenvalues below 1e-12 of the largest dropped).
Eigen::MatrixXd SymmetricPseudoInverse(const Eigen::MatrixXd& A) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (A + A.transpose()));
  const double threshold = 1e-12 * std::max(eig.eigenvalues().maxCoeff(), 0.0);
  const Eigen::VectorXd inv =
      eig.eigenvalues().unaryExpr([&](double l) { return l > threshold ? 1.0 / l : 0.0; });
  return eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace

bool SolveBorderedChain(const ChainSystem& system, const std::vector<Vec15>& damping,
                        const Eigen::VectorXd& global_damping, std::vector<Vec15>* dx,
                        Eigen::VectorXd* dx_global) {
  const int num_globals = system.num_globals();
  if (num_globals == 0) {
    dx_global->resize(0);
    return SolveChain(system, damping, dx);
  }
  ChainFactorization f;
  if (!FactorChain(system, damping, &f)) return false;
  const std::size_t n = system.D.size();
  std::vector<Vec15> rhs(n), y;
  for (std::size_t k = 0; k < n; ++k) rhs[k] = -system.g[k];
  SolveFactoredChain(f, rhs, &y);
  std::vector<BorderBlock> X(n, BorderBlock(15, num_globals));
  std::vector<Vec15> column;
  for (int j = 0; j < num_globals; ++j) {
    for (std::size_t k = 0; k < n; ++k) rhs[k] = system.C[k].col(j);
    SolveFactoredChain(f, rhs, &column);
    for (std::size_t k = 0; k < n; ++k) X[k].col(j) = column[k];
  }
  Eigen::MatrixXd schur = system.E;
  schur.diagonal() += global_damping;
  Eigen::VectorXd b = -system.g_global;
  for (std::size_t k = 0; k < n; ++k) {
    schur.noalias() -= system.C[k].transpose() * X[k];
    b.noalias() -= system.C[k].transpose() * y[k];
  }
  const Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (schur + schur.transpose()));
  if (llt.info() != Eigen::Success) return false;
  *dx_global = llt.solve(b);
  dx->resize(n);
  for (std::size_t k = 0; k < n; ++k) (*dx)[k] = y[k] - X[k] * *dx_global;
  return true;
}

double BorderedChainQuadratic(const ChainSystem& s, const std::vector<Vec15>& dx,
                              const Eigen::VectorXd& dx_global) {
  double out = 0.0;
  for (std::size_t k = 0; k < dx.size(); ++k) {
    out += dx[k].dot(s.D[k] * dx[k]);
    if (k + 1 < dx.size()) out += 2.0 * dx[k].dot(s.B[k] * dx[k + 1]);
  }
  if (s.num_globals() == 0) return out;
  for (std::size_t k = 0; k < dx.size(); ++k) out += 2.0 * dx[k].dot(s.C[k] * dx_global);
  return out + dx_global.dot(s.E * dx_global);
}

BorderedChainMarginals MarginalsOfBorderedChain(const ChainSystem& system) {
  const int num_globals = system.num_globals();
  Mat15 S = system.D.front();
  BorderBlock C = num_globals > 0 ? system.C.front() : BorderBlock(15, 0);
  Eigen::MatrixXd E = system.E;
  for (std::size_t k = 0; k + 1 < system.D.size(); ++k) {
    BorderBlock rhs(15, 15 + num_globals);
    rhs << system.B[k], C;
    const BorderBlock X = EliminateChainBlock(S, rhs);
    const BorderBlock X_C = X.rightCols(num_globals);
    E.noalias() -= C.transpose() * X_C;
    E = (0.5 * (E + E.transpose())).eval();
    C = system.C[k + 1] - system.B[k].transpose() * X_C;
    S = system.D[k + 1] - system.B[k].transpose().lazyProduct(X.leftCols<15>());
    S = 0.5 * (S + S.transpose());
  }
  BorderedChainMarginals out;
  out.newest_information = S;
  if (num_globals == 0) return out;
  out.newest_information -= C * SymmetricPseudoInverse(E) * C.transpose();
  out.newest_information = (0.5 * (out.newest_information + out.newest_information.transpose()));
  const Eigen::MatrixXd global_information = E - C.transpose() * EliminateChainBlock(S, C);
  out.global_covariance = SymmetricPseudoInverse(global_information);
  return out;
}

std::vector<Mat15> BorderedChainMarginalCovariances(const ChainSystem& system) {
  std::vector<Mat15> P = ChainMarginalCovariances(system);
  const Eigen::Index G = system.num_globals();
  if (G == 0 || P.empty()) return P;
  ChainFactorization factored;
  if (!FactorChain(system, std::vector<Vec15>(P.size(), Vec15::Zero()), &factored)) return P;
  std::vector<Eigen::Matrix<double, 15, Eigen::Dynamic>> X(P.size(), Eigen::MatrixXd::Zero(15, G));
  std::vector<Vec15> rhs(P.size());
  std::vector<Vec15> x;
  for (Eigen::Index j = 0; j < G; ++j) {
    for (std::size_t k = 0; k < P.size(); ++k) rhs[k] = system.C[k].col(j);
    SolveFactoredChain(factored, rhs, &x);
    for (std::size_t k = 0; k < P.size(); ++k) X[k].col(j) = x[k];
  }
  const Eigen::MatrixXd sigma_g = MarginalsOfBorderedChain(system).global_covariance;
  for (std::size_t k = 0; k < P.size(); ++k) {
    const Mat15 share = X[k] * sigma_g * X[k].transpose();
    P[k] += 0.5 * (share + share.transpose());
  }
  return P;
}

}  // namespace statebench::est
