// How the sliding window is optimised: ceres::Solve (sparse normal Cholesky with Eigen's
// simplicial LDLT), or the same Levenberg-Marquardt on the window's block-tridiagonal structure
// (chain_levenberg_marquardt.hpp), which agrees with Ceres to the solver's tolerances.
#pragma once

namespace statebench::est {

enum class WindowSolver { kCeres, kChain };

}  // namespace statebench::est
