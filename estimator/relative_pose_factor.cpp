#include "estimator/relative_pose_factor.hpp"

#include <ceres/autodiff_cost_function.h>

#include <Eigen/Eigenvalues>

#include "core/error.hpp"
#include "estimator/propagated_pose.hpp"
#include "estimator/sqrt_information.hpp"

namespace statebench::est {
namespace {

// Residual of the measured sensor motion given the two IMU poses and the rotation of X (any
// scalar type).
template <typename T>
void Residual(const RelativePoseMeasurement& m, const Eigen::Quaternion<T>& q_x,
              const PropagatedPose<T>& a, const PropagatedPose<T>& b, T* out) {
  using V3 = Eigen::Matrix<T, 3, 1>;
  using Q = Eigen::Quaternion<T>;
  const V3 t_x = m.T_imu_sensor.translation().cast<T>();
  // T_imu1_imu2 = T_w_imu1^-1 T_w_imu2.
  const Q q_12 = a.q_world_imu.conjugate() * b.q_world_imu;
  const V3 t_12 = a.q_world_imu.conjugate() * (b.p_world - a.p_world);
  // T_s1_s2 = X^-1 T_12 X: rotation q_x^-1 q_12 q_x, translation q_x^-1 (q_12 t_x + t_12 - t_x).
  const Q q_pred = q_x.conjugate() * q_12 * q_x;
  const V3 t_pred = q_x.conjugate() * (q_12 * t_x + t_12 - t_x);
  const Q q_m = m.T_s1_s2.rotation().cast<T>();
  const V3 t_m = m.T_s1_s2.translation().cast<T>();
  Eigen::Matrix<T, 6, 1> r;
  r.template head<3>() = q_m.conjugate() * (t_pred - t_m);
  r.template tail<3>() = so3::Log<T>(q_m.conjugate() * q_pred);
  Eigen::Map<Eigen::Matrix<T, 6, 1>> whitened(out);
  whitened = m.sqrt_information.cast<T>() * r;
}

// The rotation of X as the setup gives it, or turned by the mount correction c.
template <typename T>
Eigen::Quaternion<T> SetupRotation(const RelativePoseMeasurement& m) {
  return m.T_imu_sensor.rotation().cast<T>();
}
template <typename T>
Eigen::Quaternion<T> CorrectedRotation(const RelativePoseMeasurement& m, const T& roll,
                                       const T& pitch, const T& yaw) {
  return SetupRotation<T>(m) * so3::Exp<T>(Eigen::Matrix<T, 3, 1>(roll, pitch, yaw));
}

// The states' blocks, then none, (pitch, yaw) or (roll, pitch, yaw) of the mount correction:
// Ceres calls the operator with as many blocks as the cost function was given.
struct TwoAnchors {
  RelativePoseMeasurement m;
  PropagationDeltas d1, d2;

  template <typename T>
  bool At(const Eigen::Quaternion<T>& q_x, const T* q1, const T* p1, const T* v1, const T* b1,
          const T* q2, const T* p2, const T* v2, const T* b2, T* residual) const {
    Residual(m, q_x, Propagate(d1, q1, p1, v1, b1), Propagate(d2, q2, p2, v2, b2), residual);
    return true;
  }
  template <typename T>
  bool operator()(const T* q1, const T* p1, const T* v1, const T* b1, const T* q2, const T* p2,
                  const T* v2, const T* b2, T* residual) const {
    return At(SetupRotation<T>(m), q1, p1, v1, b1, q2, p2, v2, b2, residual);
  }
  template <typename T>
  bool operator()(const T* q1, const T* p1, const T* v1, const T* b1, const T* q2, const T* p2,
                  const T* v2, const T* b2, const T* pitch, const T* yaw, T* residual) const {
    return At(CorrectedRotation(m, T(0.0), pitch[0], yaw[0]), q1, p1, v1, b1, q2, p2, v2, b2,
              residual);
  }
  template <typename T>
  bool operator()(const T* q1, const T* p1, const T* v1, const T* b1, const T* q2, const T* p2,
                  const T* v2, const T* b2, const T* roll, const T* pitch, const T* yaw,
                  T* residual) const {
    return At(CorrectedRotation(m, roll[0], pitch[0], yaw[0]), q1, p1, v1, b1, q2, p2, v2, b2,
              residual);
  }
};

struct OneAnchor {
  RelativePoseMeasurement m;
  PropagationDeltas d1, d2;

