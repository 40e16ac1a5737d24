// Cholesky factorisation A = L L^T of a small fixed-size symmetric matrix and the triangular
// solves with L, for the chain solver's 15x15 blocks (chain_system.cpp).
//
// Eigen's LLT and TriangularView::solve on a fixed 15x15 go through its blocked, dynamic-size
// kernels (triangular_solve_matrix, gemm packing); here every step is a fixed-size column
// operation (axpy on whole columns of N, which the compiler vectorises), about ten times fewer
// instructions for the chain's blocks. Same algorithm as Eigen's unblocked LLT (the lower
// triangle of A is read; a pivot <= 0 fails), summed in another order: results differ in the
// last bits only.
#pragma once

#include <cmath>

#include <Eigen/Core>

namespace statebench::est {

template <int N>
class SmallCholesky {
 public:
  using Matrix = Eigen::Matrix<double, N, N>;

  SmallCholesky() = default;
  explicit SmallCholesky(const Matrix& A) { Compute(A); }

  // Left-looking, column by column: L_j = (A_j - sum_{k<j} L_jk L_k) / sqrt(pivot), on the rows
  // j..N-1 of column j alone (a fixed-size tail for each j; the rows above stay zero). False
  // (factor unspecified) when a pivot is not positive or not finite.
  bool Compute(const Matrix& A) {
    ok_ = ComputeFrom<0>(A);
    return ok_;
  }

  bool ok() const { return ok_; }
  const Matrix& L() const { return L_; }

  // L^-1 B: row i of X is (row i of B - sum_{k<i} L_ik row k of X) / L_ii, the rows held as the
  // columns of X^T so that each step is a column operation.
  template <int Cols>
  Eigen::Matrix<double, N, Cols> SolveLower(const Eigen::Matrix<double, N, Cols>& B) const {
    Eigen::Matrix<double, Cols, N> Xt = B.transpose();
    for (int i = 0; i < N; ++i) {
      for (int k = 0; k < i; ++k) Xt.col(i) -= L_(i, k) * Xt.col(k);
      Xt.col(i) /= L_(i, i);
    }
    return Xt.transpose();
  }

  // L^-T B, from the last row up.
  template <int Cols>
  Eigen::Matrix<double, N, Cols> SolveUpper(const Eigen::Matrix<double, N, Cols>& B) const {
    Eigen::Matrix<double, Cols, N> Xt = B.transpose();
    for (int i = N - 1; i >= 0; --i) {
      for (int k = i + 1; k < N; ++k) Xt.col(i) -= L_(k, i) * Xt.col(k);
      Xt.col(i) /= L_(i, i);
    }
    return Xt.transpose();
  }

  // A^-1 B.
  template <int Cols>
  Eigen::Matrix<double, N, Cols> Solve(const Eigen::Matrix<double, N, Cols>& B) const {
    return SolveUpper(SolveLower(B));
  }

 private:
  template <int J>
  bool ComputeFrom(const Matrix& A) {
    if constexpr (J == N) {
      return true;
    } else {
      constexpr int M = N - J;  // the rows on and below the diagonal
      Eigen::Matrix<double, M, 1> c = A.col(J).template tail<M>();
      for (int k = 0; k < J; ++k) c -= L_(J, k) * L_.col(k).template tail<M>();
      const double pivot = c(0);
      if (!(pivot > 0.0) || !std::isfinite(pivot)) return false;
      const double d = std::sqrt(pivot);
      c /= d;
      c(0) = d;
      L_.col(J).template tail<M>() = c;
      return ComputeFrom<J + 1>(A);
    }
  }

  Matrix L_ = Matrix::Zero();  // only ever written on and below the diagonal
  bool ok_ = false;
};

}  // namespace statebench::est
