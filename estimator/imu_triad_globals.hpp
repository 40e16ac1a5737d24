// The IMU's triad errors as globals of a new window (ImuTriadOptions, imu_triad_factor.hpp):
// created under the IMU's id right after the smoother is initialised, so that every IMU factor
// carries them. Named gyro_scale_x .. gyro_scale_z and gyro_xy .. gyro_zy (row, column of K),
// accel_* likewise; diagnostics.json reports them under the IMU (sensors.<imu>.globals).
#pragma once

#include <string>

#include "estimator/estimator_config.hpp"
#include "estimator/front_end.hpp"

namespace statebench::est {

// Nothing without options.any(); else the globals, and the smoother's IMU factors on them.
void AddImuTriadGlobals(const ImuTriadOptions& options, const std::string& imu_id,
                        FrontEndContext* ctx);

}  // namespace statebench::est