  template <typename T>
  bool At(const Eigen::Quaternion<T>& q_x, const T* q, const T* p, const T* v, const T* b,
          T* residual) const {
    Residual(m, q_x, Propagate(d1, q, p, v, b), Propagate(d2, q, p, v, b), residual);
    return true;
  }
  template <typename T>
  bool operator()(const T* q, const T* p, const T* v, const T* b, T* residual) const {
    return At(SetupRotation<T>(m), q, p, v, b, residual);
  }
  template <typename T>
  bool operator()(const T* q, const T* p, const T* v, const T* b, const T* pitch, const T* yaw,
                  T* residual) const {
    return At(CorrectedRotation(m, T(0.0), pitch[0], yaw[0]), q, p, v, b, residual);
  }
  template <typename T>
  bool operator()(const T* q, const T* p, const T* v, const T* b, const T* roll, const T* pitch,
                  const T* yaw, T* residual) const {
    return At(CorrectedRotation(m, roll[0], pitch[0], yaw[0]), q, p, v, b, residual);
  }
};

// The number of correction blocks; InputError for a combination nothing uses.
int MountBlocks(const MountAxes& axes) {
  if (axes.count() == 0) return 0;
  if (axes.pitch && axes.yaw) return axes.count();
  throw InputError("relative pose: a mount correction estimates pitch and yaw (and roll)");
}

PropagatedPose<double> PoseOf(const SE3& T) {
  return {T.rotation(), T.translation(), Vec3::Zero()};
}

}  // namespace

Mat6 SqrtOfInformation(const Mat6& information) {
  const Eigen::SelfAdjointEigenSolver<Mat6> eig(0.5 * (information + information.transpose()));
  const Vec6 sqrt_values = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  return sqrt_values.asDiagonal() * eig.eigenvectors().transpose();
}

Mat6 SqrtInformationOfCovariance(const Mat6& covariance, const char* what) {
  return SqrtInformation<6>(covariance, what);
}

SE3 PredictedSensorMotion(const SE3& T_w_imu1, const SE3& T_w_imu2, const SE3& T_imu_sensor) {
  return T_imu_sensor.Inverse() * T_w_imu1.Inverse() * T_w_imu2 * T_imu_sensor;
}

Vec6 RelativePoseResidual(const RelativePoseMeasurement& m, const SE3& T_w_imu1,
                          const SE3& T_w_imu2) {
  Vec6 r;
  Residual(m, SetupRotation<double>(m), PoseOf(T_w_imu1), PoseOf(T_w_imu2), r.data());
  return r;
}

ceres::CostFunction* CreateRelativePoseFactor(const RelativePoseMeasurement& m,
                                              const ImuPreintegration& to_t1,
                                              const ImuPreintegration& to_t2,
                                              const MountAxes& mount) {
  const int corrections = MountBlocks(mount);
  auto* f = new TwoAnchors{m, PropagationDeltas::From(to_t1), PropagationDeltas::From(to_t2)};
  if (corrections == 2) {
    return new ceres::AutoDiffCostFunction<TwoAnchors, 6, 4, 3, 3, 6, 4, 3, 3, 6, 1, 1>(f);
  }
  if (corrections == 3) {
    return new ceres::AutoDiffCostFunction<TwoAnchors, 6, 4, 3, 3, 6, 4, 3, 3, 6, 1, 1, 1>(f);
  }
  return new ceres::AutoDiffCostFunction<TwoAnchors, 6, 4, 3, 3, 6, 4, 3, 3, 6>(f);
}

ceres::CostFunction* CreateRelativePoseFactorOneAnchor(const RelativePoseMeasurement& m,
                                                       const ImuPreintegration& to_t1,
                                                       const ImuPreintegration& to_t2,
                                                       const MountAxes& mount) {
  const int corrections = MountBlocks(mount);
  auto* f = new OneAnchor{m, PropagationDeltas::From(to_t1), PropagationDeltas::From(to_t2)};
  if (corrections == 2) return new ceres::AutoDiffCostFunction<OneAnchor, 6, 4, 3, 3, 6, 1, 1>(f);
  if (corrections == 3) {
    return new ceres::AutoDiffCostFunction<OneAnchor, 6, 4, 3, 3, 6, 1, 1, 1>(f);
  }
  return new ceres::AutoDiffCostFunction<OneAnchor, 6, 4, 3, 3, 6>(f);
}

}  // namespace statebench::est
