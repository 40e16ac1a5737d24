#include "sensors/imu_model.hpp"

namespace statebench::sensors {

ImuModel::ImuModel(const SensorSpec& spec, const ImuOptions& options, std::uint64_t seed)
    : SensorModel(spec),
      gyro_(options.gyro, ToSeconds(spec.PeriodNs()), seed, spec.id + "/gyro"),
      accel_(options.accel, ToSeconds(spec.PeriodNs()), seed, spec.id + "/accel") {}

void ImuModel::Observe(const TruthSample& truth, std::vector<Measurement>* out) {
  if (spec().IsSampleTime(truth.t_ns)) out->push_back(Sample(truth));
}

ImuSample ImuModel::Sample(const TruthSample& truth) {
  // Exact kinematics of the IMU frame; AtMount includes the lever-arm accelerations
  // alpha x r + w x (w x r).
  const FrameKinematics imu = truth.body.AtMount(spec().T_body_sensor);
  ImuSample s;
  s.header = MakeHeader(truth.t_ns);
  s.gyro = gyro_.Measure(imu.omega_frame);
  s.accel = accel_.Measure(imu.SpecificForce());
  return s;
}

}  // namespace statebench::sensors
