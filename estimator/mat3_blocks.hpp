// A matrix made of 3x3 blocks, each zero, a multiple of the identity or general: the shape of
// the IMU's transition and noise matrices (imu_preintegration.cpp, imu_propagation.cpp), whose
// congruences F P F^T are the IMU's covariance propagation.
//
// Eigen multiplies a 15x15 by a 15x15 through its blocked GEMM (packing, 4x4 kernels) whether
// or not most blocks are zero or the identity; here only the general blocks cost a 3x3 product
// and the identity blocks an addition, and of the symmetric result only the lower blocks are
// computed (the upper ones are their transposes, the diagonal ones symmetrised: exactly
// symmetric). The sums run over the
// block columns in ascending order, so results differ from the dense products in the last bits
// only.
#pragma once

#include <array>
#include <cstdint>

#include "core/eigen_types.hpp"

namespace statebench::est {

template <int Rows, int Cols>
class Mat3Blocks {
 public:
  using Dense = Eigen::Matrix<double, 3 * Rows, 3 * Cols>;
  using RowSquare = Eigen::Matrix<double, 3 * Rows, 3 * Rows>;
  using ColSquare = Eigen::Matrix<double, 3 * Cols, 3 * Cols>;

  // Every block starts zero.
  void SetGeneral(int i, int j, const Mat3& block) {
    kind_[i][j] = Kind::kGeneral;
    block_[i][j] = block;
  }
  void SetScaledIdentity(int i, int j, double scale) {
    kind_[i][j] = Kind::kScaledIdentity;
    scale_[i][j] = scale;
  }
  void SetIdentity(int i, int j) { SetScaledIdentity(i, j, 1.0); }

  Dense ToDense() const {
    Dense out = Dense::Zero();
    for (int i = 0; i < Rows; ++i) {
      for (int j = 0; j < Cols; ++j) {
        if (kind_[i][j] == Kind::kGeneral) out.template block<3, 3>(3 * i, 3 * j) = block_[i][j];
        if (kind_[i][j] == Kind::kScaledIdentity) {
          out.template block<3, 3>(3 * i, 3 * j) = scale_[i][j] * Mat3::Identity();
        }
      }
    }
    return out;
  }

  // F P F^T for a symmetric P: the lower blocks, and the upper ones as their transposes.
  RowSquare Congruence(const ColSquare& P) const {
    // M = F P, block by block.
    std::array<std::array<Mat3, Cols>, Rows> M;
    for (int i = 0; i < Rows; ++i) {
      for (int j = 0; j < Cols; ++j) M[i][j] = RowTimes(i, P, j);
    }
    return TimesTransposed(M, /*skip_zero_left=*/false);
  }

  // Diagonal block (a, a) of Congruence(P) alone, the same bits: block row a of F P, times F's
  // block row a transposed, symmetrised.
  Mat3 CongruenceDiagonalBlock(const ColSquare& P, int a) const {
    std::array<Mat3, Cols> M_a;
    for (int j = 0; j < Cols; ++j) M_a[j] = RowTimes(a, P, j);
    Mat3 C_aa;
    bool any = false;
    for (int j = 0; j < Cols; ++j) {
      if (kind_[a][j] != Kind::kZero) Accumulate(&C_aa, TimesTransposed(M_a[j], a, j), &any);
    }
    return any ? Mat3(0.5 * (C_aa + C_aa.transpose())) : Mat3::Zero();
  }

  // s F F^T (a congruence of s I), exactly symmetric.
  RowSquare ScaledGram(double s) const {
    std::array<std::array<Mat3, Cols>, Rows> M;
    for (int i = 0; i < Rows; ++i) {
      for (int j = 0; j < Cols; ++j) M[i][j] = Block(i, j);
    }
    return s * TimesTransposed(M, /*skip_zero_left=*/true);
  }

 private:
  enum class Kind : std::uint8_t { kZero, kScaledIdentity, kGeneral };

  // C = M F^T for M of F's block shape, lower blocks (the upper ones mirrored). With
  // skip_zero_left, M's blocks where F has a zero block are taken as zero (M = F).
  RowSquare TimesTransposed(const std::array<std::array<Mat3, Cols>, Rows>& M,
                            bool skip_zero_left) const {
    RowSquare C;
    for (int a = 0; a < Rows; ++a) {
      for (int b = 0; b <= a; ++b) {
        Mat3 C_ab;
        bool any = false;
        for (int j = 0; j < Cols; ++j) {
          if (kind_[b][j] == Kind::kZero || (skip_zero_left && kind_[a][j] == Kind::kZero)) {
            continue;
          }
          Accumulate(&C_ab, TimesTransposed(M[a][j], b, j), &any);
        }
        SetSymmetricBlock(&C, a, b, any ? C_ab : Mat3::Zero());
      }
    }
    return C;
  }

  // Block (a, b) of C and, above the diagonal, its transpose; a diagonal block symmetrised.
  static void SetSymmetricBlock(RowSquare* C, int a, int b, const Mat3& block) {
    if (b == a) {
      C->template block<3, 3>(3 * a, 3 * a) = 0.5 * (block + block.transpose());
      return;
    }
    C->template block<3, 3>(3 * a, 3 * b) = block;
    C->template block<3, 3>(3 * b, 3 * a) = block.transpose();
  }

  static void Accumulate(Mat3* sum, const Mat3& term, bool* any) {
    if (*any) {
      *sum += term;
    } else {
      *sum = term;
      *any = true;
    }
  }

  Mat3 Block(int i, int j) const {
    if (kind_[i][j] == Kind::kZero) return Mat3::Zero();
    return kind_[i][j] == Kind::kGeneral ? block_[i][j] : Mat3(scale_[i][j] * Mat3::Identity());
  }

  // Block (i, j) of F P.
  Mat3 RowTimes(int i, const ColSquare& P, int j) const {
    Mat3 M_ij;
    bool any = false;
    for (int k = 0; k < Cols; ++k) {
      if (kind_[i][k] == Kind::kZero) continue;
      Accumulate(&M_ij, Times(i, k, P.template block<3, 3>(3 * k, 3 * j)), &any);
    }
    return any ? M_ij : Mat3::Zero();
  }

  // F_ik X.
  Mat3 Times(int i, int k, const Mat3& X) const {
    if (kind_[i][k] == Kind::kGeneral) return block_[i][k].lazyProduct(X);
    return scale_[i][k] == 1.0 ? X : Mat3(scale_[i][k] * X);
  }

  // X F_bj^T.
  Mat3 TimesTransposed(const Mat3& X, int b, int j) const {
    if (kind_[b][j] == Kind::kGeneral) return X.lazyProduct(block_[b][j].transpose());
    return scale_[b][j] == 1.0 ? X : Mat3(scale_[b][j] * X);
  }

  std::array<std::array<Kind, Cols>, Rows> kind_{};
  std::array<std::array<Mat3, Cols>, Rows> block_;
  std::array<std::array<double, Cols>, Rows> scale_{};
};

}  // namespace statebench::est
