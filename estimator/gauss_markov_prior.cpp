#include "estimator/gauss_markov_prior.hpp"

#include <Eigen/Cholesky>

namespace statebench::est {

void CarryGaussMarkovPrior(const std::vector<GaussMarkovStep>& steps, LinearSystem* prior) {
  if (steps.empty()) return;
  Eigen::MatrixXd& H = prior->H;
  Eigen::VectorXd& g = prior->g;
  const auto m = static_cast<Eigen::Index>(steps.size());
  for (const GaussMarkovStep& s : steps) {
    H.row(s.column) /= s.rho;
    H.col(s.column) /= s.rho;
    g(s.column) /= s.rho;
  }
  Eigen::MatrixXd HB(H.rows(), m);  // H_a B
  Eigen::MatrixXd K_inverse(m, m);  // Q^-1 + B^T H_a B
  Eigen::VectorXd BTg(m);           // B^T g_a
  for (Eigen::Index a = 0; a < m; ++a) HB.col(a) = H.col(steps[a].column);
  for (Eigen::Index a = 0; a < m; ++a) {
    for (Eigen::Index b = 0; b < m; ++b) K_inverse(a, b) = HB(steps[a].column, b);
    K_inverse(a, a) += 1.0 / steps[a].noise_variance;
    BTg(a) = g(steps[a].column);
  }
  const Eigen::LDLT<Eigen::MatrixXd> K(K_inverse);
  g -= HB * K.solve(BTg);
  H -= HB * K.solve(HB.transpose());
  H = (0.5 * (H + H.transpose())).eval();
}

}  // namespace statebench::est
