// The window's chain system solved (chain_system.hpp): block elimination oldest first, its
// factorisation reused across right-hand sides, the newest state's marginal information and every
// state's marginal covariance.
#include "estimator/chain_system.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>

#include "estimator/bordered_chain.hpp"

namespace statebench::est {
namespace {

// S - V^T V, the product's lower triangle from column dot products and its upper one mirrored
// (V^T V is symmetric; about half the products of the dense one).
Mat15 MinusGram(const Mat15& S, const Mat15& V) {
  Mat15 out = S;
  for (int j = 0; j < 15; ++j) {
    for (int i = j; i < 15; ++i) {
      const double d = V.col(i).dot(V.col(j));
      out(i, j) -= d;
      if (i != j) out(j, i) -= d;
    }
  }
  return out;
}

// Whether the Cholesky factor of S is usable for eliminating S: factored, and no pivot below
// 1e-10 of S's largest diagonal entry (SchurComplement's test).
bool ChainFactorUsable(const SmallCholesky<15>& llt, const Mat15& S) {
  return llt.ok() &&
         llt.L().diagonal().array().square().minCoeff() > 1e-10 * S.diagonal().maxCoeff();
}

// The eigen pseudo-inverse of a nearly singular S (SchurComplement's fallback).
Mat15 ChainPseudoInverse(const Mat15& S) {
  const Eigen::SelfAdjointEigenSolver<Mat15> eig(S);
  const double threshold = 1e-12 * std::max(eig.eigenvalues().maxCoeff(), 0.0);
  const Vec15 inv_values =
      eig.eigenvalues().unaryExpr([&](double l) { return l > threshold ? 1.0 / l : 0.0; });
  return eig.eigenvectors() * inv_values.asDiagonal() * eig.eigenvectors().transpose();
}

// S^-1 * rhs for a block being eliminated, as SchurComplement inverts H_mm.
template <int Cols>
Eigen::Matrix<double, 15, Cols> ChainEliminate(const Mat15& S_in,
                                               const Eigen::Matrix<double, 15, Cols>& rhs) {
  const Mat15 S = 0.5 * (S_in + S_in.transpose());
  const SmallCholesky<15> llt(S);
  if (ChainFactorUsable(llt, S)) return llt.Solve(rhs);
  return ChainPseudoInverse(S) * rhs;
}

// S_next - B^T S^-1 B, symmetrised: the Schur complement that eliminating S leaves on the next
// block (with the Cholesky factor, (L^-1 B)^T (L^-1 B)).
Mat15 ChainSchurStep(const Mat15& S_in, const Mat15& B, const Mat15& D_next) {
  const Mat15 S = 0.5 * (S_in + S_in.transpose());
  const SmallCholesky<15> llt(S);
  if (ChainFactorUsable(llt, S)) return MinusGram(D_next, llt.SolveLower(B));
  Mat15 out = D_next;
  out.noalias() -= B.transpose().lazyProduct(ChainPseudoInverse(S) * B);
  return 0.5 * (out + out.transpose());
}

}  // namespace

bool FactorChain(const ChainSystem& system, const std::vector<Vec15>& damping,
                 ChainFactorization* f) {
  // S_k = L_k L_k^T = D_k + diag(damping_k) - V_{k-1}^T V_{k-1},  V_k = L_k^-1 B_k.
  const std::size_t n = system.D.size();
  f->L.resize(n);
  f->V.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    Mat15 S = k > 0 ? MinusGram(system.D[k], f->V[k - 1]) : system.D[k];
    S.diagonal() += damping[k];
    if (!f->L[k].Compute(S)) return false;
    if (k + 1 < n) f->V[k] = f->L[k].SolveLower(system.B[k]);
  }
  return true;
}

void SolveFactoredChain(const ChainFactorization& f, const std::vector<Vec15>& rhs,
                        std::vector<Vec15>* x) {
  // Forward u_k = L_k^-1 (rhs_k - V_{k-1}^T u_{k-1}); backward x_k = L_k^-T (u_k - V_k x_{k+1}).
  const std::size_t n = f.L.size();
  std::vector<Vec15> u(n);
  for (std::size_t k = 0; k < n; ++k) {
    Vec15 y = rhs[k];
    if (k > 0) y.noalias() -= f.V[k - 1].transpose() * u[k - 1];
    u[k] = f.L[k].SolveLower(y);
  }
  x->resize(n);
  for (std::size_t k = n; k-- > 0;) {
    Vec15 w = u[k];
    if (k + 1 < n) w.noalias() -= f.V[k] * (*x)[k + 1];
    (*x)[k] = f.L[k].SolveUpper(w);
  }
}

bool SolveChain(const ChainSystem& system, const std::vector<Vec15>& damping,
                std::vector<Vec15>* dx) {
  ChainFactorization f;
  if (!FactorChain(system, damping, &f)) return false;
  std::vector<Vec15> rhs(system.g.size());
  for (std::size_t k = 0; k < rhs.size(); ++k) rhs[k] = -system.g[k];
  SolveFactoredChain(f, rhs, dx);
  return true;
}

Eigen::Matrix<double, 15, Eigen::Dynamic> EliminateChainBlock(
    const Mat15& S, const Eigen::Matrix<double, 15, Eigen::Dynamic>& rhs) {
  return ChainEliminate<Eigen::Dynamic>(S, rhs);
}

Mat15 NewestMarginalInformation(const ChainSystem& system) {
  if (system.num_globals() > 0) return MarginalsOfBorderedChain(system).newest_information;
  Mat15 S = system.D.front();
  for (std::size_t k = 0; k + 1 < system.D.size(); ++k) {
    S = ChainSchurStep(S, system.B[k], system.D[k + 1]);
  }
  return S;
}

std::vector<Mat15> ChainMarginalCovariances(const ChainSystem& system) {
  const std::size_t n = system.D.size();
  std::vector<Mat15> S_inv(n);
  std::vector<Mat15> G(n > 0 ? n - 1 : 0);
  Mat15 S = n > 0 ? system.D.front() : Mat15::Zero();
  for (std::size_t k = 0; k < n; ++k) {
    S_inv[k] = ChainEliminate<15>(S, Mat15::Identity());
    S_inv[k] = (0.5 * (S_inv[k] + S_inv[k].transpose())).eval();
    if (k + 1 == n) break;
    G[k] = S_inv[k] * system.B[k];
    S = system.D[k + 1] - system.B[k].transpose().lazyProduct(G[k]);
    S = (0.5 * (S + S.transpose())).eval();
  }
  std::vector<Mat15> P(n);
  for (std::size_t k = n; k-- > 0;) {
    P[k] = S_inv[k];
    if (k + 1 < n) P[k].noalias() += G[k] * P[k + 1] * G[k].transpose();
    P[k] = (0.5 * (P[k] + P[k].transpose())).eval();
  }
  return P;
}

}  // namespace statebench::est
