#include "estimator/output_blend.hpp"

#include <algorithm>
#include <cmath>

#include "core/so3.hpp"

namespace statebench::est {

void OutputBlend::Rebase(const NavState& shown, const NavState& best) {
  offset_.reset();
  const bool starting =
      start_ns_ != INT64_MIN && best.t_ns - start_ns_ < FromSeconds(options_.after_start_s);
  const double max_s = starting ? std::min(options_.start_max_s, options_.max_s) : options_.max_s;
  if (!(max_s > 0.0)) return;
  Offset o;
  o.t_ns = best.t_ns;
  o.d << so3::Log<double>(best.q_world_imu.conjugate() * shown.q_world_imu),
      shown.p_world - best.p_world, shown.v_world - best.v_world;
  if (!o.d.allFinite()) return;
  const double position_m = o.d.segment<3>(kPositionIndex).norm();
  const double at_rate = std::max(position_m / options_.position_rate_mps,
                                  o.d.segment<3>(kRotationIndex).norm() / options_.rotation_rate_radps);
  const double duration_s = std::min(max_s, at_rate);
  double position_duration_s = duration_s;
  if (!starting && options_.max_position_rate_mps > 0.0) {
    position_duration_s = std::max(duration_s, position_m / options_.max_position_rate_mps);
  }
  o.duration_ns = FromSeconds(duration_s);
  o.position_duration_ns = FromSeconds(position_duration_s);
  if (o.position_duration_ns > 0) offset_ = o;
}

namespace {

// The ramp's weight max(0, 1 - (t - t0) / T) (0 for T = 0).
double RampWeight(TimeNs t_ns, TimeNs t0_ns, TimeNs duration_ns) {
  if (t_ns < t0_ns || t_ns >= t0_ns + duration_ns) return 0.0;
  return 1.0 - static_cast<double>(t_ns - t0_ns) / static_cast<double>(duration_ns);
}

}  // namespace

Vec9 OutputBlend::OffsetAt(TimeNs t_ns) const {
  if (!offset_ || t_ns < offset_->t_ns) return Vec9::Zero();
  const double w = RampWeight(t_ns, offset_->t_ns, offset_->duration_ns);
  const double w_position = RampWeight(t_ns, offset_->t_ns, offset_->position_duration_ns);
  Vec9 b = w * offset_->d;
  b.segment<3>(kPositionIndex) = w_position * offset_->d.segment<3>(kPositionIndex);
  return b;
}

PropagatedState OutputBlend::Apply(const PropagatedState& best) const {
  const Vec9 b = OffsetAt(best.state.t_ns);
  if (b.isZero(0.0)) return best;
  PropagatedState out = best;
  out.state.q_world_imu =
      (best.state.q_world_imu * so3::Exp<double>(Vec3(b.segment<3>(kRotationIndex)))).normalized();
  out.state.p_world += b.segment<3>(kPositionIndex);
  out.state.v_world += b.segment<3>(kVelocityIndex);
  out.covariance.topLeftCorner<9, 9>() += b * b.transpose();
  return out;
}

}  // namespace statebench::est
