#include "estimator/chain_system.hpp"

#include "estimator/bordered_chain.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>

namespace statebench::est {
namespace {

using Mat30 = Eigen::Matrix<double, 30, 30>;
using Vec30 = Eigen::Matrix<double, 30, 1>;
using ChainAmbient = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

constexpr std::array<int, 4> kChainTangentOffset{0, 3, 6, 9};
constexpr std::array<int, 4> kChainTangentSize{3, 3, 3, 6};

// Where a factor's block sits in the 30-dim tangent of (anchor, next); -1 if in neither.
int ChainSlot(const ChainState& anchor, const ChainState* next, const double* block) {
  for (int i = 0; i < 4; ++i) {
    if (anchor.blocks[i] == block) return i;
    if (next != nullptr && next->blocks[i] == block) return 4 + i;
  }
  return -1;
}

// Ceres' robust-loss correction (ceres/internal/corrector.cc): r and J rescaled so that
// J^T J and J^T r are the loss' first-order (and, for rho'' > 0, second-order) model.
struct ChainCorrector {
  double sqrt_rho1 = 1.0;
  double residual_scaling = 1.0;
  double alpha_sq_norm = 0.0;

  ChainCorrector(double sq_norm, const double rho[3]) {
    sqrt_rho1 = std::sqrt(rho[1]);
    if (sq_norm == 0.0 || rho[2] <= 0.0) {
      residual_scaling = sqrt_rho1;
      return;
    }
    const double alpha = 1.0 - std::sqrt(1.0 + 2.0 * sq_norm * rho[2] / rho[1]);
    residual_scaling = sqrt_rho1 / (1.0 - alpha);
    alpha_sq_norm = alpha / sq_norm;
  }
};

// One parameter block of a factor in the pair's 30-dim tangent: where its columns start, how
// many, and its tangent Jacobian (m x size, column-major, in the scratch).
struct ChainTangentBlock {
  int offset = 0;
  int size = 0;
  double* J = nullptr;
};

// Scratch reused from factor to factor: buffers grow to the largest factor and stay, so a
// linearisation allocates a few times, not per factor.
struct ChainScratch {
  std::vector<double> r_buffer, ambient_buffer, J_buffer;
  std::vector<double*> ambient_ptrs;
  std::vector<ChainTangentBlock> blocks;
  Eigen::MatrixXd J_global;  // m x G, the factor's columns of the globals
};

// The border of one pair system (anchor, next): what the factors add to C (30 x G), E, g_global.
struct ChainBorderSums {
  Eigen::Matrix<double, 30, Eigen::Dynamic> C;
  Eigen::MatrixXd E;
  Eigen::VectorXd g;
};

int ChainGlobalSlot(std::span<double* const> globals, const double* block) {
  for (std::size_t i = 0; i < globals.size(); ++i) {
    if (globals[i] == block) return static_cast<int>(i);
  }
  return -1;
}

using ChainAmbientMap = Eigen::Map<const ChainAmbient>;
using ChainTangentMap = Eigen::Map<Eigen::MatrixXd>;

// f(std::integral_constant<int, size>) for a tangent block's size (3, or 6 for the biases).
template <typename F>
void WithTangentSize(int size, F&& f) {
  if (size == 3) {
    f(std::integral_constant<int, 3>{});
  } else {
    f(std::integral_constant<int, 6>{});
  }
}

// The factor's J^T J (blocks on and below the diagonal) and J^T r into the pair system, block
// pair by block pair: fixed-size products over the factor's M residuals (Eigen::Dynamic for the
// sizes not listed in AccumulateChainFactor).
template <int M>
void AccumulateChainBlocks(const std::vector<ChainTangentBlock>& blocks, const double* r_data,
                           int m, Mat30& H, Vec30& g) {
  const Eigen::Map<const Eigen::Matrix<double, M, 1>> r(r_data, m);
  for (const ChainTangentBlock& a : blocks) {
    WithTangentSize(a.size, [&](auto ta) {
      constexpr int Ta = decltype(ta)::value;
      const Eigen::Map<const Eigen::Matrix<double, M, Ta>> Ja(a.J, m, Ta);
      g.segment<Ta>(a.offset).noalias() += Ja.transpose().lazyProduct(r);
      for (const ChainTangentBlock& b : blocks) {
        if (b.offset > a.offset) continue;  // the block above the diagonal: its transpose
        WithTangentSize(b.size, [&](auto tb) {
          constexpr int Tb = decltype(tb)::value;
          const Eigen::Map<const Eigen::Matrix<double, M, Tb>> Jb(b.J, m, Tb);
          H.block<Ta, Tb>(a.offset, b.offset).noalias() += Ja.transpose().lazyProduct(Jb);
        });
      }
    });
  }
}

void AccumulateChainFactor(const std::vector<ChainTangentBlock>& blocks, const double* r, int m,
                           Mat30& H, Vec30& g) {
  switch (m) {  // the factors' residual sizes
    case 1: return AccumulateChainBlocks<1>(blocks, r, m, H, g);
    case 2: return AccumulateChainBlocks<2>(blocks, r, m, H, g);
    case 3: return AccumulateChainBlocks<3>(blocks, r, m, H, g);
    case 6: return AccumulateChainBlocks<6>(blocks, r, m, H, g);
    case 9: return AccumulateChainBlocks<9>(blocks, r, m, H, g);
    case 15: return AccumulateChainBlocks<15>(blocks, r, m, H, g);
    default: return AccumulateChainBlocks<Eigen::Dynamic>(blocks, r, m, H, g);
  }
}

// Adds one factor's J^T J (lower triangle) and J^T r to the pair system (anchor, next); its cost
// to *cost.
// Its columns of the globals, if it has any, go to border.
bool AddChainFactor(const FactorRecord& f, const ChainState& anchor, const ChainState* next,
                    const ceres::Manifold& rotation, std::span<double* const> globals,
                    ChainScratch& s, Mat30& H, Vec30& g, ChainBorderSums& border, double* cost) {
  const int m = f.cost->num_residuals();
  const auto& sizes = f.cost->parameter_block_sizes();
  int ambient_total = 0;
  for (int32_t size : sizes) ambient_total += size;
  if (s.r_buffer.size() < static_cast<std::size_t>(m)) s.r_buffer.resize(m);
  if (s.ambient_buffer.size() < static_cast<std::size_t>(m * ambient_total)) {
    s.ambient_buffer.resize(m * ambient_total);
  }
  if (s.J_buffer.size() < static_cast<std::size_t>(m * 30)) s.J_buffer.resize(m * 30);
  s.ambient_ptrs.resize(sizes.size());
  for (std::size_t b = 0, at = 0; b < sizes.size(); at += m * sizes[b], ++b) {
    s.ambient_ptrs[b] = s.ambient_buffer.data() + at;
  }
  Eigen::Map<Eigen::VectorXd> r(s.r_buffer.data(), m);
  if (!f.cost->Evaluate(f.blocks.data(), r.data(), s.ambient_ptrs.data())) return false;

  // Each block's tangent Jacobian (the rotation's through the manifold's PlusJacobian).
  s.blocks.clear();
  bool touches_global = false;
  int tangent_used = 0;
  for (std::size_t b = 0; b < sizes.size(); ++b) {
    const int slot = ChainSlot(anchor, next, f.blocks[b]);
    if (slot < 0) {
      const int column = ChainGlobalSlot(globals, f.blocks[b]);
      if (column < 0 || sizes[b] != 1) return false;
      if (!touches_global) s.J_global.setZero(m, static_cast<Eigen::Index>(globals.size()));
      touches_global = true;
      s.J_global.col(column) += ChainAmbientMap(s.ambient_ptrs[b], m, 1);
      continue;
    }
    const int size = kChainTangentSize[slot % 4];
    const ChainTangentBlock block{kChainTangentOffset[slot % 4] + 15 * (slot / 4), size,
                                  s.J_buffer.data() + m * tangent_used};
    tangent_used += size;
    ChainTangentMap T(block.J, m, size);
    const ChainAmbientMap ambient(s.ambient_ptrs[b], m, sizes[b]);
    if (slot % 4 == 0) {
      Eigen::Matrix<double, 4, 3, Eigen::RowMajor> plus;
      rotation.PlusJacobian(f.blocks[b], plus.data());
      T.noalias() = ambient.lazyProduct(plus);
    } else {
      T = ambient;
    }
    s.blocks.push_back(block);
  }
  const double sq_norm = r.squaredNorm();
  if (f.loss == nullptr) {
    *cost += 0.5 * sq_norm;
  } else {
    double rho[3];
    f.loss->Evaluate(sq_norm, rho);
    *cost += 0.5 * rho[0];
    const ChainCorrector c(sq_norm, rho);
    for (const ChainTangentBlock& block : s.blocks) {
      ChainTangentMap T(block.J, m, block.size);
      if (c.alpha_sq_norm != 0.0) {
        const Eigen::RowVectorXd rtT = r.transpose() * T;
        T -= c.alpha_sq_norm * r * rtT;
      }
      T *= c.sqrt_rho1;
    }
    if (touches_global) {
      if (c.alpha_sq_norm != 0.0) {
        const Eigen::RowVectorXd rtJg = r.transpose() * s.J_global;
        s.J_global -= c.alpha_sq_norm * r * rtJg;
      }
      s.J_global *= c.sqrt_rho1;
    }
    r *= c.residual_scaling;
  }
  AccumulateChainFactor(s.blocks, r.data(), m, H, g);
  if (touches_global) {
    for (const ChainTangentBlock& block : s.blocks) {
      border.C.middleRows(block.offset, block.size) +=
          ChainTangentMap(block.J, m, block.size).transpose() * s.J_global;
    }
    border.E.noalias() += s.J_global.transpose() * s.J_global;
    border.g.noalias() += s.J_global.transpose() * r;
  }
  return true;
}

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

bool ChainCost(const std::vector<ChainState>& chain, double* cost) {
  double total = 0.0;
  std::vector<double> buffer;
  for (const ChainState& state : chain) {
    for (const FactorRecord* f : state.factors) {
      const int m = f->cost->num_residuals();
      if (buffer.size() < static_cast<std::size_t>(m)) buffer.resize(m);
      if (!f->cost->Evaluate(f->blocks.data(), buffer.data(), nullptr)) return false;
      const double sq_norm = Eigen::Map<const Eigen::VectorXd>(buffer.data(), m).squaredNorm();
      if (f->loss == nullptr) {
        total += 0.5 * sq_norm;
      } else {
        double rho[3];
        f->loss->Evaluate(sq_norm, rho);
        total += 0.5 * rho[0];
      }
    }
  }
  *cost = total;
  return true;
}

bool LinearizeChain(const std::vector<ChainState>& chain, const ceres::Manifold& rotation,
                    ChainSystem* system, std::span<double* const> globals) {
  const std::size_t n = chain.size();
  const auto num_globals = static_cast<Eigen::Index>(globals.size());
  system->D.assign(n, Mat15::Zero());
  system->B.assign(n > 0 ? n - 1 : 0, Mat15::Zero());
  system->g.assign(n, Vec15::Zero());
  system->C.assign(num_globals > 0 ? n : 0, Eigen::MatrixXd::Zero(15, num_globals));
  system->E = Eigen::MatrixXd::Zero(num_globals, num_globals);
  system->g_global = Eigen::VectorXd::Zero(num_globals);
  system->cost = 0.0;
  ChainScratch scratch;
  ChainBorderSums border{Eigen::MatrixXd::Zero(30, num_globals), system->E, system->g_global};
  for (std::size_t k = 0; k < n; ++k) {
    const ChainState* next = k + 1 < n ? &chain[k + 1] : nullptr;
    Mat30 H = Mat30::Zero();
    Vec30 g = Vec30::Zero();
    for (const FactorRecord* f : chain[k].factors) {
      if (!AddChainFactor(*f, chain[k], next, rotation, globals, scratch, H, g, border,
                          &system->cost)) {
        return false;
      }
    }
    if (num_globals > 0) {
      system->C[k] += border.C.topRows<15>();
      if (next != nullptr) system->C[k + 1] += border.C.bottomRows<15>();
      border.C.setZero();
    }
    H.triangularView<Eigen::StrictlyUpper>() = H.transpose();
    if (k == 0 && next != nullptr) {
      system->first_pair_H = H;
      system->first_pair_g = g;
    }
    system->D[k] += H.topLeftCorner<15, 15>();
    system->g[k] += g.head<15>();
    if (next != nullptr) {
      system->B[k] += H.topRightCorner<15, 15>();
      system->D[k + 1] += H.bottomRightCorner<15, 15>();
      system->g[k + 1] += g.tail<15>();
    }
  }
  system->E = border.E;
  system->g_global = border.g;
  return true;
}

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
