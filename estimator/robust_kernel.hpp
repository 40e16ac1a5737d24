// Robust kernels for measurement factors, as Ceres loss functions on the squared norm of the
// whitened residual. The scale is in sigmas of the whitened residual norm: a residual norm
// below it is weighted fully (Huber) or nearly so (Cauchy), beyond it grows linearly (Huber)
// or logarithmically (Cauchy).
#pragma once

#include <ceres/loss_function.h>

#include <memory>
#include <string>

namespace statebench::est {

enum class RobustKernelType { kNone, kHuber, kCauchy };

struct RobustKernel {
  RobustKernelType type = RobustKernelType::kHuber;
  double scale = 3.0;  // sigmas; sqrt of the 97 % quantile of chi-square(3) is 3.0

  // kNone gives nullptr (plain least squares). Throws InputError if scale is not positive.
  // Pass ownership to ceres::Problem with release().
  std::unique_ptr<ceres::LossFunction> MakeLossFunction() const;
};

// "none", "huber" or "cauchy"; InputError naming the value otherwise.
RobustKernelType ParseRobustKernelType(const std::string& name);
const char* RobustKernelTypeName(RobustKernelType type);

}  // namespace statebench::est
