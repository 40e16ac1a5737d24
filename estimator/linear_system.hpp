// Dense Gauss-Newton linearisation of a set of factors in the tangent space, and the Schur
// complement that marginalises part of it.
//
// For factors with whitened residuals r_f(x) and tangent Jacobians J_f (ambient Jacobian times
// the block manifold's PlusJacobian), the cost 1/2 sum |r_f|^2 is approximated around the
// current estimate by 1/2 dx^T H dx + g^T dx with H = sum J_f^T J_f and g = sum J_f^T r_f.
// A robust loss rho enters with the first-order weight sqrt(rho'(|r|^2)) on r and J (the
// curvature term of Triggs et al. is dropped, so H stays positive semi-definite).
//
// Marginalising the first m tangent dimensions (Schur complement):
//   H* = H_kk - H_km H_mm^-1 H_mk,   g* = g_k - H_km H_mm^-1 g_m
// leaves the information the eliminated variables carried about the kept ones.
#pragma once

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/manifold.h>

#include <Eigen/Core>
#include <unordered_map>
#include <vector>

namespace statebench::est {

// One factor as added to a ceres::Problem: its cost, optional loss and parameter blocks.
struct FactorRecord {
  const ceres::CostFunction* cost = nullptr;
  const ceres::LossFunction* loss = nullptr;  // nullptr: plain least squares
  std::vector<double*> blocks;
};

// Tangent layout of the dense system: where each parameter block's tangent vector starts.
class BlockLayout {
 public:
  // Appends a block; manifold nullptr means Euclidean of size ambient_size.
  void Add(double* block, int ambient_size, const ceres::Manifold* manifold);
  int dimension() const { return dimension_; }
  bool Contains(const double* block) const { return entries_.count(block) > 0; }

  struct Entry {
    int offset = 0;
    int ambient_size = 0;
    int tangent_size = 0;
    const ceres::Manifold* manifold = nullptr;
  };
  const Entry& At(const double* block) const { return entries_.at(block); }

 private:
  std::unordered_map<const double*, Entry> entries_;
  int dimension_ = 0;
};

struct LinearSystem {
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  int num_skipped = 0;  // factors left out by Linearize (see there)
};

// Accumulates every factor at the current block values. Blocks a factor uses must all be in
// the layout. A factor that fails to evaluate, or whose whitened residual (its squared norm) or
// Jacobian is not finite there, carries nothing a Gaussian can hold: it is left out and counted in
// system->num_skipped (a non-finite H or g would poison every later solve through the prior).
// Returns false when a factor was left out.
bool Linearize(const std::vector<const FactorRecord*>& factors, const BlockLayout& layout,
               LinearSystem* system);

// Marginalises the first m dimensions of system. H_mm is inverted by Cholesky; if it is
// (nearly) singular, through its eigendecomposition, dropping directions with eigenvalue below
// 1e-12 of the largest (they carry no information).
LinearSystem SchurComplement(const LinearSystem& system, int m);

}  // namespace statebench::est
