#include "simulator/truth_record.hpp"

#include <limits>

namespace statebench::sim {
namespace {

constexpr TimeNs kTruthEnd = std::numeric_limits<TimeNs>::min();

// The fields of a sample after its stamp, in one place for both directions.
template <typename Doubles>
void TruthFields(TruthSample& s, Doubles&& doubles) {
  FrameKinematics& b = s.body;
  Quat q = b.T_world_frame.rotation();
  Vec3 t = b.T_world_frame.translation();
  doubles(q.coeffs().data(), 4);
  doubles(t.data(), 3);
  b.T_world_frame = SE3(q, t);
  for (Vec3* v : {&b.v_world, &b.a_world, &b.omega_frame, &b.alpha_frame}) doubles(v->data(), 3);
  doubles(&s.steering_front_rad, 1);
  doubles(&s.steering_rear_rad, 1);
  doubles(s.wheel_omega_radps.data(), 4);
  doubles(&s.sideslip_rad, 1);
  doubles(&s.distance_m, 1);
}

}  // namespace

void WriteTrackedTruth(BinaryWriter& out, const TrackedTruth& truth) {
  out.Put(truth.sample.t_ns);
  TruthSample copy = truth.sample;
  TruthFields(copy, [&out](const double* v, std::size_t n) {
    out.PutBytes(v, n * sizeof(double));
  });
  out.Put(truth.lateral_error_m);
  out.Put(truth.longitudinal_error_m);
}

void WriteTruthEnd(BinaryWriter& out) { out.Put(kTruthEnd); }

bool ReadTrackedTruth(BinaryReader& in, TrackedTruth* truth) {
  const auto t_ns = in.Get<TimeNs>();
  if (t_ns == kTruthEnd) return false;
  truth->sample.t_ns = t_ns;
  TruthFields(truth->sample, [&in](double* v, std::size_t n) {
    in.GetBytes(v, n * sizeof(double));
  });
  truth->lateral_error_m = in.Get<double>();
  truth->longitudinal_error_m = in.Get<double>();
  return true;
}

}  // namespace statebench::sim
