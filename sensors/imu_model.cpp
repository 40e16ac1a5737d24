#include "sensors/imu_model.hpp"

namespace statebench::sensors {

ImuModel::ImuModel(const SensorSpec& spec, const ImuOptions& options, std::uint64_t seed)
    : SensorModel(spec),
      gyro_(options.gyro, ToSeconds(spec.PeriodNs()), seed, spec.id + "/gyro"),
      accel_(options.accel, ToSeconds(spec.PeriodNs()), seed, spec.id + "/accel") {
  if (options.vibration.engine || options.vibration.road) {
    vibration_.emplace(options.vibration, seed, spec.id + "/vibration");
  }
}

void ImuModel::Observe(const TruthSample& truth, std::vector<Measurement>* out) {
  if (vibration_) {  // moves on at every truth step, sampled at the IMU's stamps
    const double dt_s = vibration_t_ns_ ? ToSeconds(truth.t_ns - *vibration_t_ns_) : 0.0;
    vibration_->Advance(dt_s, truth.body.v_world.norm());
    vibration_t_ns_ = truth.t_ns;
  }
  if (spec().IsSampleTime(truth.t_ns)) out->push_back(Sample(truth));
}

ImuSample ImuModel::Sample(const TruthSample& truth) {
  // Exact kinematics of the IMU frame; AtMount includes the lever-arm accelerations
  // alpha x r + w x (w x r).
  const FrameKinematics imu = truth.body.AtMount(spec().T_body_sensor);
  ImuSample s;
  s.header = MakeHeader(truth.t_ns);
  if (vibration_) {
    s.gyro = gyro_.Measure(imu.omega_frame + vibration_->gyro_radps());
    s.accel = accel_.Measure(imu.SpecificForce() + vibration_->accel_mps2());
  } else {  // the same bits as before vibration existed
    s.gyro = gyro_.Measure(imu.omega_frame);
    s.accel = accel_.Measure(imu.SpecificForce());
  }
  return s;
}

}  // namespace statebench::sensors
