// The window's Gauss-Newton system as a chain (chain_system.hpp): its cost, and each factor's
// residual and Jacobians at the current values accumulated into the chain's blocks (with a
// robust loss as Ceres applies it), the globals' border beside them.
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <type_traits>

#include "estimator/chain_system.hpp"

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
    case 1:
      return AccumulateChainBlocks<1>(blocks, r, m, H, g);
    case 2:
      return AccumulateChainBlocks<2>(blocks, r, m, H, g);
    case 3:
      return AccumulateChainBlocks<3>(blocks, r, m, H, g);
    case 6:
      return AccumulateChainBlocks<6>(blocks, r, m, H, g);
    case 9:
      return AccumulateChainBlocks<9>(blocks, r, m, H, g);
    case 15:
      return AccumulateChainBlocks<15>(blocks, r, m, H, g);
    default:
      return AccumulateChainBlocks<Eigen::Dynamic>(blocks, r, m, H, g);
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

}  // namespace statebench::est
