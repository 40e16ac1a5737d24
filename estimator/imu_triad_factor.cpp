#include "estimator/imu_triad_factor.hpp"

#include <array>

#include "core/error.hpp"

namespace statebench::est {
namespace {

constexpr int kImuBlocks = 7;
constexpr int kBiasBlock = 3;

int BiasColumn(const ImuTriadTerm& t) {
  return (t.triad == ImuTriadTerm::Triad::kAccel ? 3 : 0) + t.row;
}

int SignalIndex(const ImuTriadTerm& t) {
  return (t.triad == ImuTriadTerm::Triad::kAccel ? 3 : 0) + t.col;
}

std::vector<ImuTriadTerm> CheckedTerms(std::vector<ImuTriadTerm> terms) {
  for (const ImuTriadTerm& t : terms) {
    if (t.row < 0 || t.row > 2 || t.col < 0 || t.col > 2) {
      throw InputError("imu triad factor: a term's row and column must be 0, 1 or 2");
    }
  }
  return terms;
}

}  // namespace

std::vector<ImuTriadTerm> AllTriadTerms(ImuTriadTerm::Triad triad) {
  std::vector<ImuTriadTerm> terms;
  for (int axis = 0; axis < 3; ++axis) terms.push_back({triad, axis, axis});
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) {
      if (row != col) terms.push_back({triad, row, col});
    }
  }
  return terms;
}

Vec6 MeanRawSignal(const ImuPreintegration& pim) {
  const std::vector<ImuPreintegration::RawSample>& nodes = pim.samples();
  if (nodes.size() < 2 || !(pim.dt() > 0.0)) {
    throw InputError("imu triad factor: empty preintegration");
  }
  Vec6 sum = Vec6::Zero();
  for (std::size_t k = 1; k < nodes.size(); ++k) {
    const double h = ToSeconds(nodes[k].t_ns - nodes[k - 1].t_ns);
    sum.head<3>() += 0.5 * h * (nodes[k].gyro + nodes[k - 1].gyro);
    sum.tail<3>() += 0.5 * h * (nodes[k].accel + nodes[k - 1].accel);
  }
  return sum / pim.dt();
}

ImuTriadFactor::ImuTriadFactor(ImuPreintegration preintegration, std::vector<ImuTriadTerm> terms)
    : imu_(std::move(preintegration)),
      terms_(CheckedTerms(std::move(terms))),
      mean_raw_(MeanRawSignal(imu_.preintegration())) {
  set_num_residuals(9);
  std::vector<int32_t>* sizes = mutable_parameter_block_sizes();
  *sizes = {4, 3, 3, 6, 4, 3, 3};
  sizes->insert(sizes->end(), terms_.size(), 1);
}

bool ImuTriadFactor::Evaluate(double const* const* parameters, double* residuals,
                              double** jacobians) const {
  Vec6 bias_eff = Eigen::Map<const Vec6>(parameters[kBiasBlock]);
  for (std::size_t i = 0; i < terms_.size(); ++i) {
    const ImuTriadTerm& t = terms_[i];
    bias_eff[BiasColumn(t)] += parameters[kImuBlocks + i][0] * mean_raw_[SignalIndex(t)];
  }
  std::array<const double*, kImuBlocks> inner;
  for (int b = 0; b < kImuBlocks; ++b) inner[b] = parameters[b];
  inner[kBiasBlock] = bias_eff.data();
  if (jacobians == nullptr) return imu_.Evaluate(inner.data(), residuals, nullptr);

  bool any_term = false;
  for (std::size_t i = 0; i < terms_.size(); ++i) any_term |= jacobians[kImuBlocks + i] != nullptr;
  Eigen::Matrix<double, 9, 6, Eigen::RowMajor> bias_jacobian;
  std::array<double*, kImuBlocks> inner_jacobians;
  for (int b = 0; b < kImuBlocks; ++b) inner_jacobians[b] = jacobians[b];
  if (any_term && inner_jacobians[kBiasBlock] == nullptr) {
    inner_jacobians[kBiasBlock] = bias_jacobian.data();
  }
  if (!imu_.Evaluate(inner.data(), residuals, inner_jacobians.data())) return false;
  if (!any_term) return true;
  const Eigen::Map<const Eigen::Matrix<double, 9, 6, Eigen::RowMajor>> J_bias(
      inner_jacobians[kBiasBlock]);
  for (std::size_t i = 0; i < terms_.size(); ++i) {
    if (jacobians[kImuBlocks + i] == nullptr) continue;
    const ImuTriadTerm& t = terms_[i];
    Eigen::Map<Vec9>{jacobians[kImuBlocks + i]} =
        J_bias.col(BiasColumn(t)) * mean_raw_[SignalIndex(t)];
  }
  return true;
}

}  // namespace statebench::est
