#include "core/truth.hpp"

#include "core/state.hpp"

namespace statebench {

Vec3 FrameKinematics::SpecificForce() const {
  return T_world_frame.rotation().conjugate() * (a_world - kGravityWorld);
}

FrameKinematics FrameKinematics::AtMount(const SE3& T_frame_mount) const {
  const Vec3& r = T_frame_mount.translation();
  const Quat& q_wf = T_frame_mount.rotation();
  const Quat& q_world_frame = T_world_frame.rotation();
  const Quat q_mount_frame = q_wf.conjugate();
  FrameKinematics out;
  out.T_world_frame = T_world_frame * T_frame_mount;
  out.v_world = v_world + q_world_frame * omega_frame.cross(r);
  out.a_world =
      a_world + q_world_frame * (alpha_frame.cross(r) + omega_frame.cross(omega_frame.cross(r)));
  out.omega_frame = q_mount_frame * omega_frame;
  out.alpha_frame = q_mount_frame * alpha_frame;
  return out;
}

}  // namespace statebench
