#include "estimator/robust_kernel.hpp"

#include <cmath>

#include "core/error.hpp"

namespace statebench::est {

std::unique_ptr<ceres::LossFunction> RobustKernel::MakeLossFunction() const {
  if (type == RobustKernelType::kNone) return nullptr;
  if (!(scale > 0.0) || !std::isfinite(scale)) {
    throw InputError("robust kernel: scale must be positive, got " + std::to_string(scale));
  }
  if (type == RobustKernelType::kHuber) return std::make_unique<ceres::HuberLoss>(scale);
  return std::make_unique<ceres::CauchyLoss>(scale);
}

RobustKernelType ParseRobustKernelType(const std::string& name) {
  if (name == "none") return RobustKernelType::kNone;
  if (name == "huber") return RobustKernelType::kHuber;
  if (name == "cauchy") return RobustKernelType::kCauchy;
  throw InputError("robust kernel: unknown type '" + name + "' (none, huber, cauchy)");
}

const char* RobustKernelTypeName(RobustKernelType type) {
  switch (type) {
    case RobustKernelType::kNone:
      return "none";
    case RobustKernelType::kHuber:
      return "huber";
    case RobustKernelType::kCauchy:
      return "cauchy";
  }
  return "?";
}

}  // namespace statebench::est
