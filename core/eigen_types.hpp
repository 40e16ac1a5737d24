// Fixed-size Eigen aliases used across StateBench. MatrixXd only where sizes are dynamic.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace statebench {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Vec4 = Eigen::Vector4d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Vec9 = Eigen::Matrix<double, 9, 1>;
using Vec15 = Eigen::Matrix<double, 15, 1>;
using Mat2 = Eigen::Matrix2d;
using Mat3 = Eigen::Matrix3d;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat9 = Eigen::Matrix<double, 9, 9>;
using Mat15 = Eigen::Matrix<double, 15, 15>;
using Quat = Eigen::Quaterniond;

}  // namespace statebench
